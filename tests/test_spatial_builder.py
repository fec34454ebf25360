"""The builder's spatial models (``jointgap.Model(name, dimension=3)``): the same engine
model as the files, errors naming the element and the key, and a free fall under the
engine's default gravity against its closed form."""

from __future__ import annotations

import math
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap import ModelError, laws, profiles

ROOT = Path(__file__).resolve().parent.parent


def founding_3d() -> jointgap.Model:
    """examples/slider_crank_clearance_3d.toml, built in Python."""
    return (
        jointgap.Model("slider_crank_clearance_3d", gravity=(0, "-9.81 m/s^2", 0), dimension=3)
        .add_ground_point("O", (0, 0, 0))
        .add_body(
            "crank",
            mass="2.37 kg",
            inertia=("1e-4 kg*m^2", "0.01201 kg*m^2", "0.01201 kg*m^2"),
            position=("0.04 m", 0, 0),
            points={"O": ("-0.04 m", 0, 0), "A": ("0.04 m", 0, 0)},
        )
        .add_body(
            "rod",
            mass="0.72 kg",
            inertia=("1e-5 kg*m^2", "0.0006926 kg*m^2", "0.0006926 kg*m^2"),
            position=("0.24 m", 0, 0),
            points={"A": ("-0.16 m", 0, 0), "B": ("0.16 m", 0, 0)},
        )
        .add_body(
            "slider",
            mass="2.28 kg",
            inertia=("0.00095 kg*m^2",) * 3,
            position=("0.40 m", 0, 0),
            points={"B": (0, 0, 0)},
        )
        .add_revolute("ground_crank", "ground", "crank", "O", "O", axis=(0, 0, 1))
        .add_revolute("crank_rod", "crank", "rod", "A", "A", axis=(0, 0, 1))
        .add_clearance_cylindrical(
            "rod_slider",
            "slider",
            "rod",
            (0, 0, 1),
            "B",
            "B",
            length="20 mm",
            bearing_radius="7.5 mm",
            clearance="0.5 mm",
            bearing_material={"youngs_modulus": "97 GPa", "poisson_ratio": 0.3},
            journal_material={"youngs_modulus": "207 GPa", "poisson_ratio": 0.3},
            normal_law=laws.adams_impact("27960 N*s/m", "1e-5 m"),
            friction=laws.coulomb(0.08, 0.05, "0.0001 m/s", "0.01016 m/s"),
        )
        .add_prismatic("slider_guide", "ground", "slider", (1, 0, 0), "O", "B")
        .add_driver("motor", "ground_crank", profiles.linear_ramp("300 rpm", "0.2 s"))
    )


def four_bar_clearance() -> jointgap.Model:
    """examples/spatial_four_bar_clearance.toml, built in Python."""
    return (
        jointgap.Model("spatial_four_bar_clearance", (0, 0, "-9.81 m/s^2"), dimension=3)
        .add_ground_point("O", (0, 0, 0))
        .add_ground_point("D", ("0.2 m", 0, "0.2 m"))
        .add_body(
            "crank",
            "0.157 kg",
            ("6.5e-6 kg*m^2", "1.32e-4 kg*m^2", "1.36e-4 kg*m^2"),
            position=("0.05 m", 0, 0),
            points={"O": ("-0.05 m", 0, 0), "A": ("0.05 m", 0, 0)},
        )
        .add_body(
            "coupler",
            "0.628 kg",
            ("2.6e-5 kg*m^2", "8.37e-3 kg*m^2", "8.39e-3 kg*m^2"),
            inertia_frame={"axis": (0, -0.625, 0.739510), "angle": "75.5225 deg"},
            position=("0.15 m", "0.147902 m", "0.125 m"),
            points={
                "A": ("-0.05 m", "-0.147902 m", "-0.125 m"),
                "B": ("0.05 m", "0.147902 m", "0.125 m"),
            },
        )
        .add_body(
            "rocker",
            "0.471 kg",
            ("2.0e-5 kg*m^2", "3.53e-3 kg*m^2", "3.55e-3 kg*m^2"),
            position=("0.2 m", "0.147902 m", "0.225 m"),
            orientation={"euler": ("9.594068 deg", 0, "90 deg"), "convention": "XYZ"},
            points={"D": ("-0.15 m", 0, 0), "B": ("0.15 m", 0, 0)},
        )
        .add_revolute("ground_crank", "ground", "crank", "O", "O", axis=(0, 0, 1))
        .add_spherical("crank_coupler", "crank", "coupler", "A", "A")
        .add_clearance_spherical(
            "coupler_rocker",
            "rocker",
            "coupler",
            "B",
            "B",
            socket_radius="10 mm",
            clearance="0.1 mm",
            socket_material="steel",
            ball_material="steel",
            normal_law=laws.lankarani_nikravesh(0.9),
            friction=laws.coulomb(0.1, 0.08, "0.1 mm/s", "10 mm/s"),
        )
        .add_revolute("ground_rocker", "ground", "rocker", "D", "D", axis=(1, 0, 0))
        .add_driver("motor", "ground_crank", profiles.constant_speed("60 rpm"))
        .add_marker("coupler_mid", "coupler", (0, 0, 0))
    )


@pytest.mark.parametrize(
    ("build", "name"),
    [
        (founding_3d, "slider_crank_clearance_3d"),
        (four_bar_clearance, "spatial_four_bar_clearance"),
    ],
)
def test_the_builder_and_the_file_give_the_same_engine_model(build, name: str) -> None:
    built = build()
    loaded = jointgap.load(ROOT / "examples" / f"{name}.toml")
    assert built.to_dict() == loaded.to_dict()
    assert built.to_json() == loaded.to_json()


def test_degrees_of_freedom_and_the_read_access(engine: None) -> None:
    model = four_bar_clearance()
    assert model.spatial and model.dimension == 3
    # 3 bodies x 6 - revolute 5 - spherical 3 - revolute 5 (the clearance joint adds none)
    assert model.degrees_of_freedom() == 5
    assert model.degrees_of_freedom(with_drivers=True) == 4
    assert model.joint_equations() == 13
    assert model.gravity == (0.0, 0.0, -9.81)
    assert model.ground_points["D"] == (0.2, 0.0, 0.2)
    assert "(spatial)" in repr(model)
    assert model.check() == []


def test_every_spatial_joint_and_load_builds(engine: None) -> None:
    model = (
        jointgap.Model("kit", dimension=3)
        .add_body("a", 1, (1, 1, 1), position=(0, 0, 1), points={"P": (0, 0, -1)})
        .add_body("b", 1, (1, 1, 1), position=(0, 0, 2))
        .add_body("c", 1, (1, 1, 1), position=(0, 0, 3))
        .add_body("d", 1, (1, 1, 1), position=(0, 0, 4))
        .add_body("e", 1, ((1, 0, 0), (0, 1, 0), (0, 0, 1)), position=(0, 0, 5))
        .add_cylindrical("cyl", "ground", "a", (0, 0, 1), (0, 0, 0), "P")
        .add_universal("hooke", "a", "b", (1, 0, 0), (0, 1, 0), (0, 0, 0.5), (0, 0, -0.5))
        .add_planar("slide", "b", "c", (0, 0, 1), (0, 0, 0.5), (0, 0, -0.5))
        .add_fixed("weld", "c", "d", (0, 0, 0.5), (0, 0, -0.5))
        .add_prismatic("rail", "d", "e", (0, 0, 1), (0, 0, 0.5), (0, 0, -0.5), axis_j=(0, 0, 1))
        .add_spring_damper(
            "spring", "ground", "e", "1 kN/m", "1 N*s/m", "5 m", (0, 0, 0), (0, 0, 0)
        )
        .add_force("push", "e", (0, "1 N", 0), frame="body")
        .add_torque("twist", "e", ((0, 1), [(0, 0, 0), (0, 0, "1 N*m")]))
        .add_driver("spin", "cyl", profiles.constant_speed("10 rpm"))
    )
    types = [j["type"] for j in model.joints.values()]
    assert types == ["cylindrical", "universal", "planar", "fixed", "prismatic"]
    assert model.forces["twist"]["torque"] == {
        "time": [0.0, 1.0],
        "value": [[0.0] * 3, [0, 0, 1.0]],
    }
    assert "frame" not in model.forces["twist"]  # the engine's default: ground
    assert model.forces["push"]["frame"] == "body"
    assert model.bodies["e"]["inertia"] == {"tensor": [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]}
    # 5 x 6 - 4 - 4 - 3 - 6 - 5 = 8, less the driver
    assert model.degrees_of_freedom(with_drivers=True) == 7
    result = model.simulate(0.01, rate=1000)
    assert result.ok, result.message
    assert {"cyl.angle", "cyl.travel", "spin.torque", "rail.travel"} <= set(result.channels)


def test_builder_errors_name_the_element_and_the_key() -> None:
    model = jointgap.Model("m", dimension=3)
    with pytest.raises(ModelError) as info:
        model.add_body("a", 1, (1, 1, 1), angle="10 deg")
    assert info.value.key == "angle" and "unknown key 'angle'" in str(info.value)
    with pytest.raises(ModelError) as info:
        model.add_body("a", 1, (1, 1, 1), position=(0, 0))
    assert info.value.key == "position" and "[x, y, z]" in str(info.value)
    with pytest.raises(ModelError) as info:
        model.add_body("a", 1, (1, 1, 1), orientation={"angle": 1})
    assert info.value.key == "orientation" and info.value.element == "body 'a'"
    with pytest.raises(ModelError) as info:
        model.add_body(
            "a", 1, ((1, 0, 0), (0, 1, 0), (0, 0, 1)), inertia_frame={"quaternion": (1, 0, 0, 0)}
        )
    assert info.value.key == "inertia_frame" and "full tensor" in str(info.value)
    with pytest.raises(ModelError) as info:
        model.add_torque("t", "a", (0, 0, 1), frame="world")
    assert info.value.key == "frame"
    with pytest.raises(ModelError) as info:
        jointgap.Model("planar").add_spherical("s", "ground", "a", (0, 0), (0, 0))
    assert "unknown joint type 'spherical'" in str(info.value)
    with pytest.raises(ModelError) as info:
        jointgap.Model("m", dimension=4)
    assert info.value.key == "dimension"


def test_a_driver_in_angular_units_on_a_prismatic_joint_is_refused() -> None:
    model = (
        jointgap.Model("m", dimension=3)
        .add_body("a", 1, (1, 1, 1))
        .add_prismatic("rail", "ground", "a", (1, 0, 0), (0, 0, 0), (0, 0, 0))
    )
    with pytest.raises(ModelError) as info:
        model.add_driver("motor", "rail", profiles.constant_speed("10 rpm"))
    assert "angular units" in str(info.value) and info.value.key == "profile"


def test_save_from_dict_and_load_give_the_same_model(tmp_path: Path) -> None:
    model = four_bar_clearance()
    model.save(tmp_path / "m.toml")
    assert jointgap.load(tmp_path / "m.toml") == model
    assert jointgap.Model.from_dict(model.to_dict()) == model


def test_a_free_body_falls_under_the_engines_default_gravity(engine: None) -> None:
    """No gravity given: the engine's own, 9.81 m/s^2 along -z. A body thrown sideways
    and spinning about a principal axis follows z = z0 - g t^2 / 2, x = v t, and keeps its
    spin (the closed form, to the integration tolerance)."""
    model = jointgap.Model("fall", dimension=3).add_body(
        "ball",
        "2 kg",
        ("0.01 kg*m^2", "0.02 kg*m^2", "0.03 kg*m^2"),
        position=(0, 0, "1 m"),
        velocity=("3 m/s", 0, 0),
        angular_velocity=(0, 0, "10 rad/s"),
    )
    assert model.gravity is None and "gravity" not in model.to_dict()
    result = model.simulate(0.2, rate=100, rtol=1e-10, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["ball.z"], 1 - 9.81 * t**2 / 2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["ball.x"], 3 * t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["ball.wz"], 10, rtol=1e-9)
    # the spin about z turns the quaternion: e0 = cos(w t / 2), e3 = sin(w t / 2)
    np.testing.assert_allclose(result["ball.e0"], np.cos(5 * t), atol=1e-8)
    np.testing.assert_allclose(result["ball.e3"], np.sin(5 * t), atol=1e-8)
    assert math.isclose(result["ball.az"][-1], -9.81, rel_tol=1e-9)


def test_the_three_orientation_forms_and_the_engine_agree(engine: None) -> None:
    """The Python rotation matrices (used to move a body to its centre of mass) against
    the engine's own reading of the same orientation: the quaternion it reports at
    t = 0 for Euler angles."""
    from jointgap._spatial_frames import rotation_matrix

    euler = {"euler": {"convention": "ZYX", "angles": [0.3, -0.2, 0.5]}}
    model = jointgap.Model("turned", dimension=3).add_body(
        "b", 1, (1, 2, 2.5), orientation={"euler": (0.3, -0.2, 0.5), "convention": "ZYX"}
    )
    result = model.simulate(1e-3, rate=1000)
    e = [float(result[f"b.e{k}"][0]) for k in range(4)]
    turn = rotation_matrix(euler)
    assert turn is not None
    np.testing.assert_allclose(rotation_matrix({"quaternion": e}), turn, atol=1e-12)
    # the same turn as a quaternion and as an axis and angle
    angle = 2 * math.acos(e[0])
    axis = np.array(e[1:]) / math.sin(angle / 2)
    same = rotation_matrix({"axis_angle": {"axis": list(axis), "angle": angle}})
    np.testing.assert_allclose(same, turn, atol=1e-12)
    # intrinsic ZYX: the body's x axis is (cos b cos a, cos b sin a, -sin b)
    a, b = 0.3, -0.2
    np.testing.assert_allclose(
        turn[:, 0], [math.cos(b) * math.cos(a), math.cos(b) * math.sin(a), -math.sin(b)]
    )


def test_a_body_in_its_own_frame_runs_as_in_its_centre_of_mass_frame(engine: None) -> None:
    """An arm described from its pivot (``com`` 0.25 m along its x axis, turned 30 deg
    about z and spinning) is the arm described from its centre of mass."""
    turn = {"axis": (0, 0, 1), "angle": "30 deg"}
    c30, s30 = math.cos(math.pi / 6), math.sin(math.pi / 6)

    def arm(own_frame: bool) -> jointgap.Model:
        model = jointgap.Model("arm", dimension=3).add_ground_point("O", (0, 0, 0))
        if own_frame:
            model.add_body(
                "arm",
                1,
                (1e-4, 0.02, 0.02),
                com=(0.25, 0, 0),
                orientation=turn,
                angular_velocity=(0, 0, 2),
                points={"P": (0, 0, 0)},
            )
            model.add_marker("tip", "arm", (0.5, 0, 0))
        else:
            model.add_body(
                "arm",
                1,
                (1e-4, 0.02, 0.02),
                position=(0.25 * c30, 0.25 * s30, 0),
                velocity=(-0.5 * s30, 0.5 * c30, 0),
                orientation=turn,
                angular_velocity=(0, 0, 2),
                points={"P": (-0.25, 0, 0)},
            )
            model.add_marker("tip", "arm", (0.25, 0, 0))
        return model.add_revolute("pivot", "ground", "arm", "O", "P", axis=(0, 1, 1))

    own, centre = arm(True).to_dict(), arm(False).to_dict()
    body, expected = own["bodies"][0], centre["bodies"][0]
    for key in ("position", "velocity"):
        np.testing.assert_allclose(body[key], expected[key], atol=1e-15)
    assert body["points"] == expected["points"] and "com" not in body
    assert own["markers"] == centre["markers"]
    a, b = arm(True).simulate(0.05, rate=1000), arm(False).simulate(0.05, rate=1000)
    for q in ("tip.x", "tip.y", "tip.z", "arm.wx", "pivot.fz"):
        np.testing.assert_allclose(a[q], b[q], rtol=1e-9, atol=1e-12)


def test_euler_angles_and_angular_velocity_of_a_spinning_ball(engine: None) -> None:
    """A ball (equal principal moments) turned by ZYX angles (0.3, -0.2, 0.5) and spinning
    at 2 rad/s about the global z axis keeps its spin: its yaw grows as 0.3 + 2 t while
    its pitch and roll stay, and its angular velocity is (0, 0, 2) in global axes and
    R^T (0, 0, 2) in its own."""
    model = jointgap.Model("spin", (0, 0, 0), dimension=3).add_body(
        "ball",
        1,
        (0.1, 0.1, 0.1),
        orientation={"euler": (0.3, -0.2, 0.5), "convention": "ZYX"},
        angular_velocity=(0, 0, 2),
    )
    result = model.simulate(0.5, rate=100, rtol=1e-11, atol=1e-13)
    t = result.time
    angles = result.euler_angles("ball", "ZYX")
    np.testing.assert_allclose(np.unwrap(angles[:, 0]), 0.3 + 2 * t, atol=1e-8)
    np.testing.assert_allclose(angles[:, 1], -0.2, atol=1e-8)
    np.testing.assert_allclose(angles[:, 2], 0.5, atol=1e-8)
    ground = result.angular_velocity("ball")
    np.testing.assert_allclose(ground, np.tile([0, 0, 2.0], (len(t), 1)), atol=1e-8)
    from jointgap._spatial_frames import rotation_matrix

    turn = rotation_matrix({"euler": {"convention": "ZYX", "angles": [0.3, -0.2, 0.5]}})
    assert turn is not None
    np.testing.assert_allclose(
        result.angular_velocity("ball", "body")[0], turn.T @ [0, 0, 2], atol=1e-9
    )
    with pytest.raises(ValueError, match="convention"):
        result.euler_angles("ball", "ABC")
