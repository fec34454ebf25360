"""Grashof four-bar (crank-rocker) driven at constant speed: the coupler-point path
against the closed-form loop closure (two-circle intersection on the assembly branch),
and the initial assembly from an approximate placement."""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from reference import FourBar, add_bar, add_four_bar, body_point, simulate_ok, wrap

# Ground 0.40 m, crank 0.12 m, coupler 0.35 m, rocker 0.30 m: s + l = 0.52 < p + q = 0.65
# and the shortest link is the crank, so the crank turns fully and the rocker rocks.
TH2_0 = 0.5  # initial crank angle [rad]
SPEED = 2 * math.pi  # 60 rpm [rad/s]
P_LOCAL = (0.05, 0.10)  # coupler point, coupler frame, from the coupler's centre of mass [m]


def coupler_point_closed_form(fb: FourBar, th2):
    """Coupler point P and coupler angle from the crank angle (loop closure)."""
    (ax, ay), _, th3, th4 = fb.positions(th2)
    cx = ax + 0.5 * fb.b * np.cos(th3)
    cy = ay + 0.5 * fb.b * np.sin(th3)
    px, py = body_point(cx, cy, th3, P_LOCAL)
    return px, py, th3, th4


def driven_four_bar(fb: FourBar) -> jointgap.Model:
    m = jointgap.Model(name="four_bar", gravity=(0.0, -9.81))
    add_four_bar(m, fb, TH2_0, coupler_points={"P": P_LOCAL})
    m.add_driver("motor", "ground_crank", jointgap.profiles.constant_speed(SPEED))
    return m


@pytest.mark.parametrize("branch", [1, -1], ids=["open", "crossed"])
def test_coupler_point_path_matches_loop_closure(branch):
    fb = FourBar(ground=0.4, a=0.12, b=0.35, c=0.3, branch=branch)
    assert fb.is_grashof()
    assert min(fb.ground, fb.a, fb.b, fb.c) == fb.a  # crank-rocker
    r = simulate_ok(driven_four_bar(fb), 2.0, rate=100, rtol=1e-10, atol=1e-12)
    t = r.time
    th2 = TH2_0 + SPEED * t
    px_ref, py_ref, th3_ref, th4_ref = coupler_point_closed_form(fb, th2)
    px, py = body_point(r["coupler.x"], r["coupler.y"], r["coupler.angle"], P_LOCAL)
    err = np.max(np.hypot(px - px_ref, py - py_ref))
    assert err < 1e-8, f"coupler point off the closed-form path by {err:.3e} m"
    assert np.max(np.abs(wrap(r["coupler.angle"] - th3_ref))) < 1e-8
    assert np.max(np.abs(wrap(r["rocker.angle"] - th4_ref))) < 1e-8
    # The path is a closed curve of period one crank revolution (1 s).
    assert np.hypot(px[100] - px[0], py[100] - py[0]) < 1e-8

    # Velocity of P: v_cm + omega x (A s'), against the time derivative of the closed-form
    # path (fourth-order central difference, error ~1e-12 m/s).
    h = 1e-5

    def path(dt):
        x, y, _, _ = coupler_point_closed_form(fb, TH2_0 + SPEED * (t + dt))
        return np.array([x, y])

    v_ref = (path(-2 * h) - 8 * path(-h) + 8 * path(h) - path(2 * h)) / (12 * h)
    phi, w = r["coupler.angle"], r["coupler.omega"]
    c, s = np.cos(phi), np.sin(phi)
    sx, sy = c * P_LOCAL[0] - s * P_LOCAL[1], s * P_LOCAL[0] + c * P_LOCAL[1]
    vx = r["coupler.vx"] - w * sy
    vy = r["coupler.vy"] + w * sx
    v_peak = np.max(np.hypot(*v_ref))
    assert np.max(np.hypot(vx - v_ref[0], vy - v_ref[1])) < 1e-8 * v_peak


def test_assembly_from_approximate_placement():
    """Coupler and rocker placed a few millimetres and degrees off: assembly (Newton on
    the position constraints, crank held by its driver) closes the loop on the branch of
    the placement, and the run then follows the closed form."""
    fb = FourBar(ground=0.4, a=0.12, b=0.35, c=0.3, branch=1)
    (ax, ay), (bx, by), th3, th4 = fb.positions(TH2_0)
    m = jointgap.Model(name="four_bar_misplaced", gravity=(0.0, -9.81))
    add_bar(m, "crank", 0.5, fb.a, (0.0, 0.0), TH2_0)
    add_bar(
        m,
        "coupler",
        1.2,
        fb.b,
        (float(ax) + 0.003, float(ay) - 0.002),
        float(th3) + 0.04,
        {"P": P_LOCAL},
    )
    add_bar(m, "rocker", 0.8, fb.c, (fb.ground - 0.002, 0.001), float(th4) - 0.03)
    m.add_revolute("ground_crank", "ground", "crank", point_i=(0.0, 0.0), point_j="a")
    m.add_revolute("crank_coupler", "crank", "coupler", point_i="b", point_j="a")
    m.add_revolute("coupler_rocker", "coupler", "rocker", point_i="b", point_j="b")
    m.add_revolute("rocker_ground", "rocker", "ground", point_i="a", point_j=(fb.ground, 0.0))
    m.add_driver("motor", "ground_crank", jointgap.profiles.constant_speed(SPEED))
    r = simulate_ok(m, 1.0, rate=100, rtol=1e-10, atol=1e-12)
    assert r["crank.angle"][0] == pytest.approx(TH2_0, abs=1e-12)
    assert r["coupler.angle"][0] == pytest.approx(float(th3), abs=1e-10)
    assert r["rocker.angle"][0] == pytest.approx(float(th4), abs=1e-10)
    assert np.max(np.abs(r["system.constraint_error"])) < 1e-10
    px_ref, py_ref, _, _ = coupler_point_closed_form(fb, TH2_0 + SPEED * r.time)
    px, py = body_point(r["coupler.x"], r["coupler.y"], r["coupler.angle"], P_LOCAL)
    assert np.max(np.hypot(px - px_ref, py - py_ref)) < 1e-8
