"""Ideal slider-crank against closed forms (docs/physics.md section 6).

Kinematics: x = r cos(th) + sqrt(L^2 - r^2 sin^2 th), differentiated exactly, with th(t)
from the linear ramp (th'' = w/T during the ramp). Motor torque: Lagrange's equation with
the crank angle as the only coordinate (virtual work), written independently in
reference.SliderCrank.
"""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from reference import SliderCrank, error_at_corners, linear_ramp, simulate_ok

OMEGA = 300 * 2 * math.pi / 60  # 300 rpm [rad/s]
RAMP = 0.2  # [s]
T_END = 0.5  # [s]: the ramp and 1.5 revolutions at full speed
RATE = 10_000  # [Hz]
SLIDER_INERTIA = 0.004  # [kg m^2]; irrelevant, the slider does not rotate

VERTICAL = SliderCrank(gravity=(0.0, -9.81))
HORIZONTAL = SliderCrank(gravity=(0.0, 0.0))

# Integrator tolerances per method (the test's accuracy bounds do not depend on them).
RTOL = {"dopri5": 1e-10, "sdirk4": 1e-10, "radau5": 1e-10}
ATOL = 1e-12


def build(sc: SliderCrank) -> jointgap.Model:
    """The founding slider-crank, fully extended at t = 0, driven by the 300 rpm ramp."""
    r, L = sc.r, sc.L
    m = jointgap.Model(name="slider_crank", gravity=sc.gravity)
    m.add_body(
        "crank",
        sc.m_crank,
        sc.J_crank,
        position=(r / 2, 0.0),
        points={"O": (-r / 2, 0.0), "A": (r / 2, 0.0)},
    )
    m.add_body(
        "rod",
        sc.m_rod,
        sc.J_rod,
        position=(r + L / 2, 0.0),
        points={"A": (-L / 2, 0.0), "B": (L / 2, 0.0)},
    )
    m.add_body("slider", sc.m_slider, SLIDER_INERTIA, position=(r + L, 0.0))
    m.add_revolute("ground_crank", "ground", "crank", point_i=(0.0, 0.0), point_j="O")
    m.add_revolute("crank_rod", "crank", "rod", point_i="A", point_j="A")
    m.add_revolute("rod_slider", "rod", "slider", point_i="B", point_j=(0.0, 0.0))
    m.add_prismatic(
        "slider_guide", "ground", "slider", axis=(1.0, 0.0), point_i=(0.0, 0.0), point_j=(0.0, 0.0)
    )
    m.add_driver("motor", "ground_crank", jointgap.profiles.linear_ramp(OMEGA, RAMP))
    return m


def crank_motion(t, side):
    """th, th', th'' of the crank; `side` picks the limit of th'' at the ramp's corner."""
    return linear_ramp(t, OMEGA, RAMP, side=side)


CORNERS = (0.0, RAMP)  # the ramp's acceleration jumps at its start and at its end


def error_at_either_side(t, actual, expected_of):
    """Error against the closed form, either limit accepted at the ramp's corners."""
    return error_at_corners(t, actual, expected_of, CORNERS)


def slider_expected(sc, t, side):
    return sc.slider_motion(*crank_motion(t, side))


# --- the closed form itself ------------------------------------------------------------


def test_closed_form_derivatives_match_numerical_differentiation():
    """The analytic slider velocity and acceleration (with the th'' term) are the time
    derivatives of the analytic position, during and after the ramp."""
    sc = VERTICAL
    t = np.linspace(0.003, T_END, 400)
    h = 1e-5
    t = t[np.abs(t - RAMP) > 10 * h]

    def motion(tt):
        return sc.slider_motion(*crank_motion(tt, "right"))

    def d_dt(k):
        """Fourth-order central difference of component k (0: x, 1: v) of the motion."""
        f = [motion(t + j * h)[k] for j in (-2, -1, 1, 2)]
        return (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / (12 * h)

    _, v, a = motion(t)
    v_peak = np.max(np.abs(v))
    a_peak = np.max(np.abs(a))
    assert np.max(np.abs(d_dt(0) - v)) < 1e-8 * v_peak
    assert np.max(np.abs(d_dt(1) - a)) < 1e-8 * a_peak
    # The th'' term matters: dropping it changes the acceleration during the ramp by
    # x'(th) w/T, up to r w/T ~ 12.6 m/s^2 here.
    th, thd, _ = crank_motion(t, "right")
    _, _, a_without = sc.slider_motion(th, thd, 0.0)
    assert np.max(np.abs(a_without - a)) > 0.05 * a_peak


def test_generalized_mass_and_potential_derivatives():
    """m'(th) and V'(th) of the virtual-work reference equal finite differences of m, V."""
    sc = VERTICAL
    th = np.linspace(0.0, 2 * math.pi, 73)
    h = 1e-5
    m, dm = sc.generalized_mass(th)
    m_num = (sc.generalized_mass(th + h)[0] - sc.generalized_mass(th - h)[0]) / (2 * h)
    v_num = (sc.potential(th + h) - sc.potential(th - h)) / (2 * h)
    assert np.max(np.abs(m_num - dm)) < 1e-8 * np.max(m)
    assert np.max(np.abs(v_num - sc.potential_slope(th))) < 1e-8 * sc.m_crank * 9.81 * sc.r
    # At th = 0 (fully extended) the slider does not move: m = J_crank + m_crank r^2/4
    # + J_rod (r/L)^2 + m_rod r^2/4 (the rod's centre of mass moves vertically by r/2 th).
    m0, _ = sc.generalized_mass(0.0)
    expected = (
        sc.J_crank
        + sc.m_crank * sc.r**2 / 4
        + sc.J_rod * (sc.r / sc.L) ** 2
        + sc.m_rod * sc.r**2 / 4
    )
    assert m0 == pytest.approx(expected, rel=1e-14)


# --- the engine against the closed form ------------------------------------------------


@pytest.mark.parametrize("method", ["dopri5", "sdirk4", "radau5"])
def test_slider_kinematics_match_closed_form(method):
    sc = VERTICAL
    r = simulate_ok(build(sc), T_END, rate=RATE, rtol=RTOL[method], atol=ATOL, method=method)
    t = r.time
    assert len(t) == int(round(T_END * RATE)) + 1
    x_ref, v_ref, a_ref = slider_expected(sc, t, "right")

    stroke = 2 * sc.r
    v_peak = np.max(np.abs(v_ref))
    a_peak = np.max(np.abs(a_ref))
    # Scales: peak |vx| ~ r w = 2.5 m/s, peak |ax| ~ r w^2 (1 + r/L) = 98.7 m/s^2.
    assert v_peak == pytest.approx(2.6, rel=0.05)
    assert a_peak == pytest.approx(OMEGA**2 * sc.r * (1 + sc.r / sc.L), rel=1e-3)

    err_x = np.max(np.abs(r["slider.x"] - x_ref))
    err_v = np.max(np.abs(r["slider.vx"] - v_ref))
    err_a = np.max(
        error_at_either_side(t, r["slider.ax"], lambda tt, s: slider_expected(sc, tt, s)[2])
    )
    assert err_x < 1e-6 * stroke, f"max |x error| = {err_x:.3e} m"
    assert err_v < 1e-6 * v_peak, f"max |vx error| = {err_v:.3e} m/s"
    assert err_a < 1e-6 * a_peak, f"max |ax error| = {err_a:.3e} m/s^2"

    # The slider stays on its axis without rotating.
    assert np.max(np.abs(r["slider.y"])) < 1e-10
    assert np.max(np.abs(r["slider.angle"])) < 1e-10
    # The crank follows the profile.
    th, thd, _ = crank_motion(t, "right")
    assert np.max(np.abs(r["crank.angle"] - th)) < 1e-9
    assert np.max(np.abs(r["crank.omega"] - thd)) < 1e-6 * OMEGA


@pytest.mark.parametrize(
    ("method", "sc"),
    [("dopri5", VERTICAL), ("dopri5", HORIZONTAL), ("sdirk4", VERTICAL)],
    ids=["dopri5-vertical", "dopri5-horizontal", "sdirk4-vertical"],
)
def test_motor_torque_matches_virtual_work(method, sc):
    """motor.torque (torque of the motor on the crank, counter-clockwise positive) equals
    m(th) th'' + m'(th) th'^2 / 2 + V'(th) at the simulated times."""
    r = simulate_ok(build(sc), T_END, rate=RATE, rtol=RTOL[method], atol=ATOL, method=method)
    t = r.time

    def expected(tt, side):
        return sc.motor_torque(*crank_motion(tt, side))

    tau_ref = expected(t, "right")
    peak = np.max(np.abs(tau_ref))
    err = np.max(error_at_either_side(t, r["motor.torque"], expected))
    assert err < 1e-6 * peak, f"max |torque error| = {err:.3e} N m, peak {peak:.3f} N m"

    # Sign and size: the motor accelerates the crank counter-clockwise from rest, fully
    # extended: just after t = 0 the torque is m(0) w/T + V'(0) > 0.
    m0, _ = sc.generalized_mass(0.0)
    tau0 = m0 * OMEGA / RAMP + sc.potential_slope(0.0)
    assert tau0 > 0.1 * peak
    assert expected(0.0, "right") == pytest.approx(tau0, rel=1e-12)
    assert r["motor.torque"][1] == pytest.approx(expected(t[1], "right"), rel=1e-5)
    if sc.gravity == (0.0, 0.0):
        # Horizontal plane at constant speed: over one revolution the motor does no net
        # work (the kinetic energy is periodic), so the torque averages to zero. One
        # revolution takes 0.2 s; integrate over [0.25, 0.45] s by the trapezoidal rule
        # (exact to round-off for a periodic integrand over a whole period).
        window = (t >= 0.25 - 1e-9) & (t <= 0.45 + 1e-9)
        tau = r["motor.torque"][window]
        dt = np.diff(t[window])
        work_per_speed = np.sum(0.5 * (tau[1:] + tau[:-1]) * dt)
        assert abs(work_per_speed) < 1e-6 * peak * 0.2


def test_founding_example_matches_closed_form():
    """examples/slider_crank_ideal.toml reproduces the closed-form kinematics and torque
    (crank and rod as bars with centres of mass at mid-length, docs/physics.md section 5)."""
    model = jointgap.load("examples/slider_crank_ideal.toml")
    r = simulate_ok(model, T_END, rate=RATE, rtol=1e-10, atol=ATOL, method="dopri5")
    sc = VERTICAL
    t = r.time
    x_ref, v_ref, a_ref = slider_expected(sc, t, "right")
    assert np.max(np.abs(r["slider.x"] - x_ref)) < 1e-6 * 2 * sc.r
    err_a = np.max(
        error_at_either_side(t, r["slider.ax"], lambda tt, s: slider_expected(sc, tt, s)[2])
    )
    assert err_a < 1e-6 * np.max(np.abs(a_ref))

    def expected(tt, side):
        return sc.motor_torque(*crank_motion(tt, side))

    tau_peak = np.max(np.abs(expected(t, "right")))
    err_tau = np.max(error_at_either_side(t, r["motor.torque"], expected))
    assert err_tau < 1e-6 * tau_peak
