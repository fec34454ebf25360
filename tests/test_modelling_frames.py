"""Modelling as an engineer writes it: bodies in their own frames, initial conditions by
joint coordinates, point masses. Each against physics: the same mechanism written two
ways, closed-form slider-crank kinematics, the energy of a passive mechanism."""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from reference import SliderCrank, error_at_corners, linear_ramp, simulate_ok

SC = SliderCrank(gravity=(0.0, -9.81))
OMEGA = 10 * math.pi  # 300 rpm [rad/s]
RAMP = 0.2  # [s]


def slider_crank(
    frames: str = "centre", slider_inertia: float = 0.004, driven: bool = True
) -> jointgap.Model:
    """The founding slider-crank, fully extended at t = 0. ``frames="own"`` describes the
    crank from its pivot and the rod from its big end (``com`` at mid-length), as a CAD
    or URDF model would; ``"centre"`` from the centres of mass."""
    r, L = SC.r, SC.L
    m = jointgap.Model(name="slider_crank", gravity=SC.gravity)
    if frames == "own":
        m.add_body(
            "crank",
            SC.m_crank,
            SC.J_crank,
            com=(r / 2, 0.0),
            position=(0.0, 0.0),
            points={"O": (0.0, 0.0), "A": (r, 0.0)},
            shape={"type": "bar", "from": (0.0, 0.0), "to": "A"},
        )
        m.add_body(
            "rod",
            SC.m_rod,
            SC.J_rod,
            com=("160 mm", 0.0),
            position=(r, 0.0),
            points={"A": (0.0, 0.0)},
        )
        rod_b: tuple[float, float] = (L, 0.0)  # a joint point given as a vector
    else:
        m.add_body(
            "crank",
            SC.m_crank,
            SC.J_crank,
            position=(r / 2, 0.0),
            points={"O": (-r / 2, 0.0), "A": (r / 2, 0.0)},
            shape={"type": "bar", "from": (-r / 2, 0.0), "to": "A"},
        )
        m.add_body(
            "rod", SC.m_rod, SC.J_rod, position=(r + L / 2, 0.0), points={"A": (-L / 2, 0.0)}
        )
        rod_b = (L / 2, 0.0)
    m.add_body("slider", SC.m_slider, slider_inertia, position=(r + L, 0.0))
    m.add_revolute("ground_crank", "ground", "crank", point_i=(0.0, 0.0), point_j="O")
    m.add_revolute("crank_rod", "crank", "rod", point_i="A", point_j="A")
    m.add_revolute("rod_slider", "rod", "slider", point_i=rod_b, point_j=(0.0, 0.0))
    m.add_prismatic("slider_guide", "ground", "slider", axis=(1, 0), point_i=(0, 0), point_j=(0, 0))
    if driven:
        m.add_driver("motor", "ground_crank", jointgap.profiles.linear_ramp(OMEGA, RAMP))
    return m


# --- body frames apart from the centre of mass -----------------------------------------


def test_a_body_in_its_own_frame_is_the_same_mechanism(engine) -> None:
    own, centre = slider_crank("own"), slider_crank("centre")
    engine_own, engine_centre = own.to_dict(), centre.to_dict()
    assert engine_own["bodies"] == engine_centre["bodies"]
    assert engine_own["joints"] == engine_centre["joints"]
    assert own.bodies["crank"]["com"] == [SC.r / 2, 0.0]  # the user's frame is kept
    a = simulate_ok(own, 0.3, rate=1000, rtol=1e-10, atol=1e-12)
    b = simulate_ok(centre, 0.3, rate=1000, rtol=1e-10, atol=1e-12)
    assert a.channels == b.channels
    for channel in a.channels:
        assert np.array_equal(a[channel], b[channel]), channel


def test_a_frame_origin_moves_to_the_centre_of_mass_with_its_velocity(engine) -> None:
    """r_cm = r + R c and v_cm = v + omega k x (R c), for a frame turned by 30 deg."""
    c = (0.3, 0.1)
    phi, w = math.radians(30), 2.0
    m = jointgap.Model(gravity=(0, 0)).add_body(
        "bar",
        1.0,
        0.1,
        com=c,
        position=(1.0, 2.0),
        angle="30 deg",
        velocity=(0.5, -0.25),
        omega=w,
        points={"P": (0.0, 0.0)},
    )
    m.add_force("push", "bar", (1.0, 0.0), point="P")
    body = m.to_dict()["bodies"][0]
    rc = (math.cos(phi) * c[0] - math.sin(phi) * c[1], math.sin(phi) * c[0] + math.cos(phi) * c[1])
    assert body["position"] == pytest.approx([1.0 + rc[0], 2.0 + rc[1]], rel=1e-15)
    assert body["velocity"] == pytest.approx([0.5 - w * rc[1], -0.25 + w * rc[0]], rel=1e-15)
    assert body["points"] == {"P": [-0.3, -0.1]}
    assert "com" not in body
    # A free body: its centre of mass moves at the converted velocity, and the frame's
    # origin (point P) at v + omega k x r_P as rigid-body kinematics says.
    r = simulate_ok(m, 0.01, rate=1000)
    assert r["bar.vx"][0] == pytest.approx(0.5 - w * rc[1], rel=1e-12)
    assert r["bar.vy"][0] == pytest.approx(-0.25 + w * rc[0], rel=1e-12)


# --- initial conditions by joint coordinates --------------------------------------------


def passive(**ground_crank) -> jointgap.Model:
    """The slider-crank in a horizontal plane, no motor; keyword arguments go to the crank's
    pivot joint (``initial``, ``initial_rate``)."""
    sc = SliderCrank(gravity=(0.0, 0.0))
    r, L = sc.r, sc.L
    m = jointgap.Model(name="passive", gravity=(0, 0))
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
    m.add_body("slider", sc.m_slider, 0.004, position=(r + L, 0.0))
    m.add_revolute("ground_crank", "ground", "crank", (0.0, 0.0), "O", **ground_crank)
    m.add_revolute("crank_rod", "crank", "rod", "A", "A")
    m.add_revolute("rod_slider", "rod", "slider", "B", (0.0, 0.0))
    m.add_prismatic("guide", "ground", "slider", (1, 0), (0, 0), (0, 0))
    return m


def test_a_slider_crank_starts_at_the_given_crank_angle_and_rate(engine) -> None:
    """Crank at 60 deg turning at -1 rad/s, given on its joint: the slider starts where
    the closed form puts it, and, with no load in a horizontal plane, the kinetic energy
    m(th) th'^2 / 2 keeps its initial value, so th'(th) is known everywhere."""
    sc = SliderCrank(gravity=(0.0, 0.0))
    th0, w0 = math.radians(60), -1.0
    m = passive(initial="60 deg", initial_rate="-1 rad/s")
    r = simulate_ok(m, 0.5, rate=1000, rtol=1e-10, atol=1e-12)
    assert r.warnings == []
    assert r["crank.angle"][0] == pytest.approx(th0, abs=1e-12)
    assert r["crank.omega"][0] == pytest.approx(w0, rel=1e-12)
    x0, vx0, _ = sc.slider_motion(th0, w0, 0.0)
    assert r["slider.x"][0] == pytest.approx(x0, abs=1e-12)
    assert r["slider.vx"][0] == pytest.approx(vx0, rel=1e-10)
    th = r["crank.angle"]
    assert th[-1] < th0 - 0.3  # it turned clockwise
    m0, _ = sc.generalized_mass(th0)
    m_th, _ = sc.generalized_mass(th)
    expected_rate = -np.sqrt(m0 * w0**2 / m_th)
    assert np.max(np.abs(r["crank.omega"] - expected_rate)) < 1e-7
    x, _, _ = sc.slider_x(th)
    assert np.max(np.abs(r["slider.x"] - x)) < 1e-10


def test_a_slider_travel_fixes_the_crank_angle(engine) -> None:
    """Given the slider's travel instead, assembly finds the crank angle of that slider
    position on the branch of the placement (crank above the line)."""
    sc = SliderCrank(gravity=(0.0, 0.0))
    th0 = math.radians(70)
    x0, _, _ = sc.slider_x(th0)
    m = passive()
    m_dict = m.to_dict()
    guide = {**m.joints["guide"], "initial": x0, "initial_rate": 0.0}
    m_dict["joints"] = [guide if j["name"] == "guide" else j for j in m_dict["joints"]]
    m_dict["bodies"][0]["angle"] = 1.0  # crank roughly up: the branch of the placement
    m_dict["bodies"][0]["position"] = [sc.r / 2 * math.cos(1.0), sc.r / 2 * math.sin(1.0)]
    r = simulate_ok(jointgap.Model.from_dict(m_dict), 0.01, rate=1000)
    assert r["slider.x"][0] == pytest.approx(x0, abs=1e-12)
    assert r["crank.angle"][0] == pytest.approx(th0, abs=1e-9)
    assert r["slider.vx"][0] == pytest.approx(0.0, abs=1e-12)


def test_assembly_warns_when_it_changes_a_given_velocity(engine) -> None:
    """The reproducer: omega = -1 rad/s on the crank alone of a passive slider-crank
    started silently at another speed, since the rod and the slider were given none."""
    m = passive()
    data = m.to_dict()
    data["bodies"][0]["omega"] = -1.0
    m = jointgap.Model.from_dict(data)
    warnings = m.check()
    r = simulate_ok(m, 0.001, rate=1000)
    used = r["crank.omega"][0]
    assert abs(used + 1.0) > 0.01
    expected = (
        f"body 'crank': omega = -1.000000 rad/s was given, {used:.6f} rad/s is used: "
        "assembly changed it to satisfy the joints and drivers; give a joint's initial_rate "
        "to set a velocity that assembly keeps"
    )
    assert warnings == [expected]
    assert r.warnings == [expected]


def test_initial_conditions_that_fight_the_mechanism_are_errors(engine) -> None:
    m = passive(initial="10 deg")
    m.add_driver("motor", "ground_crank", jointgap.profiles.constant_speed(1.0))
    with pytest.raises(jointgap.ModelError) as err:
        m.check()
    assert str(err.value) == (
        "joint 'ground_crank': initial and initial_rate cannot be given for a driven joint "
        "(driver 'motor' sets its motion): give its coordinate at t = 0 as the driver's initial"
    )
    m = passive(initial="60 deg")
    data = m.to_dict()
    data["joints"][1]["initial"] = 0.5  # crank_rod: already fixed by the crank angle
    with pytest.raises(jointgap.ModelError, match=r"already fix this joint's coordinate"):
        jointgap.Model.from_dict(data).check()


# --- point masses ----------------------------------------------------------------------


def test_a_zero_inertia_slider_moves_as_any_slider(engine) -> None:
    """The prismatic joint fixes the slider's rotation, so its inertia multiplies a zero
    angular acceleration: 0, 0.004 and 1 kg m^2 give the same motion and motor torque,
    and the closed forms (which have no slider inertia) hold."""
    runs = {
        j: simulate_ok(slider_crank(slider_inertia=j), 0.5, rate=2000, rtol=1e-10, atol=1e-12)
        for j in (0.0, 0.004, 1.0)
    }
    zero = runs[0.0]
    for j in (0.004, 1.0):
        for channel in ("slider.x", "slider.ax", "crank.omega", "motor.torque", "rod.angle"):
            scale = np.max(np.abs(zero[channel]))
            assert np.max(np.abs(runs[j][channel] - zero[channel])) < 1e-7 * scale, (j, channel)
    t = zero.time

    def crank(tt, side):
        return linear_ramp(tt, OMEGA, RAMP, side=side)

    def torque(tt, side):
        return SC.motor_torque(*crank(tt, side))

    def slider_x(tt, side):
        return SC.slider_motion(*crank(tt, side))[0]

    assert np.max(error_at_corners(t, zero["slider.x"], slider_x, (0.0, RAMP))) < 1e-7
    peak = np.max(np.abs(zero["motor.torque"]))
    err = np.max(error_at_corners(t, zero["motor.torque"], torque, (0.0, RAMP)))
    assert err < 1e-6 * peak
    assert np.max(np.abs(zero["slider.angle"])) < 1e-12


def test_a_point_mass_that_can_turn_is_an_error_naming_its_rotation(engine) -> None:
    m = jointgap.Model().add_body("bob", 1.0, 0.0, position=(0.0, -1.0), points={"top": (0, 1)})
    m.add_revolute("pin", "ground", "bob", (0, 0), "top")
    with pytest.raises(jointgap.ModelError) as err:
        m.check()
    assert str(err.value) == (
        "body 'bob': inertia = 0 (a point mass) needs its rotation fixed by its joints, but "
        "its rotation is free: no prismatic or fixed joint ties it to the ground or to a "
        "body that cannot turn (its joints: 'pin' revolute); give its moment of inertia"
    )
