"""Pendulums against closed forms: the large-amplitude period (complete elliptic integral),
the pin reaction of a swinging pendulum, and a torsional pendulum."""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from reference import simulate_ok, wrap
from scipy.interpolate import CubicHermiteSpline
from scipy.special import ellipk

G = 9.81

# The simple pendulum of the check: massless 1 m link, 1 kg point mass, released
# horizontally from rest. Period T = 4 sqrt(L/g) K(k^2) with k = sin(theta0/2) and
# theta0 = pi/2 the amplitude; scipy's ellipk takes the parameter m = k^2 = 1/2.
L_SIMPLE = 1.0
PERIOD = 2.367841947576  # [s]

# The engine needs J > 0, so the point mass becomes a compound pendulum: mass m, centre of
# mass at d from the pivot, centroidal inertia J. Its equation of motion about the pivot,
# (J + m d^2) phi'' = -m g d cos(phi) (phi from the horizontal), divided by m d reads
# L_eq phi'' = -g cos(phi) with L_eq = (J + m d^2) / (m d): the simple pendulum's equation
# of length L_eq, term for term, with the same initial conditions. The two motions are
# identical, not approximately equal, so the period is the same. With d = 0.5 m and
# J = m d (1 - d): L_eq = (m d (1 - d) + m d^2) / (m d) = 1 m.
MASS = 1.0
D = 0.5
J = MASS * D * (1 - D)


def compound_pendulum() -> jointgap.Model:
    m = jointgap.Model(name="pendulum", gravity=(0.0, -G))
    m.add_body("bob", MASS, J, position=(D, 0.0), angle=0.0, points={"pivot": (-D, 0.0)})
    m.add_revolute("pin", "ground", "bob", point_i=(0.0, 0.0), point_j="pivot")
    return m


def zero_crossings(t, f, dfdt):
    """Roots of f on (t[0], t[-1]] from the cubic Hermite interpolant of samples of f and
    its derivative (interpolation error O(dt^4))."""
    spline = CubicHermiteSpline(t, f, dfdt)
    roots = spline.roots(extrapolate=False)
    return np.sort(roots[roots > t[0] + 1e-6])


def test_reference_period_is_the_elliptic_integral():
    assert J + MASS * D**2 == pytest.approx(MASS * D * L_SIMPLE, rel=1e-15)
    exact = 4 * math.sqrt(L_SIMPLE / G) * ellipk(math.sin(math.pi / 4) ** 2)
    assert exact == pytest.approx(PERIOD, abs=1e-12)
    # 18 % longer than the small-angle period 2 pi sqrt(L/g) = 2.006 s.
    assert PERIOD / (2 * math.pi * math.sqrt(L_SIMPLE / G)) == pytest.approx(1.18034, rel=1e-5)


def test_large_amplitude_period():
    """Turning points (omega = 0) fall at k T/2 with T the elliptic-integral period,
    within 1e-8 relative; the pendulum reaches the horizontal on both sides."""
    r = simulate_ok(compound_pendulum(), 10.0, rate=1000, rtol=1e-11, atol=1e-13, method="dopri5")
    t_turn = zero_crossings(r.time, r["bob.omega"], r["bob.alpha"])
    assert len(t_turn) == 8  # 10 s is 4.2 periods
    k = np.arange(1, len(t_turn) + 1)
    estimates = 2 * t_turn / k
    worst = np.max(np.abs(estimates / PERIOD - 1))
    assert worst < 1e-8, f"period error {worst:.2e} relative; estimates {estimates}"
    # The first swing's half-period, from the first two turning points alone.
    assert 2 * (t_turn[1] - t_turn[0]) == pytest.approx(PERIOD, rel=1e-8)
    # At the turning points the bar is horizontal: angle 0 (start side) or -pi.
    angle = CubicHermiteSpline(r.time, r["bob.angle"], r["bob.omega"])(t_turn)
    expected = np.where(k % 2 == 1, -math.pi, 0.0)
    assert np.max(np.abs(wrap(angle - expected))) < 1e-8


def test_swinging_pendulum_pin_reaction():
    """pin.fx, pin.fy is the force of the pin on the bob (body_j): m a_cm - m g, with a_cm
    from the closed-form angular velocity and acceleration at the simulated angle:
    phi'^2 = -2 m g d sin(phi) / J_O, phi'' = -m g d cos(phi) / J_O, J_O = J + m d^2."""
    r = simulate_ok(compound_pendulum(), 3.0, rate=500, rtol=1e-11, atol=1e-13, method="dopri5")
    phi = r["bob.angle"]
    j_o = J + MASS * D**2
    w2 = -2 * MASS * G * D * np.sin(phi) / j_o
    alpha = -MASS * G * D * np.cos(phi) / j_o
    assert np.min(w2) > -1e-9
    assert np.max(np.abs(r["bob.omega"] ** 2 - w2)) < 1e-8 * np.max(w2)
    assert np.max(np.abs(r["bob.alpha"] - alpha)) < 1e-8 * G / D
    c, s = np.cos(phi), np.sin(phi)
    ax = D * (-s * alpha - c * w2)
    ay = D * (c * alpha - s * w2)
    fx = MASS * ax
    fy = MASS * (ay + G)
    scale = MASS * G
    assert np.max(np.abs(r["pin.fx"] - fx)) < 1e-8 * scale
    assert np.max(np.abs(r["pin.fy"] - fy)) < 1e-8 * scale
    # At release (phi = 0, at rest) the pin carries m g (1 - m d^2 / J_O) = m g / 2 here;
    # at the bottom (phi = -pi/2) it pulls up with m g (1 + 2 m d^2 / J_O) = 2 m g (not the
    # point mass's 3 m g: same motion, different mass distribution). The 500 Hz samples
    # miss the bottom by up to 4.4e-3 rad, hence the looser bound on the maximum.
    assert r["pin.fy"][0] == pytest.approx(MASS * G * (1 - MASS * D**2 / j_o), rel=1e-9)
    assert np.max(r["pin.fy"]) == pytest.approx(MASS * G * (1 + 2 * MASS * D**2 / j_o), rel=1e-3)


@pytest.mark.parametrize("ground_first", [True, False])
def test_hanging_pendulum_at_rest_reaction_sign(ground_first):
    """A pendulum hanging at rest. The reaction is reported on body_j: with (ground, bob)
    the pin holds the bob up, pin.fy = +m g; with (bob, ground) it is the force on the
    ground, pulled down, pin.fy = -m g."""
    m = jointgap.Model(name="hanging", gravity=(0.0, -G))
    m.add_body("bob", 2.0, 0.1, position=(0.0, -0.5), angle=-math.pi / 2)
    if ground_first:
        m.add_revolute("pin", "ground", "bob", point_i=(0.0, 0.0), point_j=(-0.5, 0.0))
    else:
        m.add_revolute("pin", "bob", "ground", point_i=(-0.5, 0.0), point_j=(0.0, 0.0))
    r = simulate_ok(m, 1.0, rate=10, rtol=1e-10, atol=1e-12)
    sign = 1.0 if ground_first else -1.0
    assert np.max(np.abs(r["pin.fy"] - sign * 2.0 * G)) < 1e-9 * G
    assert np.max(np.abs(r["pin.fx"])) < 1e-9 * G
    assert np.max(np.abs(r["bob.angle"] + math.pi / 2)) < 1e-12
    assert np.max(np.abs(r["bob.y"] + 0.5)) < 1e-12


def test_torsional_pendulum():
    """A wheel pinned at its centre on a rotational spring (no damping): angle
    phi0 cos(w t), w = sqrt(k/J), period 2 pi sqrt(J/k); energy k phi^2/2 + J w^2/2 is
    kept; gravity loads only the pin."""
    inertia, k, phi0, mass = 0.02, 3.0, 0.4, 1.5
    m = jointgap.Model(name="torsional", gravity=(0.0, -G))
    m.add_body("wheel", mass, inertia, angle=phi0)
    m.add_revolute("pin", "ground", "wheel", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_rotational_spring_damper("spring", "ground", "wheel", stiffness=k, damping=0.0)
    r = simulate_ok(m, 3.0, rate=1000, rtol=1e-11, atol=1e-13, method="dopri5")
    w = math.sqrt(k / inertia)
    t = r.time
    assert np.max(np.abs(r["wheel.angle"] - phi0 * np.cos(w * t))) < 1e-8 * phi0
    assert np.max(np.abs(r["wheel.omega"] + phi0 * w * np.sin(w * t))) < 1e-8 * phi0 * w
    assert np.max(np.abs(r["wheel.alpha"] + k / inertia * r["wheel.angle"])) < 1e-9 * phi0 * w**2
    period = 2 * math.pi * math.sqrt(inertia / k)
    t_turn = zero_crossings(t, r["wheel.omega"], r["wheel.alpha"])
    k_turn = np.arange(1, len(t_turn) + 1)
    assert len(t_turn) == int(3.0 // (period / 2))
    assert np.max(np.abs(2 * t_turn / k_turn / period - 1)) < 1e-8
    # The pin carries the weight (force on the wheel, body_j, upwards).
    assert np.max(np.abs(r["pin.fy"] - mass * G)) < 1e-9 * mass * G
    assert np.max(np.abs(r["pin.fx"])) < 1e-9 * mass * G
    # Energy: kinetic plus spring potential plus (constant) gravity potential.
    e = r["system.kinetic_energy"] + r["system.potential_energy"]
    spring_energy = 0.5 * k * phi0**2
    assert np.max(np.abs(e - e[0])) < 1e-9 * spring_energy
    assert r["system.kinetic_energy"][0] == pytest.approx(0.0, abs=1e-15)
    assert e[0] == pytest.approx(spring_energy, rel=1e-12)
    # The potential is the torsion spring's k phi^2 / 2 (the centre of mass stays at y = 0).
    pe = 0.5 * k * r["wheel.angle"] ** 2
    assert np.max(np.abs(r["system.potential_energy"] - pe)) < 1e-12 * spring_energy


def test_applied_torque_spins_up_a_wheel():
    """A constant counter-clockwise torque tau on a wheel pinned at its centre:
    omega = tau t / J, angle = tau t^2 / (2 J); a clockwise torque turns it the other way."""
    inertia, tau = 0.05, 0.8
    for sign in (1.0, -1.0):
        m = jointgap.Model(name="wheel", gravity=(0.0, -G))
        m.add_body("wheel", 3.0, inertia, position=(0.2, 0.1))
        m.add_revolute("pin", "ground", "wheel", point_i=(0.2, 0.1), point_j=(0.0, 0.0))
        m.add_torque("motor_load", "wheel", sign * tau)
        r = simulate_ok(m, 2.0, rate=100, rtol=1e-10, atol=1e-12)
        t = r.time
        assert np.max(np.abs(r["wheel.omega"] - sign * tau * t / inertia)) < 1e-9 * tau / inertia
        assert np.max(np.abs(r["wheel.angle"] - sign * 0.5 * tau * t**2 / inertia)) < 1e-8
        assert np.max(np.abs(r["wheel.alpha"] - sign * tau / inertia)) < 1e-9 * tau / inertia
        assert np.max(np.abs(r["wheel.x"] - 0.2)) < 1e-12
        # Work done equals the kinetic energy gained.
        ke = r["system.kinetic_energy"]
        assert ke[-1] == pytest.approx(0.5 * (tau * t[-1]) ** 2 / inertia, rel=1e-9)
