"""The examples of the joint kinds beyond the revolute clearance joint: each runs from its
model file through the command, writing results, impacts and a report; the lubricated
founding case differs from the dry one by its joint's type line and film only; the
dry-against-lubricated figure is drawn; a spatial joint with play runs from a file."""

from __future__ import annotations

import csv
import difflib
import importlib.util
import json
from pathlib import Path

import pytest
from jointgap.cli import main

#: Each example's joint, channels it must write, and whether its parts strike (the oil
#: film keeps the lubricated founding case's journal off its bearing's wall).
EXAMPLES = {
    "slider_crank_guide_clearance.toml": (
        "slider_guide",
        ["slider_guide.p3.fn", "slider_guide.tilt"],
        True,
    ),
    "slider_crank_lubricated.toml": (
        "rod_slider",
        ["rod_slider.eccentricity_ratio", "rod_slider.film_mode"],
        False,
    ),
    "gear_backlash_arm.toml": ("mesh", ["mesh.mesh", "mesh.torque_2"], True),
}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_each_example_runs_with_outputs_impacts_and_a_report(
    examples, tmp_path, capsys, name
) -> None:
    joint, channels, strikes = EXAMPLES[name]
    out = tmp_path / "out"
    status = main(
        [
            "run",
            str(examples / name),
            "--t-end",
            "0.3",
            "--rate",
            "2000",
            "--out",
            str(out),
            "--report",
        ]
    )
    assert status == 0, capsys.readouterr().err
    with open(out / "results.csv", newline="") as f:
        header = next(csv.reader(f))
    assert all(c in header for c in channels), [c for c in channels if c not in header]
    with open(out / "impacts.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    listed = any(r["joint"].split(".")[0] == joint for r in rows)
    assert listed == strikes, f"{joint}: impacts listed {listed}, expected {strikes}"
    if not strikes:
        with open(out / "results.csv", newline="") as f:
            table = list(csv.reader(f))
        mode = table[0].index(f"{joint}.film_mode")
        assert all(float(row[mode]) == 0.0 for row in table[1:]), "the film carries throughout"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "finished"
    assert joint in (out / "report.html").read_text()


def test_the_lubricated_file_is_the_dry_one_but_for_its_type_and_film(examples) -> None:
    dry = (examples / "slider_crank_clearance.toml").read_text().splitlines()
    lubricated = (examples / "slider_crank_lubricated.toml").read_text().splitlines()
    changed = [
        line
        for line in difflib.unified_diff(dry, lubricated, lineterm="", n=0)
        if line[:1] in "+-"
        and not line.startswith(("+++", "---"))
        and not line[1:].lstrip().startswith("#")
    ]
    removed = [line for line in changed if line.startswith("-")]
    added = [line for line in changed if line.startswith("+")]
    # The model's name and the joint's type change; the film's table is added.
    assert [line.split("=")[0].strip("- ") for line in removed] == ["name", "type"], removed
    keys = {line[1:].split("=")[0].strip() for line in added if "=" in line}
    assert keys == {"name", "type", "length", "viscosity", "film"}, added
    assert '+type = "lubricated_revolute"' in [line.split("#")[0].strip() for line in added]


def test_the_dry_against_lubricated_figure(examples, tmp_path) -> None:
    spec = importlib.util.spec_from_file_location(
        "dry_vs_lubricated", examples / "dry_vs_lubricated.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = module.main(str(tmp_path / "figure"), "0.1")
    assert Path(path).stat().st_size > 10_000


SPATIAL_PLAY = """
[model]
name = "spatial_play"
dimension = 3
gravity = [0, 0, 0]

[[body]]
name = "part"
mass = "1 kg"
inertia = { principal = { moments = ["2e-3 kg*m^2", "2e-3 kg*m^2", "2e-3 kg*m^2"] } }
angular_velocity = ["0 rad/s", "1.8 rad/s", "2.4 rad/s"]

[[joint]]
name = "hub"
type = "revolute_with_play"
body_i = "ground"
point_i = [0, 0, 0]
body_j = "part"
point_j = [0, 0, 0]
axis = [0, 0.6, 0.8]

[joint.play]
play = "1 deg"
stiffness = "500 N*m/rad"
normal_law = { type = "hertz", exponent = 1 }
"""


def test_a_spatial_joint_with_play_from_a_file(write_model) -> None:
    import jointgap

    result = jointgap.load(write_model(SPATIAL_PLAY, "play.toml")).simulate(0.05, rate=20_000)
    # Free through half the play at 3 rad/s about the axis, then stopped.
    onset = result.impacts["hub"][0].onset_time
    assert onset == pytest.approx(0.5 * (1.0 * 3.141592653589793 / 180) / 3.0, rel=1e-8)
    before = result.time < onset
    assert (result["hub.torque"][before] == 0).all()
    assert result["hub.omega"][before] == pytest.approx(3.0, rel=1e-12)
