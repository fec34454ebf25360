"""Clearance revolute joints in model files: the nested engine form, the examples, the CLI
run with its impact list, and bad input named by file, line, joint and key."""

from __future__ import annotations

import csv
from pathlib import Path

import jointgap
import pytest
from jointgap.cli import main

FOUNDING = "slider_crank_clearance.toml"


def founding_text(examples: Path) -> str:
    return (examples / FOUNDING).read_text(encoding="utf-8")


def load_error(tmp_path: Path, text: str, old: str, new: str) -> tuple[Path, str]:
    assert old in text, old
    path = tmp_path / "model.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(jointgap.ModelError) as err:
        jointgap.load(path)
    return path, str(err.value)


def test_flat_keys_become_the_nested_clearance(examples, engine) -> None:
    joint = jointgap.load(examples / FOUNDING).joints["rod_slider"]
    assert joint["type"] == "clearance_revolute"
    assert (joint["body_i"], joint["point_i"], joint["body_j"], joint["point_j"]) == (
        "slider",
        "B",
        "rod",
        "B",
    )
    assert joint["clearance"] == {
        "bearing_radius": pytest.approx(7.5e-3),
        "clearance": pytest.approx(5e-4),
        "bearing_material": {"youngs_modulus": 97e9, "poisson_ratio": 0.3},
        "journal_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
        "normal_law": {
            "type": "adams_impact",
            "exponent": 1.5,
            "c_max": 27960.0,
            "d_max": 1e-5,
            "clip": True,
        },
        "friction": {"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05, "v_s": 1e-4, "v_d": 0.01016},
    }


@pytest.mark.parametrize(
    "name",
    [FOUNDING, "slider_crank_two_clearances.toml", "slider_crank_clearance_horizontal.toml"],
)
def test_examples_are_valid(examples, name, engine) -> None:
    model = jointgap.load(examples / name)
    assert model.check() == []
    clearance = [j for j in model.joints.values() if j["type"] == "clearance_revolute"]
    assert len(clearance) == (2 if "two" in name else 1)
    assert model.gravity == ((0.0, 0.0) if "horizontal" in name else (0.0, -9.81))


def test_nested_form_and_save_read_back(examples, tmp_path, engine) -> None:
    model = jointgap.load(examples / FOUNDING)
    assert jointgap.Model.from_dict(model.to_dict()) == model
    model.save(tmp_path / "again.toml")
    assert jointgap.load(tmp_path / "again.toml") == model


def test_library_material_names_and_stiffness(examples, tmp_path, engine) -> None:
    text = founding_text(examples)
    text = text.replace(
        'bearing_material = { youngs_modulus = "97 GPa", poisson_ratio = 0.3 }',
        'bearing_material = "brass"',
    ).replace(
        'journal_material = { youngs_modulus = "207 GPa", poisson_ratio = 0.3 }',
        'stiffness = "3.136e10 N/m^1.5"',
    )
    path = tmp_path / "lib.toml"
    path.write_text(text, encoding="utf-8")
    clearance = jointgap.load(path).joints["rod_slider"]["clearance"]
    assert clearance["bearing_material"] == "brass"
    assert clearance["stiffness"] == pytest.approx(3.136e10)


def test_cli_run_writes_results_and_impacts(examples, tmp_path, capsys, engine) -> None:
    out = tmp_path / "run"
    status = main(
        ["run", str(examples / FOUNDING), "--t-end", "0.1", "--rate", "10000", "--out", str(out)]
    )
    assert status == 0
    with open(out / "results.csv", newline="") as f:
        header = next(csv.reader(f))
    for channel in (
        "slider.x",
        "slider.vx",
        "slider.ax",
        "motor.torque",
        "rod_slider.fn",
        "rod_slider.ex",
        "rod_slider.ey",
    ):
        assert channel in header
    with open(out / "impacts.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == [
        "joint",
        "onset_time",
        "onset_speed",
        "peak_force",
        "max_penetration",
        "duration",
    ]
    assert len(rows) >= 1 and all(r["joint"] == "rod_slider" for r in rows)
    assert all(float(r["peak_force"]) > 0 and float(r["max_penetration"]) > 0 for r in rows)
    printed = capsys.readouterr().out
    assert f"contact    rod_slider: {len(rows)} impacts; free flight" in printed
    assert "max penetration" in printed and "onset speed mean" in printed
    again = jointgap.Result.load(out)
    assert len(again.impacts["rod_slider"]) == len(rows)


# ---------------------------------------------------------------------- bad input

BAD = [
    (
        'bearing_radius = "7.5 mm"               # two of bearing_radius, journal_radius, '
        'clearance\nclearance = "0.5 mm"',
        'bearing_radius = "7.5 mm"\njournal_radius = "7.5 mm"',
        "joint 'rod_slider': journal_radius = 0.0075 m must be smaller than bearing_radius = "
        "0.0075 m",
    ),
    (
        'clearance = "0.5 mm"',
        'clearance = "-0.5 mm"',
        "joint 'rod_slider': clearance = -0.0005 m must be positive",
    ),
    (
        'type = "adams_impact", exponent = 1.5, c_max = "27960 N*s/m", d_max = "1e-5 m"',
        'type = "flores", restitution = 1.2',
        "joint 'rod_slider': restitution = 1.2 must lie in (0, 1]",
    ),
    (
        'bearing_material = { youngs_modulus = "97 GPa", poisson_ratio = 0.3 }',
        'bearing_material = "unobtainium"',
        "joint 'rod_slider': bearing_material 'unobtainium' is not in the material library "
        "(steel, stainless_steel, brass, bronze, aluminium_alloy, cast_iron, titanium_alloy)",
    ),
    (
        'd_max = "1e-5 m"',
        'd_max = "0 m"',
        "joint 'rod_slider': d_max = 0 m must be positive",
    ),
    (
        'body_i = "slider"                       # bearing: the hole in the slider',
        'body_i = "rod"',
        "joint 'rod_slider': connects body 'rod' to itself",
    ),
    (
        'type = "adams_impact"',
        'type = "impact"',
        "joint 'rod_slider': unknown normal_law type 'impact' (allowed: hertz, kelvin_voigt, "
        "hunt_crossley, lankarani_nikravesh, gonthier, flores, adams_impact)",
    ),
    (
        'type = "coulomb"',
        'type = "stribeck"',
        "joint 'rod_slider': unknown friction type 'stribeck' (allowed: none, coulomb, "
        "modified_coulomb, viscous_coulomb)",
    ),
    (
        'c_max = "27960 N*s/m"',
        'c_max = "27960 N/m"',
        "joint 'rod_slider': normal_law.c_max '27960 N/m': expected a damping coefficient "
        "[N*s/m], got a stiffness [N/m]",
    ),
    (
        'clearance = "0.5 mm"',
        'clearance = "0.5 mm/s"',
        "joint 'rod_slider': clearance '0.5 mm/s': expected a length [m], got a speed [m/s]",
    ),
    (
        'bearing_radius = "7.5 mm" ',
        'stiffness = "3e10 N/m^2"\nbearing_radius = "7.5 mm" ',
        "joint 'rod_slider': stiffness '3e10 N/m^2': expected a contact stiffness [N/m^1.5], "
        "got a pressure [Pa]",
    ),
    (
        "mu_d = 0.05,",
        "mu_d = 0.05, mu = 0.1,",
        "joint 'rod_slider': unknown key 'friction.mu' for a coulomb friction "
        "(allowed: type, mu_s, mu_d, v_s, v_d)",
    ),
    (
        'clearance = "0.5 mm"',
        'clearance = "0.5 mm"\ngap = "0.5 mm"',
        "joint 'rod_slider': unknown key 'gap' for a clearance_revolute joint",
    ),
]


@pytest.mark.parametrize(("old", "new", "expected"), BAD, ids=[b[2][21:60] for b in BAD])
def test_bad_input_names_file_line_joint(examples, tmp_path, old, new, expected, engine) -> None:
    path, message = load_error(tmp_path, founding_text(examples), old, new)
    assert message.startswith(f"{path}:")
    line = int(message.split(":")[1])
    assert 60 < line < 90  # within the rod_slider table
    assert expected in message
