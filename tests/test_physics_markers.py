"""Markers and joint coordinates against the closed-form slider-crank.

A marker on the connecting rod (in the ground frame) and the wrist pin seen from the
crank (in the crank's frame), and the coordinates of every joint, against positions
written as functions of the crank angle th and differentiated by the chain rule:
v = P'(th) th', a = P''(th) th'^2 + P'(th) th'' (reference.SliderCrank gives the rod's
and slider's derivatives with respect to th).
"""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from reference import error_at_corners, rotation, simulate_ok
from test_physics_slider_crank import CORNERS, OMEGA, VERTICAL, build, crank_motion

SC = VERTICAL
ROD_POINT = (0.05, 0.012)  # a point of the rod off its axis, rod frame from its CM [m]
T_END = 0.5
RATE = 10_000


def turn(phi, p):
    """A(phi) p for a fixed vector p, and perp(A p) (its derivative by phi)."""
    c, s = rotation(phi)
    ax, ay = c * p[0] - s * p[1], s * p[0] + c * p[1]
    return np.array([ax, ay]), np.array([-ay, ax])


def rod_point(th):
    """The rod point P and dP/dth, d2P/dth2: P = r_cm(th) + A(psi(th)) p."""
    _, rod, _ = SC.velocity_coefficients(th)
    _, _, d1, d2 = rod
    r = SC.r
    x, _, _ = SC.slider_x(th)
    psi, dpsi, ddpsi = SC.rod_angle(th)
    cm = np.array([0.5 * (r * np.cos(th) + x), 0.5 * r * np.sin(th)])
    arm, arm_perp = turn(psi, ROD_POINT)
    p = cm + arm
    dp = np.array([d1[0], d1[1]]) + dpsi * arm_perp
    ddp = np.array([d2[0], d2[1]]) + ddpsi * arm_perp - dpsi**2 * arm
    return p, dp, ddp


def pin_in_crank_frame(th):
    """The wrist pin B = (x, 0) in the crank's frame, u = A(th)^T (B - c), c the crank's
    centre of mass (r/2)(cos th, sin th), and du/dth, d2u/dth2. With d/dth A^T = -A^T J:
    u' = A^T (d' - J d), u'' = A^T (d'' - 2 J d' - d), d = B - c."""
    r = SC.r
    x, dx, ddx = SC.slider_x(th)
    c, s = rotation(th)
    d = np.array([x - 0.5 * r * c, -0.5 * r * s])
    dd = np.array([dx + 0.5 * r * s, -0.5 * r * c])
    ddd = np.array([ddx + 0.5 * r * c, 0.5 * r * s])

    def J(v):
        return np.array([-v[1], v[0]])

    def back(v):  # A(th)^T v
        return np.array([c * v[0] + s * v[1], -s * v[0] + c * v[1]])

    return back(d), back(dd - J(d)), back(ddd - 2 * J(dd) - d)


def in_time(of_th, t, side):
    """Position, velocity, acceleration against time from functions of th."""
    th, thd, thdd = crank_motion(t, side)
    p, dp, ddp = of_th(th)
    return p, dp * thd, ddp * thd**2 + dp * thdd


@pytest.fixture(scope="module")
def run() -> jointgap.Result:
    model = build(SC)
    model.add_marker("rod_point", "rod", ROD_POINT)
    model.add_marker("pin_on_crank", "rod", (SC.L / 2, 0.0), frame="crank")
    return simulate_ok(model, T_END, rate=RATE, rtol=1e-12, atol=1e-14, method="dopri5")


@pytest.mark.parametrize(
    ("marker", "of_th"), [("rod_point", rod_point), ("pin_on_crank", pin_in_crank_frame)]
)
def test_marker_matches_the_closed_form(run, marker, of_th):
    """Position, velocity and acceleration of the marker to 1e-8 of their scales (the
    acceleration's jumps at the ramp's corners either side)."""
    t = run.time
    scales = {"": SC.L, "v": OMEGA * SC.r, "a": OMEGA**2 * SC.r}
    for k, prefix in enumerate(("", "v", "a")):
        for axis in (0, 1):
            name = f"{marker}.{prefix}{'xy'[axis]}"

            def expected(tt, side, k=k, axis=axis):
                return in_time(of_th, tt, side)[k][axis]

            err = np.max(error_at_corners(t, run[name], expected, CORNERS))
            assert err < 1e-8 * scales[prefix], f"{name}: max error {err:.3e}"
    # Not a constant: the checks compare real motion.
    assert np.ptp(run[f"{marker}.ax"]) > 10.0


def test_marker_in_the_crank_frame_is_not_the_global_motion(run):
    """Seen from the crank the wrist pin swings about a point; the ground frame sees it
    slide along x. The frame changes the numbers, not only their axes."""
    assert np.max(np.abs(run["pin_on_crank.y"])) > 0.01
    speed_seen = np.hypot(run["pin_on_crank.vx"], run["pin_on_crank.vy"])
    assert np.max(np.abs(speed_seen - np.abs(run["slider.vx"]))) > 1.0


def test_joint_coordinates_match_the_closed_form(run):
    """Relative angles and rates of the revolute joints, travel and speed of the slider."""
    t = run.time
    th, thd, _ = crank_motion(t, "right")
    psi, dpsi, _ = SC.rod_angle(th)
    x, dx, _ = SC.slider_x(th)
    expected = {
        "ground_crank.angle": th,
        "ground_crank.omega": thd,
        "crank_rod.angle": psi - th,
        "crank_rod.omega": (dpsi - 1.0) * thd,
        "rod_slider.angle": 0.0 - psi,  # the slider does not turn
        "rod_slider.omega": -dpsi * thd,
        "slider_guide.travel": x,
        "slider_guide.speed": dx * thd,
    }
    for name, value in expected.items():
        scale = OMEGA if name.endswith((".omega", ".speed")) else 1.0
        err = np.max(np.abs(run[name] - value))
        assert err < 1e-8 * scale, f"{name}: max error {err:.3e}"
    assert jointgap.channel_unit("slider_guide.travel") == "m"
    assert jointgap.channel_unit("slider_guide.speed") == "m/s"
    assert jointgap.channel_unit("crank_rod.omega") == "rad/s"


def test_joint_coordinate_channels_follow_each_joint(run):
    names = run.channels
    i = names.index("crank_rod.fy")
    assert names[i + 1 : i + 3] == ["crank_rod.angle", "crank_rod.omega"]
    i = names.index("slider_guide.moment")
    assert names[i + 1 : i + 3] == ["slider_guide.travel", "slider_guide.speed"]
    # markers after the drivers, before the system
    assert names.index("motor.torque") < names.index("rod_point.x")
    assert names.index("pin_on_crank.ay") < names.index("system.kinetic_energy")


def test_marker_from_a_model_file_and_back(tmp_path):
    """[[marker]] in a model file: read, written back by save, rerun alike."""
    text = (
        open("examples/slider_crank_ideal.toml").read()
        + '\n[[marker]]\nname = "big_end"\nbody = "rod"\npoint = "A"\nframe = "crank"\n'
    )
    model = jointgap.loads(text, "with_marker.toml")
    assert model.markers["big_end"] == {
        "name": "big_end",
        "body": "rod",
        "point": "A",
        "frame": "crank",
    }
    model.save(tmp_path / "again.toml")
    again = jointgap.load(tmp_path / "again.toml")
    assert again == model
    r = again.simulate(0.05, rate=1000)
    # The big end is the crank pin: fixed in the crank's frame at (r/2, 0).
    np.testing.assert_allclose(r["big_end.x"], 0.04, atol=1e-9)
    np.testing.assert_allclose(r["big_end.y"], 0.0, atol=1e-9)
    assert np.max(np.abs(r["big_end.vx"])) < 1e-7


@pytest.mark.parametrize(
    ("marker", "message"),
    [
        ('name = "m"\nbody = "rodd"\npoint = [0, 0]', "with_marker.toml:"),
        ('name = "m"\nbody = "rod"\npoint = "Z"', "'Z' is not a point of body 'rod'"),
        ('name = "m"\nbody = "rod"', "missing field 'point'"),
        ('name = "m"\nbody = "rod"\npoint = [0, 0]\nframe = "crnk"', "frame 'crnk'"),
        ('name = "crank"\nbody = "rod"\npoint = [0, 0]', "crank"),
    ],
)
def test_bad_markers_are_errors_naming_them(marker, message):
    text = open("examples/slider_crank_ideal.toml").read() + "\n[[marker]]\n" + marker + "\n"
    with pytest.raises(jointgap.ModelError) as err:
        jointgap.loads(text, "with_marker.toml")
    assert message in str(err.value)
    assert "marker" in str(err.value)


def test_builder_marker_with_units():
    model = build(SC).add_marker("tip", "crank", ("40 mm", "0 mm"))
    assert model.markers["tip"]["point"] == [0.04, 0.0]
    assert "frame" not in model.markers["tip"]
    r = model.simulate(0.01, rate=1000)
    th = crank_motion(r.time, "right")[0]
    np.testing.assert_allclose(r["tip.x"], SC.r * np.cos(th), atol=1e-9)
    assert math.isclose(r["tip.y"][-1], SC.r * math.sin(th[-1]), abs_tol=1e-9)
