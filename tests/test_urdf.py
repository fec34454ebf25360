"""Robots from URDF (jointgap.urdf): the loaded model against forward kinematics and rigid-
body mass properties computed here with homogeneous transforms written independently of
the loader (URDF rpy as Rz(yaw) Ry(pitch) Rx(roll), the fixed-axis convention), energy
conservation of a double pendulum read from URDF, the overlay, and errors."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from jointgap import ModelError
from jointgap._engine import run_options, simulate
from jointgap.results import Result
from jointgap.urdf import engine_model, load_robot, load_urdf, read_urdf

# A double pendulum with turned frames everywhere: a tilted shoulder, an elbow origin and
# an inertial frame with all three rpy angles, an off-diagonal inertia tensor, a carriage
# on a prismatic joint and a massless tool frame on a fixed joint (merged into its parent).
SHOULDER = ([0.1, -0.05, 1.0], [0.2, -0.1, 0.3])
ELBOW = ([0.5, 0.02, 0.0], [0.0, 0.25, -0.4])
LOWER_INERTIAL = ([0.2, 0.01, -0.02], [0.3, 0.2, 0.1])
LOWER_MASS = 1.0
LOWER_INERTIA = np.array([[0.0012, 0.0005, 0.0002], [0.0005, 0.014, 0.0], [0.0002, 0.0, 0.0135]])
UPPER_INERTIAL = ([0.25, 0.0, 0.0], [0.0, 0.0, 0.0])
UPPER_MASS = 2.0
UPPER_INERTIA = np.diag([0.001, 0.0425, 0.0425])
TOOL = ([0.4, 0.0, 0.03], [0.0, 0.0, 0.0])
AXIS_SHOULDER = [0.0, 1.0, 0.0]
AXIS_ELBOW = [0.0, 0.6, 0.8]
# A carriage sliding on the upper link.
SLIDE = ([0.3, 0.0, 0.05], [0.1, 0.0, 0.5])
AXIS_SLIDE = [0.6, 0.0, 0.8]
CARRIAGE_INERTIAL = ([0.0, 0.02, 0.0], [0.0, 0.0, 0.3])
CARRIAGE_MASS = 0.5
CARRIAGE_INERTIA = np.diag([2e-4, 3e-4, 4e-4])


def _origin(xyz_rpy: tuple[list[float], list[float]]) -> str:
    xyz, rpy = xyz_rpy
    return f'<origin xyz="{" ".join(map(str, xyz))}" rpy="{" ".join(map(str, rpy))}"/>'


def _inertia(tensor: np.ndarray) -> str:
    t = tensor
    return (
        f'<inertia ixx="{t[0, 0]}" ixy="{t[0, 1]}" ixz="{t[0, 2]}" '
        f'iyy="{t[1, 1]}" iyz="{t[1, 2]}" izz="{t[2, 2]}"/>'
    )


URDF = f"""<?xml version="1.0"?>
<robot name="double_pendulum">
  <link name="base"/>
  <link name="upper">
    <inertial>{_origin(UPPER_INERTIAL)}<mass value="{UPPER_MASS}"/>
      {_inertia(UPPER_INERTIA)}</inertial>
  </link>
  <link name="lower">
    <inertial>{_origin(LOWER_INERTIAL)}<mass value="{LOWER_MASS}"/>
      {_inertia(LOWER_INERTIA)}</inertial>
  </link>
  <link name="tool"/>
  <link name="carriage">
    <inertial>{_origin(CARRIAGE_INERTIAL)}<mass value="{CARRIAGE_MASS}"/>
      {_inertia(CARRIAGE_INERTIA)}</inertial>
  </link>
  <joint name="shoulder" type="continuous">
    <parent link="base"/><child link="upper"/>{_origin(SHOULDER)}
    <axis xyz="{" ".join(map(str, AXIS_SHOULDER))}"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="lower"/>{_origin(ELBOW)}
    <axis xyz="{" ".join(map(str, AXIS_ELBOW))}"/>
    <limit lower="-2.0" upper="2.5" effort="50" velocity="3"/>
  </joint>
  <joint name="tip" type="fixed">
    <parent link="lower"/><child link="tool"/>{_origin(TOOL)}
  </joint>
  <joint name="slide" type="prismatic">
    <parent link="upper"/><child link="carriage"/>{_origin(SLIDE)}
    <axis xyz="{" ".join(map(str, AXIS_SLIDE))}"/>
    <limit lower="-0.1" upper="0.1" effort="20" velocity="0.5"/>
  </joint>
</robot>
"""

# Points of the lower link (its frame) followed as markers: three independent directions
# fix its orientation as well as its position.
LOWER_POINTS = {"l0": [0.0, 0.0, 0.0], "lx": [0.1, 0.0, 0.0], "ly": [0.0, 0.1, 0.0]}
CARRIAGE_POINTS = {"c0": [0.0, 0.0, 0.0], "cx": [0.1, 0.0, 0.0], "cy": [0.0, 0.1, 0.0]}


# -- Forward kinematics, written here from the URDF conventions --------------------------


def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _transform(xyz_rpy: tuple[list[float], list[float]]) -> np.ndarray:
    """URDF <origin>: translation xyz, rotation Rz(yaw) Ry(pitch) Rx(roll) (fixed axes)."""
    xyz, (roll, pitch, yaw) = xyz_rpy
    t = np.eye(4)
    t[:3, :3] = _rz(yaw) @ _ry(pitch) @ _rx(roll)
    t[:3, 3] = xyz
    return t


def _turn(axis: list[float], angle: float) -> np.ndarray:
    """Rodrigues: a turn by angle about a unit axis, as a 4x4 transform."""
    k = np.asarray(axis) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    t = np.eye(4)
    t[:3, :3] = np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx
    return t


def _slide(axis: list[float], travel: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = travel * np.asarray(axis) / np.linalg.norm(axis)
    return t


def _forward(q_shoulder: float, q_elbow: float, q_slide: float) -> dict[str, np.ndarray]:
    """Link frames in the ground: T = origin * turn(axis, q) (or slide) down the tree."""
    upper = _transform(SHOULDER) @ _turn(AXIS_SHOULDER, q_shoulder)
    lower = upper @ _transform(ELBOW) @ _turn(AXIS_ELBOW, q_elbow)
    carriage = upper @ _transform(SLIDE) @ _slide(AXIS_SLIDE, q_slide)
    return {"upper": upper, "lower": lower, "tool": lower @ _transform(TOOL), "carriage": carriage}


def _at(frame: np.ndarray, point: list[float]) -> np.ndarray:
    return (frame @ np.append(point, 1.0))[:3]


# -- Helpers -----------------------------------------------------------------------------


@pytest.fixture
def urdf(tmp_path: Path) -> Path:
    path = tmp_path / "pendulum.urdf"
    path.write_text(URDF)
    return path


def _markers() -> dict[str, Any]:
    lower = {name: {"link": "lower", "point": p} for name, p in LOWER_POINTS.items()}
    carriage = {name: {"link": "carriage", "point": p} for name, p in CARRIAGE_POINTS.items()}
    return {"tip": {"link": "tool"}, **lower, **carriage}


def _run(model: dict[str, Any], t_end: float, **options: Any) -> Result:
    result = simulate(engine_model(model), run_options(t_end, **options))
    assert result.status == "finished", result.message
    return result


def _set(model: dict[str, Any], joint: str, **values: float) -> None:
    next(j for j in model["joint"] if j["name"] == joint).update(values)


# -- Tests -------------------------------------------------------------------------------


def test_reads_links_joints_and_limits(urdf: Path) -> None:
    robot = read_urdf(urdf)
    assert robot.root == "base"
    assert list(robot.joints) == ["shoulder", "elbow", "slide", "tip"]
    assert robot.joints["elbow"].limits == {
        "lower": -2.0,
        "upper": 2.5,
        "effort": 50.0,
        "velocity": 3.0,
    }
    assert robot.joints["shoulder"].type == "continuous"
    np.testing.assert_allclose(robot.joints["elbow"].axis, AXIS_ELBOW, atol=1e-15)
    model = load_urdf(urdf)
    assert model["model"]["dimension"] == 3
    assert [b["name"] for b in model["body"]] == ["upper", "lower", "carriage"]  # tool merged
    assert [(j["name"], j["type"]) for j in model["joint"]] == [
        ("shoulder", "revolute"),
        ("elbow", "revolute"),
        ("slide", "prismatic"),
    ]


@pytest.mark.parametrize("q", [(0.0, 0.0, 0.0), (0.7, -1.1, 0.06)])
def test_kinematics_match_forward_kinematics(urdf: Path, q: tuple[float, float, float]) -> None:
    """Marker positions at t = 0 (the assembled configuration with the joints turned by
    q from the URDF zero configuration) against the chain of transforms composed here.
    The engine measures a joint's angle from its own reference directions, so the zero
    configuration's angles come from a first run placed there."""
    model = load_urdf(urdf, {"gravity": [0, 0, 0], "marker": _markers()})
    zero = _run(model, 1e-3, rate=1000)
    _set(model, "shoulder", initial=zero["shoulder.angle"][0] + q[0])
    _set(model, "elbow", initial=zero["elbow.angle"][0] + q[1])
    _set(model, "slide", initial=zero["slide.travel"][0] + q[2])
    result = _run(model, 1e-3, rate=1000)
    frames = _forward(*q)
    expected = {"tip": _at(frames["tool"], [0, 0, 0])}
    expected |= {name: _at(frames["lower"], p) for name, p in LOWER_POINTS.items()}
    expected |= {name: _at(frames["carriage"], p) for name, p in CARRIAGE_POINTS.items()}
    for name, point in expected.items():
        got = [result[f"{name}.{c}"][0] for c in "xyz"]
        np.testing.assert_allclose(got, point, atol=1e-9, err_msg=name)
    # The centre of mass of each body at its link's inertial origin.
    for body, inertial in (
        ("upper", UPPER_INERTIAL),
        ("lower", LOWER_INERTIAL),
        ("carriage", CARRIAGE_INERTIAL),
    ):
        got = [result[f"{body}.{c}"][0] for c in "xyz"]
        np.testing.assert_allclose(
            got, frames[body][:3, 3] + frames[body][:3, :3] @ inertial[0], atol=1e-9
        )


def test_mass_and_inertia_rotated_into_the_ground(urdf: Path) -> None:
    """Kinetic energy of a spinning pendulum, 1/2 w^2 a.J_O.a, with J_O the ground-frame
    inertia about the pivot of both links (each tensor turned by R J R^T of its inertial
    frame, moved by the parallel-axis theorem), against the engine's at t = 0."""
    model = load_urdf(urdf, {"gravity": [0, 0, 0]})
    rate = 2.5
    _set(model, "shoulder", initial_rate=rate)
    _set(model, "elbow", initial_rate=0.0)
    _set(model, "slide", initial_rate=0.0)
    result = _run(model, 1e-3, rate=1000)
    frames = _forward(0.0, 0.0, 0.0)
    pivot = frames["upper"][:3, 3]
    axis = frames["upper"][:3, :3] @ np.asarray(AXIS_SHOULDER)
    j_pivot = np.zeros((3, 3))
    for body, inertial, mass, tensor in (
        ("upper", UPPER_INERTIAL, UPPER_MASS, UPPER_INERTIA),
        ("lower", LOWER_INERTIAL, LOWER_MASS, LOWER_INERTIA),
        ("carriage", CARRIAGE_INERTIAL, CARRIAGE_MASS, CARRIAGE_INERTIA),
    ):
        frame = frames[body] @ _transform(inertial)
        r = frame[:3, 3] - pivot
        j_pivot += frame[:3, :3] @ tensor @ frame[:3, :3].T
        j_pivot += mass * (r @ r * np.eye(3) - np.outer(r, r))
    expected = 0.5 * rate**2 * axis @ j_pivot @ axis
    assert result["system.kinetic_energy"][0] == pytest.approx(expected, rel=1e-9)
    bodies = {b["name"]: b for b in load_urdf(urdf)["body"]}
    assert bodies["lower"]["mass"] == LOWER_MASS
    np.testing.assert_array_equal(bodies["lower"]["inertia"], LOWER_INERTIA)


def test_double_pendulum_conserves_energy(urdf: Path) -> None:
    """Released from rest with ideal joints and gravity: kinetic plus potential energy
    stays at its initial value while the links swing through a large motion."""
    model = load_urdf(urdf, {"gravity": [0, 0, "-9.81 m/s^2"]})
    result = _run(model, 1.5, rate=200, rtol=1e-10, atol=1e-12)
    kinetic = np.asarray(result["system.kinetic_energy"])
    energy = kinetic + np.asarray(result["system.potential_energy"])
    assert kinetic.max() > 5.0  # it swings: several joules exchanged
    assert np.max(np.abs(energy - energy[0])) < 1e-6 * kinetic.max()


def test_overlay_gives_clearance_drive_and_driver(urdf: Path) -> None:
    overlay = {
        "joint": {
            "elbow": {
                "type": "clearance_cylindrical",
                **CONTACT,
                "drive": {
                    "stiffness": "1e4 N*m/rad",
                    "damping": "5 N*m*s/rad",
                    "arm": "40 mm",
                    "mass": "0.1 kg",
                },
            }
        },
        "driver": {
            "elbow": {
                "profile": {"type": "table_angle", "time": [0, 1], "value": ["0 deg", "10 deg"]}
            },
            "shoulder": {
                "profile": {"type": "smooth_ramp", "speed": "30 deg/s", "ramp_time": "0.5 s"}
            },
        },
    }
    model = load_urdf(urdf, overlay)
    elbow = next(j for j in model["joint"] if j["name"] == "elbow")
    assert elbow["type"] == "clearance_cylindrical"
    assert elbow["bearing_radius"] == pytest.approx(0.01)
    assert elbow["length"] == pytest.approx(0.02)
    drivers = {d["name"]: d for d in model["driver"]}
    assert drivers["elbow_motor"]["joint"] == "elbow_drive"
    assert drivers["elbow_motor"]["profile"]["value"] == pytest.approx([0, math.radians(10)])
    (mesh,) = model["force"]
    # Torsional stiffness 1e4 N m/rad at a 40 mm arm: k = 1e4 / 0.04^2 N/m.
    assert mesh["stiffness"] == pytest.approx(1e4 / 0.04**2)
    engine = engine_model(model)
    assert engine["joints"][1]["clearance"]["clearance"] == pytest.approx(1e-4)


CONTACT = {
    "bearing_radius": "10 mm",
    "clearance": "0.1 mm",
    "length": "20 mm",
    "bearing_material": "steel",
    "journal_material": "steel",
    "normal_law": {"type": "lankarani_nikravesh", "restitution": 0.8},
}


@pytest.mark.parametrize(
    ("text", "overlay", "message"),
    [
        (
            URDF.replace('type="continuous"', 'type="floating"'),
            None,
            "joint 'shoulder': type 'floating'",
        ),
        (
            URDF.replace('type="continuous"', 'type="planar"'),
            None,
            "joint 'shoulder': type 'planar'",
        ),
        (
            URDF.replace('<axis xyz="0.0 0.6 0.8"/>', '<axis xyz="0 0 0"/>'),
            None,
            "joint 'elbow': axis",
        ),
        (
            URDF.replace('type="fixed"', 'type="revolute"'),
            None,
            "link 'tool': has no mass",
        ),
        (
            URDF,
            {"joint": {"wrist": {"type": "clearance_cylindrical"}}},
            "no joint 'wrist' in the URDF",
        ),
        (URDF, {"driver": {"knee": {"profile": {}}}}, "joint 'knee'"),
        (URDF, {"joint": {"tip": {"type": "clearance_spherical"}}}, "the joint is fixed"),
        (URDF, {"joint": {"elbow": {"type": "revolute"}}}, "joint 'elbow': overlay type"),
        (URDF, {"marker": {"m": {"link": "hand"}}}, "marker 'm': link = 'hand'"),
        (URDF, {"grav": [0, 0, 0]}, "unknown table(s) grav"),
        (
            URDF,
            {
                "joint": {"elbow": {"type": "clearance_cylindrical", **CONTACT}},
                "driver": {"elbow": {"profile": {"type": "constant_speed", "speed": 1.0}}},
            },
            "joint 'elbow': has clearance and a driver",
        ),
    ],
)
def test_bad_input_is_named(tmp_path: Path, text: str, overlay: Any, message: str) -> None:
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    with pytest.raises(ModelError, match=message.replace("(", r"\(").replace(")", r"\)")):
        load_urdf(path, overlay)


def test_overlay_errors_name_the_line(urdf: Path, tmp_path: Path) -> None:
    overlay = tmp_path / "over.toml"
    overlay.write_text('gravity = [0, 0, "-9.81 m/s^2"]\n\n[joint.elbow]\ntype = "gap"\n')
    with pytest.raises(ModelError, match=r"over.toml:3: joint 'elbow': overlay type = 'gap'"):
        load_urdf(urdf, overlay)
    overlay.write_text('[driver.wrist.profile]\ntype = "constant_speed"\nspeed = 1.0\n')
    with pytest.raises(ModelError, match=r"over.toml:1: joint 'wrist': overlay \[driver.wrist\]"):
        load_urdf(urdf, overlay)


def test_missing_files_are_named(tmp_path: Path, urdf: Path) -> None:
    with pytest.raises(ModelError, match="nothere.urdf: no such URDF file"):
        load_urdf(tmp_path / "nothere.urdf")
    with pytest.raises(ModelError, match="over.toml: no such overlay file"):
        load_urdf(urdf, tmp_path / "over.toml")


def test_arm_example_runs_with_elbow_clearance(examples: Path, tmp_path: Path) -> None:
    """The example arm with clearance in its elbow against the same move with ideal
    joints, over its first 0.1 s: both start on the zero configuration's tool point
    (shoulder axis to tool 0.45 + 0.40 + 0.09 + 0.10 m along x, 0.12 - 0.10 + 0.09 m
    across, 0.15 m up), the journal settles in its bearing with impacts, and the tool
    point leaves the ideal path by more than the radial clearance (the forearm tilts in
    the bearing and its drive train winds up under the load)."""
    from jointgap.robot_path import path_deviation, plot_path_deviation

    result = path_deviation(
        examples / "arm" / "arm.urdf", examples / "arm" / "arm_clearance.toml", "tool", 0.1
    )
    np.testing.assert_allclose(result.ideal[:, 0], [1.04, 0.11, 0.15], atol=1e-9)
    assert result.deviation[0] < 1e-9
    peak, _ = result.largest
    assert 0.05e-3 < peak < 0.02
    assert sum(len(v) for v in result.runs[1].impacts.values()) > 0
    assert plot_path_deviation(result, tmp_path / "figures").is_file()


def test_an_overlay_that_names_its_urdf_is_a_model(examples: Path, tmp_path: Path) -> None:
    model = load_robot(examples / "arm" / "arm_clearance.toml")
    assert model == load_urdf(
        examples / "arm" / "arm.urdf", examples / "arm" / "arm_clearance.toml"
    )
    assert len([b for b in model["body"] if b["name"] != "elbow_rotor"]) == 6
    lost = tmp_path / "lost.toml"
    lost.write_text('gravity = [0, 0, "-9.81 m/s^2"]')
    with pytest.raises(ModelError, match="lost.toml: urdf = None: the overlay must name"):
        load_robot(lost)


ONE_LINK = """<robot name="one_link">
  <link name="base"/>
  <link name="arm">
    <inertial><origin xyz="0.25 0 0" rpy="0 0 0"/><mass value="2.0"/>
      <inertia ixx="0.0005" ixy="0" ixz="0" iyy="0.041667" iyz="0" izz="0.041667"/></inertial>
  </link>
  <link name="tip"/>
  <joint name="pivot" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="end" type="fixed"><parent link="arm"/><child link="tip"/>
    <origin xyz="0.5 0 0" rpy="0 0 0"/></joint>
</robot>
"""


def test_drive_train_has_the_torsional_stiffness_it_is_given(tmp_path: Path) -> None:
    """A 0.5 m link on a pivot with clearance, its rotor started at constant speed w
    without gravity or damping: the link lags the rotor by phi(t) = (w / W) sin(W t),
    W = sqrt(K_t / J_O) (J_O = J_G + m d^2 about the pivot), as long as the clearance is
    small against the link; a spring set as K_t instead of K_t / arm^2 would be off by a
    factor arm^2 = 0.25 in W^2."""
    path = tmp_path / "one_link.urdf"
    path.write_text(ONE_LINK)
    k_t, speed, j_o = 100.0, 0.5, 0.041667 + 2.0 * 0.25**2
    overlay = {
        "gravity": [0, 0, 0],
        "joint": {
            "pivot": {
                **CONTACT,
                "type": "clearance_cylindrical",
                "clearance": "0.01 mm",
                "drive": {"stiffness": k_t, "damping": 0.0, "arm": "0.5 m", "mass": 0.1},
            }
        },
        "driver": {"pivot": {"profile": {"type": "constant_speed", "speed": speed}}},
        "marker": {"tip": {"link": "tip"}},
    }
    result = _run(load_urdf(path, overlay), 0.2, rate=2000)
    t = np.asarray(result.time)
    lag = speed * t - np.unwrap(np.arctan2(result["tip.y"], result["tip.x"]))
    omega = math.sqrt(k_t / j_o)
    assert np.max(np.abs(lag - speed / omega * np.sin(omega * t))) < 0.02 * speed / omega
