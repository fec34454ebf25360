"""Closed-form references for the physics tests, written independently of the engine.

Everything here is plain NumPy: driver profiles, slider-crank kinematics and inverse
dynamics by virtual work (crank angle as the only coordinate), four-bar position analysis
by two-circle intersection, and the damped single-degree-of-freedom oscillator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# --- driver profiles -----------------------------------------------------------------


def linear_ramp(t, speed: float, ramp_time: float, side: str = "right"):
    """Displacement, speed and acceleration of the linear ramp, for t >= 0.

    The speed rises linearly from 0 at t = 0 to `speed` at `ramp_time`, then stays constant:
    displacement = speed t^2 / (2 T) for t < T, speed (t - T/2) after. The acceleration jumps
    from 0 to speed/T at t = 0 and back to 0 at t = T; `side` ("right" or "left") chooses
    which limit is returned exactly at those two corners.
    """
    t = np.asarray(t, dtype=float)
    if side == "right":
        accelerating = (t >= 0.0) & (t < ramp_time)
    else:
        accelerating = (t > 0.0) & (t <= ramp_time)
    during = t < ramp_time
    disp = np.where(during, 0.5 * speed * t**2 / ramp_time, speed * (t - 0.5 * ramp_time))
    vel = np.where(during, speed * t / ramp_time, speed)
    acc = np.where(accelerating, speed / ramp_time, 0.0)
    return disp, vel, acc


def constant_speed(t, speed: float, side: str = "right"):
    """Displacement speed t, speed, no acceleration."""
    t = np.asarray(t, dtype=float)
    return speed * t, speed + 0 * t, 0 * t


def smooth_ramp(t, speed: float, ramp_time: float, side: str = "right"):
    """Speed w STEP(t, 0, 0, T, 1) = w s^2 (3 - 2 s), s = t/T, then w.

    Displacement w T (s^3 - s^4/2) during the ramp (w T/2 at its end), then
    w T/2 + w (t - T); acceleration 6 w s (1 - s) / T, continuous at both ends.
    """
    t = np.asarray(t, dtype=float)
    s = np.clip(t / ramp_time, 0.0, 1.0)
    during = t < ramp_time
    disp = np.where(during, speed * ramp_time * (s**3 - 0.5 * s**4), speed * (t - 0.5 * ramp_time))
    vel = speed * s**2 * (3 - 2 * s)
    acc = 6 * speed * s * (1 - s) / ramp_time
    return disp, vel, acc


def table_speed(t, times, speeds, side: str = "right"):
    """Speed linear between the table's points (constant outside it), displacement its
    exact integral from times[0]; the acceleration jumps at the table times."""
    t = np.asarray(t, dtype=float)
    times = np.asarray(times, dtype=float)
    speeds = np.asarray(speeds, dtype=float)
    slopes = np.diff(speeds) / np.diff(times)
    # displacement at the table times (trapezoids are exact for linear speed)
    at_knots = np.concatenate([[0.0], np.cumsum(0.5 * (speeds[1:] + speeds[:-1]) * np.diff(times))])
    # segment index: times[i] <= t < times[i+1] (right limits) or times[i] < t <= times[i+1]
    i_raw = np.searchsorted(times, t, side="right" if side == "right" else "left") - 1
    inside = (i_raw >= 0) & (i_raw < len(times) - 1)
    i = np.clip(i_raw, 0, len(times) - 1)
    seg = np.minimum(i, len(slopes) - 1)
    a = np.where(inside, slopes[seg], 0.0)
    dt = t - times[i]
    vel = speeds[i] + a * dt
    disp = at_knots[i] + speeds[i] * dt + 0.5 * a * dt**2
    return disp, vel, a


def rotation(phi) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of an angle (array)."""
    return np.cos(phi), np.sin(phi)


def body_point(x, y, phi, local) -> tuple[np.ndarray, np.ndarray]:
    """Global position of a point given in the body frame relative to the centre of mass."""
    c, s = rotation(phi)
    return x + c * local[0] - s * local[1], y + s * local[0] + c * local[1]


# --- slider-crank ----------------------------------------------------------------------


@dataclass(frozen=True)
class SliderCrank:
    """Zero-offset slider-crank: crank pivot at the origin, slider on the x axis.

    Crank and rod are bars with their centres of mass at mid-length; the slider's centre of
    mass is the wrist pin. `gravity` is the gravity vector [m/s^2].
    """

    r: float = 0.08
    L: float = 0.32
    m_crank: float = 2.37
    J_crank: float = 0.01201
    m_rod: float = 0.72
    J_rod: float = 0.0006926
    m_slider: float = 2.28
    gravity: tuple[float, float] = (0.0, -9.81)

    # Position analysis and its first two derivatives with respect to theta.

    def slider_x(self, th):
        """x = r cos(th) + sqrt(L^2 - r^2 sin^2(th)) and dx/dth, d2x/dth2."""
        r, L = self.r, self.L
        c, s = rotation(th)
        S = np.sqrt(L**2 - (r * s) ** 2)
        x = r * c + S
        dx = -r * s - r**2 * s * c / S
        ddx = -r * c - r**2 * (c**2 - s**2) / S - r**4 * s**2 * c**2 / S**3
        return x, dx, ddx

    def slider_motion(self, th, thd, thdd):
        """Slider position, velocity and acceleration from the crank's angle, speed and
        acceleration: v = x' th', a = x'' th'^2 + x' th''."""
        x, dx, ddx = self.slider_x(th)
        return x, dx * thd, ddx * thd**2 + dx * thdd

    def rod_angle(self, th):
        """Angle psi of the rod (from crank pin to slider) and dpsi/dth, d2psi/dth2.

        sin(psi) = -r sin(th) / L, cos(psi) = S / L with S = sqrt(L^2 - r^2 sin^2 th).
        """
        r, L = self.r, self.L
        c, s = rotation(th)
        S = np.sqrt(L**2 - (r * s) ** 2)
        psi = np.arctan2(-r * s, S)
        dpsi = -r * c / S
        ddpsi = r * s / S - r**3 * s * c**2 / S**3
        return psi, dpsi, ddpsi

    def velocity_coefficients(self, th):
        """For each body (crank, rod, slider): mass, inertia, and the first and second
        derivatives with respect to th of (x_cm, y_cm, phi)."""
        r = self.r
        c, s = rotation(th)
        x, dx, ddx = self.slider_x(th)
        psi, dpsi, ddpsi = self.rod_angle(th)
        zero = np.zeros_like(np.asarray(th, dtype=float))
        one = zero + 1.0
        # crank centre of mass: (r/2)(cos th, sin th)
        crank = (
            self.m_crank,
            self.J_crank,
            (-0.5 * r * s, 0.5 * r * c, one),
            (-0.5 * r * c, -0.5 * r * s, zero),
        )
        # rod centre of mass: midpoint of crank pin (r cos th, r sin th) and slider (x, 0)
        rod = (
            self.m_rod,
            self.J_rod,
            (0.5 * (-r * s + dx), 0.5 * r * c, dpsi),
            (0.5 * (-r * c + ddx), -0.5 * r * s, ddpsi),
        )
        slider = (self.m_slider, 0.0, (dx, zero, zero), (ddx, zero, zero))
        return crank, rod, slider

    def generalized_mass(self, th):
        """m(th) = sum m |d r_cm/dth|^2 + J (dphi/dth)^2 and its derivative m'(th)."""
        m = 0.0
        dm = 0.0
        for mass, inertia, d1, d2 in self.velocity_coefficients(th):
            m = m + mass * (d1[0] ** 2 + d1[1] ** 2) + inertia * d1[2] ** 2
            dm = dm + 2 * mass * (d1[0] * d2[0] + d1[1] * d2[1]) + 2 * inertia * d1[2] * d2[2]
        return m, dm

    def potential(self, th):
        """Gravity potential V(th) = -sum m g . r_cm (datum: the origin)."""
        r = self.r
        c, s = rotation(th)
        x, _, _ = self.slider_x(th)
        gx, gy = self.gravity
        cms = (
            (self.m_crank, 0.5 * r * c, 0.5 * r * s),
            (self.m_rod, 0.5 * (r * c + x), 0.5 * r * s),
            (self.m_slider, x, 0.0 * x),
        )
        return sum(-mass * (gx * px + gy * py) for mass, px, py in cms)

    def potential_slope(self, th):
        """dV/dth = -sum m g . d r_cm / dth."""
        gx, gy = self.gravity
        return sum(
            -mass * (gx * d1[0] + gy * d1[1]) for mass, _, d1, _ in self.velocity_coefficients(th)
        )

    def motor_torque(self, th, thd, thdd):
        """Torque on the crank for a prescribed crank motion, by Lagrange's equation with
        T = m(th) thd^2 / 2: tau = m thdd + m'(th) thd^2 / 2 + V'(th)."""
        m, dm = self.generalized_mass(th)
        return m * thdd + 0.5 * dm * thd**2 + self.potential_slope(th)


# --- four-bar --------------------------------------------------------------------------


@dataclass(frozen=True)
class FourBar:
    """Four-bar linkage: ground pivots O2 = (0, 0) and O4 = (ground, 0); crank a (O2-A),
    coupler b (A-B), rocker c (O4-B). `branch` +1 puts B to the left of the directed line
    from A to O4 (for this layout: the open, upper assembly)."""

    ground: float
    a: float
    b: float
    c: float
    branch: int = 1

    def positions(self, th2):
        """Crank pin A, rocker pin B (two-circle intersection) and the coupler and rocker
        angles, for crank angle th2 (array)."""
        th2 = np.asarray(th2, dtype=float)
        ax, ay = self.a * np.cos(th2), self.a * np.sin(th2)
        dx, dy = self.ground - ax, -ay
        d = np.hypot(dx, dy)
        ex, ey = dx / d, dy / d
        along = (self.b**2 - self.c**2 + d**2) / (2 * d)
        h = np.sqrt(self.b**2 - along**2)
        bx = ax + along * ex - self.branch * h * ey
        by = ay + along * ey + self.branch * h * ex
        th3 = np.arctan2(by - ay, bx - ax)
        th4 = np.arctan2(by, bx - self.ground)
        return (ax, ay), (bx, by), th3, th4

    def is_grashof(self) -> bool:
        """s + l <= p + q."""
        links = sorted([self.ground, self.a, self.b, self.c])
        return links[0] + links[3] <= links[1] + links[2]


# --- single-degree-of-freedom oscillator -----------------------------------------------


def damped_free_vibration(t, mass: float, stiffness: float, damping: float, u0: float):
    """Displacement u(t) and velocity of m u'' + c u' + k u = 0 with u(0) = u0, u'(0) = 0,
    underdamped: u = u0 e^(-s t) (cos wd t + s/wd sin wd t), s = c/(2m),
    wd = sqrt(k/m - s^2); u' = -u0 (k/m)/wd e^(-s t) sin wd t."""
    t = np.asarray(t, dtype=float)
    s = damping / (2 * mass)
    w0sq = stiffness / mass
    wd = math.sqrt(w0sq - s**2)
    decay = np.exp(-s * t)
    u = u0 * decay * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    v = -u0 * w0sq / wd * decay * np.sin(wd * t)
    return u, v


# --- engine helpers --------------------------------------------------------------------


def simulate_ok(model, t_end: float, **options):
    """Runs `model.simulate` and fails the test unless the run reached `t_end`."""
    result = model.simulate(t_end, **options)
    assert result.status == "finished", f"run did not finish: {result.status}"
    assert abs(result.time[-1] - t_end) < 1e-12 * max(1.0, t_end)
    return result


def error_at_corners(t, actual, expected_of, corners):
    """|actual - expected(t)|, where a sample at a corner (a time at which the prescribed
    acceleration jumps) may match either the left or the right limit there.

    `expected_of(t, side)` returns the expected value for side "left" or "right"; away
    from the corners the two agree.
    """
    t_eval = np.asarray(t, dtype=float).copy()
    for corner in corners:
        t_eval[np.abs(t_eval - corner) < 1e-9] = corner
    left = np.abs(actual - expected_of(t_eval, "left"))
    right = np.abs(actual - expected_of(t_eval, "right"))
    return np.minimum(left, right)


def add_bar(m, name, mass, length, start, angle, points=None):
    """Adds a uniform bar (J = m l^2 / 12) whose end 'a' is at `start`, at `angle`; its
    other end is 'b'; `points` adds named points (body frame, from the centre of mass).
    Returns the global position of 'b'."""
    c, s = math.cos(angle), math.sin(angle)
    named = {"a": (-0.5 * length, 0.0), "b": (0.5 * length, 0.0), **(points or {})}
    m.add_body(
        name,
        mass,
        mass * length**2 / 12,
        position=(start[0] + 0.5 * length * c, start[1] + 0.5 * length * s),
        angle=angle,
        points=named,
    )
    return (start[0] + length * c, start[1] + length * s)


def add_four_bar(m, fb: FourBar, th2: float, masses=(0.5, 1.2, 0.8), coupler_points=None):
    """Adds crank, coupler and rocker (uniform bars) at the exact position of crank angle
    th2, branch fb.branch, with revolute joints ground_crank, crank_coupler,
    coupler_rocker, rocker_ground (the last with the ground as body_j)."""
    (ax, ay), (bx, by), th3, th4 = fb.positions(th2)
    add_bar(m, "crank", masses[0], fb.a, (0.0, 0.0), th2)
    add_bar(m, "coupler", masses[1], fb.b, (float(ax), float(ay)), float(th3), coupler_points)
    add_bar(m, "rocker", masses[2], fb.c, (fb.ground, 0.0), float(th4))
    m.add_revolute("ground_crank", "ground", "crank", point_i=(0.0, 0.0), point_j="a")
    m.add_revolute("crank_coupler", "crank", "coupler", point_i="b", point_j="a")
    m.add_revolute("coupler_rocker", "coupler", "rocker", point_i="b", point_j="b")
    m.add_revolute("rocker_ground", "rocker", "ground", point_i="a", point_j=(fb.ground, 0.0))


def wrap(angle):
    """Angle difference wrapped into (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(angle)))
