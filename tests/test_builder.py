"""The Python builder: same model as the file, errors at once, runs and results."""

from __future__ import annotations

import json
import math

import jointgap
import numpy as np
import pytest
from jointgap import ModelError, Result, profiles


def slider_crank() -> jointgap.Model:
    """examples/slider_crank_ideal.toml, written with the builder."""
    return (
        jointgap.Model(name="slider_crank_ideal", gravity=("0 m/s^2", "-9.81 m/s^2"))
        .add_ground_point("O", (0, 0))
        .add_body(
            "crank",
            mass="2.37 kg",
            inertia="0.01201 kg*m^2",
            position=("0.04 m", "0 m"),
            angle="0 deg",
            points={"O": ("-0.04 m", "0 m"), "A": ("0.04 m", "0 m")},
            shape={"type": "bar", "from": "O", "to": "A", "width": "20 mm"},
        )
        .add_body(
            "rod",
            mass=0.72,
            inertia=0.0006926,
            position=(0.24, 0),
            points={"A": (-0.16, 0), "B": (0.16, 0)},
            shape={"type": "bar", "from": "A", "to": "B", "width": 0.015},
        )
        .add_body(
            "slider",
            mass="2.28 kg",
            inertia=2.28 * (0.05**2 + 0.05**2) / 12,
            position=(0.40, 0),
            points={"B": (0, 0)},
            shape={"type": "block", "width": "50 mm", "height": "50 mm"},
        )
        .add_revolute("ground_crank", "ground", "crank", point_i="O", point_j="O")
        .add_revolute("crank_rod", "crank", "rod", point_i="A", point_j="A")
        .add_revolute("rod_slider", "slider", "rod", point_i="B", point_j="B")
        .add_prismatic("slider_guide", "ground", "slider", axis=(1, 0), point_i="O", point_j="B")
        .add_driver("motor", "ground_crank", profiles.linear_ramp("300 rpm", "0.2 s"))
    )


def test_builder_and_file_give_the_same_model(examples, engine) -> None:
    from_file = jointgap.load(examples / "slider_crank_ideal.toml")
    built = slider_crank()
    assert built.to_dict() == from_file.to_dict()
    assert built == from_file


def test_to_dict_is_the_engine_schema_in_si() -> None:
    d = slider_crank().to_dict()
    assert list(d) == [
        "name",
        "gravity",
        "bodies",
        "joints",
        "drivers",
        "forces",
        "ground_points",
        "markers",
    ]
    assert d["gravity"] == [0.0, -9.81]
    assert d["bodies"][0] == {
        "name": "crank",
        "mass": 2.37,
        "inertia": 0.01201,
        "position": [0.04, 0.0],
        "angle": 0.0,
        "velocity": [0.0, 0.0],
        "omega": 0.0,
        "points": {"O": [-0.04, 0.0], "A": [0.04, 0.0]},
        "shape": {"type": "bar", "from": "O", "to": "A", "width": 0.02},
    }
    assert d["joints"][3] == {
        "name": "slider_guide",
        "type": "prismatic",
        "body_i": "ground",
        "point_i": "O",
        "body_j": "slider",
        "point_j": "B",
        "axis": [1.0, 0.0],
    }
    assert d["drivers"] == [
        {
            "name": "motor",
            "joint": "ground_crank",
            "profile": {"type": "linear_ramp", "speed": 10 * math.pi, "ramp_time": 0.2},
        }
    ]
    assert json.loads(slider_crank().to_json()) == d


def test_from_dict_and_save_round_trip(tmp_path, engine) -> None:
    model = slider_crank()
    assert jointgap.Model.from_dict(model.to_dict()) == model
    model.save(tmp_path / "m.toml")
    assert jointgap.load(tmp_path / "m.toml") == model


def test_read_access_returns_copies() -> None:
    model = slider_crank()
    assert list(model.bodies) == ["crank", "rod", "slider"]
    assert list(model.joints) == ["ground_crank", "crank_rod", "rod_slider", "slider_guide"]
    assert list(model.drivers) == ["motor"]
    assert model.forces == {}
    model.bodies["rod"]["mass"] = 99.0
    assert model.bodies["rod"]["mass"] == 0.72
    assert repr(model) == "<Model 'slider_crank_ideal': 3 bodies, 4 joints, 1 driver, 0 forces>"


def test_forces_and_tables() -> None:
    model = (
        jointgap.Model("loads", gravity=(0, 0))
        .add_body("a", 1, 0.1)
        .add_body("b", 1, 0.1, position=(1, 0))
        .add_spring_damper(
            "spring",
            "a",
            "b",
            stiffness="1e4 N/m",
            damping="20 N*s/m",
            free_length="0.9 m",
            point_i=(0, 0),
            point_j=(0, 0),
        )
        .add_rotational_spring_damper(
            "torsion", "a", "b", stiffness="5 N*m/rad", free_angle="10 deg"
        )
        .add_force("push", "a", ("1 kN", 0), point=(0.1, 0))
        .add_force("gust", "b", ([0, "1 s"], [(0, 0), (0, "2 N")]))
        .add_torque("twist", "b", ([0, 1], ["0 N*m", "3 N*m"]))
        .add_torque("hold", "a", "-2 N*m")
    )
    forces = model.forces
    assert forces["spring"]["stiffness"] == 1e4 and forces["spring"]["free_length"] == 0.9
    assert forces["torsion"]["free_angle"] == pytest.approx(math.radians(10), rel=1e-15)
    assert forces["torsion"]["damping"] == 0.0
    assert forces["push"]["force"] == [1000.0, 0.0]
    assert forces["push"]["point"] == [0.1, 0.0]
    assert forces["gust"]["force"] == {"time": [0.0, 1.0], "value": [[0.0, 0.0], [0.0, 2.0]]}
    assert forces["twist"]["torque"] == {"time": [0.0, 1.0], "value": [0.0, 3.0]}
    assert forces["hold"]["torque"] == -2.0


# ---------------------------------------------------------------------- errors at once


def test_zero_mass_raises_at_once_naming_the_body() -> None:
    with pytest.raises(ModelError, match=r"^body 'crank': mass must be positive, got 0 kg$"):
        jointgap.Model().add_body("crank", 0, 1)


def test_negative_inertia_raises_at_once() -> None:
    with pytest.raises(ModelError) as err:
        jointgap.Model().add_body("crank", 1, "-2 kg*m^2")
    assert str(err.value) == "body 'crank': inertia must not be negative, got -2 kg*m^2"


def test_wrong_unit_raises_at_once() -> None:
    with pytest.raises(ModelError) as err:
        jointgap.Model().add_body("rod", "0.72 m", 1)
    assert str(err.value) == "body 'rod': mass '0.72 m': expected a mass [kg], got a length [m]"


def test_malformed_number_raises_at_once() -> None:
    with pytest.raises(ModelError) as err:
        jointgap.Model().add_body("rod", 1, 1, position=("0,24 m", 0))
    assert str(err.value) == "body 'rod': position '0,24 m': malformed number"


def test_duplicate_name_raises_at_once() -> None:
    model = jointgap.Model().add_body("crank", 1, 1)
    with pytest.raises(ModelError) as err:
        model.add_revolute("crank", "ground", "crank", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    assert str(err.value) == "joint 'crank': duplicate name 'crank', already used by a body"
    assert list(model.joints) == []  # nothing was added


def test_bad_profile_raises_when_made() -> None:
    with pytest.raises(ModelError) as err:
        profiles.linear_ramp("300 rpm", "0 s")
    assert str(err.value) == "linear_ramp profile: ramp_time must be positive, got 0 s"


def test_unknown_profile_type_in_a_dict() -> None:
    model = (
        jointgap.Model()
        .add_body("a", 1, 1)
        .add_revolute("j", "ground", "a", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    )
    with pytest.raises(ModelError) as err:
        model.add_driver("motor", "j", {"type": "ramp", "speed": 1})
    assert str(err.value).startswith("driver 'motor': unknown profile type 'ramp' (allowed: ")


def test_linear_speed_on_a_revolute_joint() -> None:
    model = (
        jointgap.Model()
        .add_body("a", 1, 1)
        .add_revolute("j", "ground", "a", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    )
    with pytest.raises(ModelError) as err:
        model.add_driver("motor", "j", profiles.constant_speed("2 m/s"))
    assert str(err.value) == (
        "driver 'motor': profile is given in linear units (m) but joint 'j' is revolute: "
        "use angular units (rad, deg, rpm)"
    )


def test_unknown_body_is_found_by_check(engine) -> None:
    model = (
        jointgap.Model()
        .add_body("crank", 1, 1)
        .add_revolute("pin", "ground", "crnak", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    )
    with pytest.raises(ModelError) as err:
        model.check()
    assert str(err.value).startswith("joint 'pin': body_j 'crnak' is not a body")
    assert (err.value.kind, err.value.name, err.value.index, err.value.key) == (
        "joint",
        "pin",
        0,
        "body_j",
    )


def test_unknown_body_is_found_before_a_run(engine) -> None:
    model = (
        jointgap.Model()
        .add_body("crank", 1, 1)
        .add_revolute("pin", "ground", "crnak", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
    )
    with pytest.raises(ModelError, match=r"^joint 'pin': body_j 'crnak' is not a body"):
        model.simulate(0.1)


def test_invalid_option_is_a_value_error(engine) -> None:
    with pytest.raises(ValueError, match=r"^option t_end = -1: must be positive$"):
        slider_crank().simulate(-1)
    with pytest.raises(ValueError, match=r"^option method 'rk4': must be one of auto"):
        slider_crank().simulate(1, method="rk4")
    with pytest.raises(ValueError, match=r"^option rate '10 m': expected a frequency"):
        slider_crank().simulate(1, rate="10 m")


# ---------------------------------------------------------------------- runs and results


@pytest.fixture(scope="module")
def result() -> Result:
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built")
    return slider_crank().simulate("0.5 s", rate="10 kHz")


def test_slider_crank_run_matches_the_closed_form(result: Result) -> None:
    # crank angle at 0.5 s: w T / 2 + w (t - T) = 4 pi: slider back at r + L = 0.40 m
    assert result.ok and result.status == "finished" and result.message == ""
    assert result.time[0] == 0.0 and result.time[-1] == pytest.approx(0.5, abs=1e-12)
    assert len(result.time) == 5001
    assert result["slider.x"][-1] == pytest.approx(0.40, abs=1e-7)
    assert result["slider.x"].min() == pytest.approx(0.24, abs=1e-6)  # L - r
    # at full speed and theta = 2 pi k: a = -r w^2 (1 + r / L)
    w = 10 * math.pi
    assert result["slider.ax"].min() == pytest.approx(-0.08 * w**2 * 1.25, rel=1e-5)
    assert result["slider.ax"].max() == pytest.approx(0.08 * w**2 * 0.75, rel=1e-5)


def test_result_metadata(result: Result) -> None:
    assert result.model == slider_crank().to_dict()
    assert result.options["t_end"] == 0.5 and result.options["rate"] == 10000.0
    assert result.options["rtol"] == 1e-8 and result.options["method"] == "auto"
    assert result.stats["accepted_steps"] > 0
    assert set(result.stats) >= {"rhs_evaluations", "rejected_steps", "wall_time", "method"}
    assert result.warnings == []


def test_channels_in_model_order(result: Result) -> None:
    assert result.channels[:9] == [
        f"crank.{q}" for q in ("x", "y", "angle", "vx", "vy", "omega", "ax", "ay", "alpha")
    ]
    assert "motor.torque" in result.channels
    assert result.channels[-3:] == [
        "system.kinetic_energy",
        "system.potential_energy",
        "system.constraint_error",
    ]


def test_missing_channel_lists_close_matches(result: Result) -> None:
    with pytest.raises(KeyError) as err:
        result["slider.acc"]
    assert "no channel 'slider.acc'; close matches: " in str(err.value)
    assert "slider.ax" in str(err.value)


def test_result_arrays_are_read_only(result: Result) -> None:
    with pytest.raises(ValueError):
        result["slider.x"][0] = 1.0


def test_to_pandas_has_time_first(result: Result) -> None:
    df = result.to_pandas()
    assert list(df.columns) == ["time", *result.channels]
    assert df["slider.x"].iloc[-1] == result["slider.x"][-1]


def test_save_and_load_round_trip(result: Result, tmp_path) -> None:
    result.save(tmp_path / "run")
    header = (tmp_path / "run" / "results.csv").read_text().split("\n", 1)[0]
    assert header.startswith("time,crank.x,crank.y,")
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert set(summary) >= {"model", "options", "stats", "status"}
    again = Result.load(tmp_path / "run")
    assert again.channels == result.channels
    np.testing.assert_array_equal(again.time, result.time)
    np.testing.assert_array_equal(again.data, result.data)  # shortest exact floats
    assert again.model == result.model and again.options == result.options
    # the folder alone reproduces the run
    rerun = jointgap.Model.from_dict(again.model).simulate(**again.run_arguments())
    np.testing.assert_array_equal(rerun["slider.x"], result["slider.x"])


def test_failed_run_keeps_what_was_computed(engine) -> None:
    r = slider_crank().simulate(0.5, max_steps=5)
    assert r.status == "failed" and not r.ok
    assert r.message.startswith("failed at t = ")
    assert 0.0 < r.time[-1] < 0.5
    assert len(r["slider.x"]) == len(r.time)


def test_numpy_vectors_are_accepted() -> None:
    model = jointgap.Model(gravity=np.array([0.0, -9.81])).add_body(
        "a", np.float64(1.0), 0.1, position=np.array([0.5, 0.25]), points={"P": np.zeros(2)}
    )
    assert model.bodies["a"]["position"] == [0.5, 0.25]
    assert model.bodies["a"]["points"] == {"P": [0.0, 0.0]}


def test_shape_ends_must_be_points_of_the_body() -> None:
    with pytest.raises(ModelError) as err:
        jointgap.Model().add_body(
            "crank", 1, 1, points={"O": (0, 0)}, shape={"type": "bar", "from": "O", "to": "A"}
        )
    assert str(err.value) == "body 'crank': shape.to 'A' is not a point of body 'crank' (points: O)"
