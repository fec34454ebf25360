"""Clearance revolute joints from Python: the builder and jointgap.laws give the same
model as the file; Result.impacts, impacts_frame() and impacts.csv."""

from __future__ import annotations

import math
from pathlib import Path

import jointgap
import pytest
from jointgap import laws
from jointgap.results import IMPACT_COLUMNS, Impact

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def founding_builder(**overrides) -> jointgap.Model:
    """examples/slider_crank_clearance.toml, built in Python."""
    ideal = jointgap.load(EXAMPLES / "slider_crank_ideal.toml").to_dict()
    m = jointgap.Model("slider_crank_clearance", gravity=("0 m/s^2", "-9.81 m/s^2"))
    m.add_ground_point("O", (0, 0))
    for body in ideal["bodies"]:
        m.add_body(**body)
    m.add_revolute("ground_crank", "ground", "crank", point_i="O", point_j="O")
    m.add_revolute("crank_rod", "crank", "rod", point_i="A", point_j="A")
    kwargs = dict(
        bearing_radius="7.5 mm",
        clearance="0.5 mm",
        bearing_material=laws.material("97 GPa", 0.3),
        journal_material={"youngs_modulus": "207 GPa", "poisson_ratio": 0.3},
        normal_law=laws.adams_impact("27960 N*s/m", "1e-5 m", exponent=1.5),
        friction=laws.coulomb(0.08, 0.05, "0.0001 m/s", "0.01016 m/s"),
    )
    kwargs.update(overrides)
    m.add_clearance_revolute("rod_slider", "slider", "rod", "B", "B", **kwargs)
    m.add_prismatic("slider_guide", "ground", "slider", axis=(1, 0), point_i="O", point_j="B")
    m.add_driver("motor", "ground_crank", jointgap.linear_ramp("300 rpm", "0.2 s"))
    return m


def test_builder_and_file_give_the_same_dict(examples, engine) -> None:
    from_file = jointgap.load(examples / "slider_crank_clearance.toml")
    built = founding_builder()
    assert built.to_dict() == from_file.to_dict()
    assert built.check() == []


def test_every_law_helper_converts_units() -> None:
    assert laws.hertz().to_si() == {"type": "hertz", "exponent": 1.5}
    assert laws.kelvin_voigt("2 kN*s/m", exponent=1).to_si() == {
        "type": "kelvin_voigt",
        "exponent": 1.0,
        "damping": 2000.0,
        "clip": True,
    }
    for make in (laws.hunt_crossley, laws.lankarani_nikravesh, laws.gonthier, laws.flores):
        law = make(0.8, clip=False).to_si()
        assert law["restitution"] == 0.8 and law["clip"] is False
    assert laws.adams_impact("27960 N*s/m").to_si() == {
        "type": "adams_impact",
        "exponent": 1.5,
        "c_max": 27960.0,
        "clip": True,
    }
    assert laws.adams_impact(1, "0.01 mm").to_si()["d_max"] == pytest.approx(1e-5)
    assert laws.no_friction().to_si() == {"type": "none"}
    assert laws.coulomb(0.08, 0.05, "0.1 mm/s", "10.16 mm/s").to_si()["v_d"] == pytest.approx(
        0.01016
    )
    assert laws.modified_coulomb(0.1, "1 mm/s", "1 cm/s").to_si()["v_1"] == pytest.approx(0.01)
    assert laws.viscous_coulomb(0.1, "1 mm/s", "5 N*s/m").to_si()["viscous"] == 5.0


def test_law_helper_rejects_a_wrong_unit() -> None:
    with pytest.raises(jointgap.ModelError) as err:
        laws.adams_impact("27960 N/m", "0.01 mm")
    assert str(err.value) == (
        "adams_impact normal law: c_max '27960 N/m': expected a damping coefficient [N*s/m], "
        "got a stiffness [N/m]"
    )


def test_stiffness_unit_follows_the_exponent(engine) -> None:
    m = founding_builder(
        bearing_material=None,
        journal_material=None,
        stiffness="1e9 N/m",
        normal_law=laws.hunt_crossley(0.9, exponent=1),
    )
    assert m.joints["rod_slider"]["clearance"]["stiffness"] == 1e9
    with pytest.raises(jointgap.ModelError) as err:
        founding_builder(stiffness="1e9 N/m")
    assert str(err.value) == (
        "joint 'rod_slider': stiffness '1e9 N/m': expected a contact stiffness [N/m^1.5], "
        "got a stiffness [N/m]"
    )


@pytest.mark.parametrize(
    ("overrides", "expected"),
    [
        (
            {"clearance": None, "journal_radius": "8 mm"},
            "joint 'rod_slider': journal_radius = 0.008 m must be smaller than "
            "bearing_radius = 0.0075 m",
        ),
        ({"clearance": -5e-4}, "joint 'rod_slider': clearance = -0.0005 m must be positive"),
        (
            {"normal_law": laws.gonthier(0.0)},
            "joint 'rod_slider': restitution = 0 must lie in (0, 1]",
        ),
        (
            {"journal_material": "kryptonite"},
            "joint 'rod_slider': journal_material 'kryptonite' is not in the material library",
        ),
        (
            {"normal_law": laws.adams_impact(27960, -1e-5)},
            "joint 'rod_slider': d_max = -0.00001 m must be positive",
        ),
        (
            {"normal_law": {"type": "soft", "restitution": 0.5}},
            "joint 'rod_slider': unknown normal_law type 'soft'",
        ),
        (
            {"clearance": "0.5 N"},
            "joint 'rod_slider': clearance '0.5 N': expected a length [m], got a force [N]",
        ),
    ],
)
def test_builder_errors_name_the_joint(overrides, expected, engine) -> None:
    with pytest.raises(jointgap.ModelError) as err:
        founding_builder(**overrides).check()
    message = str(err.value)
    if "d_max" in expected:  # the engine's float formatting
        assert message.startswith("joint 'rod_slider': d_max = -") and "must be positive" in message
    else:
        assert message.startswith(expected)
    assert err.value.name == "rod_slider"


def test_clearance_joint_between_a_body_and_itself(engine) -> None:
    m = jointgap.Model().add_body("a", 1, 1)
    m.add_clearance_revolute(
        "gap",
        "a",
        "a",
        (0, 0),
        (0, 0),
        clearance="0.1 mm",
        journal_radius="5 mm",
        stiffness=1e9,
        normal_law=laws.hertz(),
    )
    with pytest.raises(jointgap.ModelError) as err:
        m.check()
    assert str(err.value) == "joint 'gap': connects body 'a' to itself"


def test_result_impacts_and_save_load(tmp_path, engine) -> None:
    result = founding_builder().simulate("0.05 s", rate="10 kHz")
    assert result.ok
    assert list(result.impacts) == ["rod_slider"]
    impacts = result.impacts["rod_slider"]
    assert len(impacts) >= 1
    first = impacts[0]
    assert isinstance(first, Impact) and first.joint == "rod_slider"
    assert first.onset_time > 0 and first.peak_force > 0 and first.max_penetration > 0
    assert all(a.onset_time < b.onset_time for a, b in zip(impacts, impacts[1:], strict=False))
    frame = result.impacts_frame()
    assert list(frame.columns) == list(IMPACT_COLUMNS)
    assert len(frame) == len(impacts)
    assert frame["peak_force"].max() == max(i.peak_force for i in impacts)
    result.save(tmp_path)
    again = jointgap.Result.load(tmp_path)
    assert list(again.impacts) == ["rod_slider"]
    for a, b in zip(again.impacts["rod_slider"], impacts, strict=True):
        for c in IMPACT_COLUMNS[1:]:
            x, y = getattr(a, c), getattr(b, c)
            assert x == y or (math.isnan(x) and math.isnan(y))


def test_a_model_without_clearance_joints_writes_no_impacts(examples, tmp_path, engine) -> None:
    result = jointgap.load(examples / "pendulum.toml").simulate(0.01)
    assert result.impacts == {}
    result.save(tmp_path)
    assert not (tmp_path / "impacts.csv").exists()
