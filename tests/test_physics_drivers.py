"""Drivers and applied loads against closed forms: every motion profile on a prismatic
joint (force = m a, sign along the axis), the revolute driver's torque sign, a driver
between two moving bodies (reaction on body_i), applied forces and a free body."""

from __future__ import annotations

import math
from functools import partial

import jointgap
import numpy as np
import pytest
from reference import (
    constant_speed,
    error_at_corners,
    linear_ramp,
    simulate_ok,
    smooth_ramp,
    table_speed,
    wrap,
)
from scipy.interpolate import CubicSpline

G = 9.81
MASS = 3.0


def table_angle(t, times, values, side="right"):
    """Natural cubic spline through the table (scipy), continued linearly beyond its last
    point with the end slope (no acceleration there)."""
    spline = CubicSpline(times, values, bc_type="natural")
    t = np.asarray(t, dtype=float)
    end = times[-1]
    inside = t <= end
    te = np.minimum(t, end)
    slope_end = spline(end, 1)
    disp = np.where(inside, spline(te), spline(end) + slope_end * (t - end))
    vel = np.where(inside, spline(te, 1), slope_end)
    acc = np.where(inside, spline(te, 2), 0.0)
    return disp, vel, acc


TABLE_T = [0.0, 0.1, 0.25, 0.4]
TABLE_X = [0.0, 0.03, -0.02, 0.05]
SPEED_T = [0.0, 0.1, 0.3]
SPEED_V = [0.0, 0.6, 0.2]

# (builder profile, reference (disp, speed, acc), times at which the acceleration jumps)
PROFILES = {
    "constant_speed": (
        jointgap.profiles.constant_speed(0.5),
        partial(constant_speed, speed=0.5),
        (),
    ),
    "linear_ramp": (
        jointgap.profiles.linear_ramp(0.5, 0.1),
        partial(linear_ramp, speed=0.5, ramp_time=0.1),
        (0.0, 0.1),
    ),
    "smooth_ramp": (
        jointgap.profiles.smooth_ramp(0.5, 0.1),
        partial(smooth_ramp, speed=0.5, ramp_time=0.1),
        (),
    ),
    "table_speed": (
        jointgap.profiles.table_speed(SPEED_T, SPEED_V),
        partial(table_speed, times=SPEED_T, speeds=SPEED_V),
        tuple(SPEED_T),
    ),
    "table_angle": (
        jointgap.profiles.table_angle(TABLE_T, TABLE_X),
        partial(table_angle, times=TABLE_T, values=TABLE_X),
        (),
    ),
}


@pytest.mark.parametrize("name", list(PROFILES))
def test_profile_reference_derivatives(name):
    """The reference speed and acceleration are derivatives of the reference displacement
    (fourth-order central differences away from the corners)."""
    _, ref, corners = PROFILES[name]
    t = np.linspace(0.001, 0.5, 500)
    h = 1e-5
    kinks = set(corners) | set(TABLE_T) | set(SPEED_T) | {0.1}  # jerk jumps too
    for c in kinks:
        t = t[np.abs(t - c) > 5 * h]
    for k in (0, 1):
        f = [ref(t + j * h)[k] for j in (-2, -1, 1, 2)]
        num = (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / (12 * h)
        assert np.max(np.abs(num - ref(t)[k + 1])) < 1e-7 * (1 + np.max(np.abs(ref(t)[k + 1])))


def pushed_slider(axis_angle: float, profile) -> jointgap.Model:
    """A slider on a prismatic guide from the origin along (cos a, sin a), in a vertical
    plane, moved by a driver on the guide."""
    c, s = math.cos(axis_angle), math.sin(axis_angle)
    m = jointgap.Model(name="pushed_slider", gravity=(0.0, -G))
    m.add_body("slider", MASS, 0.01)
    m.add_prismatic(
        "guide", "ground", "slider", axis=(c, s), point_i=(0.0, 0.0), point_j=(0.0, 0.0)
    )
    m.add_driver("push", "guide", profile)
    return m


@pytest.mark.parametrize("name", list(PROFILES))
@pytest.mark.parametrize("axis_deg", [0.0, 90.0, 30.0])
def test_prismatic_driver_force_is_mass_times_acceleration(name, axis_deg):
    """The slider moves by the profile's displacement along the axis; push.force (the
    motor's force on the slider, positive along the axis) is m (a + g sin(axis angle)):
    zero at constant speed on a horizontal guide, m x ramp acceleration during a ramp,
    +m g holding the slider on a vertical guide. The guide's reaction carries the
    weight's component across the axis."""
    profile, ref, corners = PROFILES[name]
    alpha = math.radians(axis_deg)
    t_end = 0.4 if name == "table_angle" else 0.5
    r = simulate_ok(pushed_slider(alpha, profile), t_end, rate=1000, rtol=1e-10, atol=1e-12)
    t = r.time
    disp, vel, _ = ref(t)
    c, s = math.cos(alpha), math.sin(alpha)
    assert np.max(np.abs(r["slider.x"] - c * disp)) < 1e-10
    assert np.max(np.abs(r["slider.y"] - s * disp)) < 1e-10
    assert np.max(np.abs(r["slider.vx"] - c * vel)) < 1e-9
    assert np.max(np.abs(r["slider.vy"] - s * vel)) < 1e-9
    assert np.max(np.abs(r["slider.angle"])) < 1e-12

    def expected_force(tt, side):
        return MASS * (ref(tt, side=side)[2] + G * s)

    err = np.max(error_at_corners(t, r["push.force"], expected_force, corners))
    scale = MASS * (G + np.max(np.abs(ref(t)[2])))
    assert err < 1e-8 * scale, f"max |force error| {err:.3e} N"
    # The guide pushes across the axis: m g cos(a) (-sin a, cos a).
    assert np.max(np.abs(r["guide.fx"] + MASS * G * c * s)) < 1e-8 * MASS * G
    assert np.max(np.abs(r["guide.fy"] - MASS * G * c * c)) < 1e-8 * MASS * G
    assert np.max(np.abs(r["guide.moment"])) < 1e-8 * MASS * G


def test_linear_ramp_force_sign_on_horizontal_guide():
    """Explicit numbers: 3 kg pushed from rest to 0.5 m/s in 0.1 s along +x needs +15 N,
    then nothing."""
    r = simulate_ok(
        pushed_slider(0.0, jointgap.profiles.linear_ramp(0.5, 0.1)), 0.3, rate=100, rtol=1e-10
    )
    during = (r.time > 0.005) & (r.time < 0.095)
    after = r.time > 0.105
    assert np.allclose(r["push.force"][during], 15.0, rtol=1e-8, atol=0)
    assert np.allclose(r["push.force"][after], 0.0, rtol=0, atol=1e-7)
    assert r["slider.vx"][-1] == pytest.approx(0.5, rel=1e-10)


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_revolute_driver_torque_sign(direction):
    """A crank pinned at its centre of mass, driven at constant speed (counter-clockwise
    for direction +1) against a constant applied torque -direction tau: the motor supplies
    +direction tau (torque on the driven body, counter-clockwise positive)."""
    tau, speed = 2.5, 10.0
    m = jointgap.Model(name="crank_vs_brake", gravity=(0.0, -G))
    m.add_body("crank", 1.2, 0.05)
    m.add_revolute("ground_crank", "ground", "crank", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_torque("brake", "crank", -direction * tau)
    m.add_driver("motor", "ground_crank", jointgap.profiles.constant_speed(direction * speed))
    r = simulate_ok(m, 1.0, rate=100, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(r["motor.torque"] - direction * tau)) < 1e-9 * tau
    assert np.max(np.abs(r["crank.omega"] - direction * speed)) < 1e-9 * speed
    assert np.max(np.abs(wrap(r["crank.angle"] - direction * speed * r.time))) < 1e-9
    # The pin carries the weight.
    assert np.max(np.abs(r["ground_crank.fy"] - 1.2 * G)) < 1e-9 * G


def test_driver_on_joint_with_ground_as_body_j():
    """Joint (crank, ground): the driver prescribes phi_ground - phi_crank = w t, so the
    crank turns clockwise; the channel then reports the motor's torque on body_i (the
    crank). Against a counter-clockwise load tau the motor supplies -tau."""
    tau, speed = 1.5, 4.0
    m = jointgap.Model(name="reversed_joint", gravity=(0.0, -G))
    m.add_body("crank", 1.0, 0.02)
    m.add_revolute("crank_ground", "crank", "ground", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_torque("load", "crank", tau)
    m.add_driver("motor", "crank_ground", jointgap.profiles.constant_speed(speed))
    r = simulate_ok(m, 1.0, rate=100, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(r["crank.omega"] + speed)) < 1e-9 * speed
    assert np.max(np.abs(r["motor.torque"] + tau)) < 1e-9 * tau
    # The joint's reaction is reported on body_j, here the ground: the crank's weight
    # pulls it down.
    assert np.max(np.abs(r["crank_ground.fy"] + 1.0 * G)) < 1e-9 * G


def test_tabulated_torque():
    """A torque table rising linearly from 0 to tau1 over 1 s, held after: on a wheel
    pinned at its centre, omega = tau1 t^2 / (2 J) then tau1 / (2 J) + tau1 (t - 1) / J."""
    inertia, tau1 = 0.1, 0.6
    m = jointgap.Model(name="torque_table", gravity=(0.0, 0.0))
    m.add_body("wheel", 1.0, inertia)
    m.add_revolute("pin", "ground", "wheel", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_torque("ramp", "wheel", ([0.0, 1.0], [0.0, tau1]))
    r = simulate_ok(m, 2.0, rate=50, rtol=1e-10, atol=1e-12)
    t = r.time
    omega = np.where(
        t < 1.0, tau1 * t**2 / (2 * inertia), tau1 / (2 * inertia) + tau1 * (t - 1) / inertia
    )
    alpha = np.where(t < 1.0, tau1 * t / inertia, tau1 / inertia)
    assert np.max(np.abs(r["wheel.omega"] - omega)) < 1e-9 * tau1 / inertia
    assert np.max(np.abs(r["wheel.alpha"] - alpha)) < 1e-12 * tau1 / inertia


def test_driver_between_two_moving_bodies():
    """Two wheels on one axle: wheel_1 pinned to the ground, wheel_2 pinned to wheel_1, a
    linear-ramp motor between them prescribing phi_2 - phi_1. The motor torque acts on
    body_j (wheel_2) and its reaction on body_i (wheel_1):
    J2 phi_2'' = tau, J1 phi_1'' = -tau, so tau = J1 J2 / (J1 + J2) theta''."""
    j1, j2, speed, ramp = 0.03, 0.01, 20.0, 0.5
    m = jointgap.Model(name="two_wheels", gravity=(0.0, -G))
    m.add_body("wheel_1", 2.0, j1)
    m.add_body("wheel_2", 1.0, j2)
    m.add_revolute("axle", "ground", "wheel_1", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_revolute("hub", "wheel_1", "wheel_2", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_driver("motor", "hub", jointgap.profiles.linear_ramp(speed, ramp))
    r = simulate_ok(m, 1.0, rate=100, rtol=1e-10, atol=1e-12)
    t = r.time
    theta, theta_d, _ = linear_ramp(t, speed, ramp)
    tau_expected = j1 * j2 / (j1 + j2) * speed / ramp

    def torque(tt, side):
        return j1 * j2 / (j1 + j2) * linear_ramp(tt, speed, ramp, side=side)[2]

    err = np.max(error_at_corners(t, r["motor.torque"], torque, (0.0, ramp)))
    assert err < 1e-9 * tau_expected
    assert np.max(np.abs(r["wheel_2.angle"] - r["wheel_1.angle"] - theta)) < 1e-10
    # Momentum about the axle is conserved: J1 w1 + J2 w2 = 0.
    assert np.max(np.abs(j1 * r["wheel_1.omega"] + j2 * r["wheel_2.omega"])) < 1e-9 * j2 * speed
    assert np.max(np.abs(r["wheel_1.omega"] + j2 / (j1 + j2) * theta_d)) < 1e-9 * speed


def test_applied_force_on_pinned_wheel():
    """A wheel pinned at its centre, a constant force F (global axes) at a rim point s:
    J phi'' = (A(phi) s) x F; the pin reaction on the wheel is -F - m g at all times."""
    mass, inertia = 2.0, 0.04
    force = (3.0, -1.5)
    rim = (0.1, 0.05)
    m = jointgap.Model(name="wheel_with_force", gravity=(0.0, -G))
    m.add_body("wheel", mass, inertia, points={"rim": rim})
    m.add_revolute("pin", "ground", "wheel", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    m.add_force("push", "wheel", force, point="rim")
    r = simulate_ok(m, 2.0, rate=200, rtol=1e-10, atol=1e-12)
    phi = r["wheel.angle"]
    sx = np.cos(phi) * rim[0] - np.sin(phi) * rim[1]
    sy = np.sin(phi) * rim[0] + np.cos(phi) * rim[1]
    moment = sx * force[1] - sy * force[0]
    assert (
        np.max(np.abs(r["wheel.alpha"] - moment / inertia))
        < 1e-9 * np.max(np.abs(moment)) / inertia
    )
    # At t = 0: s x F = 0.1 (-1.5) - 0.05 (3) = -0.3 N m, clockwise.
    assert r["wheel.alpha"][0] == pytest.approx(-0.3 / inertia, rel=1e-12)
    assert np.max(np.abs(r["pin.fx"] + force[0])) < 1e-9
    assert np.max(np.abs(r["pin.fy"] + force[1] - mass * G)) < 1e-9
    # Energy balance: the force's work equals the kinetic energy (the pin does none).
    px, py = sx, sy
    work = force[0] * (px - px[0]) + force[1] * (py - py[0])
    assert np.max(np.abs(r["system.kinetic_energy"] - work)) < 1e-9 * np.max(np.abs(work))


def test_free_body_projectile():
    """A body without joints: parabola for the centre of mass, constant spin; an applied
    force through the centre of mass adds F t^2 / (2 m)."""
    mass, inertia = 1.5, 0.02
    v0, w0, f = (3.0, 4.0), 2.0, (0.6, 0.0)
    m = jointgap.Model(name="projectile", gravity=(0.0, -G))
    m.add_body("ball", mass, inertia, position=(0.1, 0.2), velocity=v0, omega=w0)
    m.add_force("wind", "ball", f)
    r = simulate_ok(m, 1.0, rate=100, rtol=1e-10, atol=1e-12)
    t = r.time
    assert np.max(np.abs(r["ball.x"] - (0.1 + v0[0] * t + 0.5 * f[0] / mass * t**2))) < 1e-10
    assert np.max(np.abs(r["ball.y"] - (0.2 + v0[1] * t - 0.5 * G * t**2))) < 1e-10
    assert np.max(np.abs(r["ball.angle"] - w0 * t)) < 1e-10
    assert np.max(np.abs(r["ball.ax"] - f[0] / mass)) < 1e-12
    assert np.max(np.abs(r["ball.ay"] + G)) < 1e-12
    assert np.max(np.abs(r["system.constraint_error"])) == 0.0
