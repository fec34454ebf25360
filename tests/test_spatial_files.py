"""Spatial model files (``dimension = 3`` in ``[model]``): the examples load and run, units
and orientations convert, every bad input is an error naming the file, the line, the
element and the key, and the founding slider-crank written as a spatial model reproduces
the planar run.

The base model below is small so that the line numbers in the expected messages can be
read off it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap import ModelError
from jointgap.cli import main

ROOT = Path(__file__).resolve().parent.parent
SPATIAL_EXAMPLES = (
    "spatial_four_bar",
    "spatial_four_bar_clearance",
    "spatial_slider_crank",
    "slider_crank_clearance_3d",
)

BASE = """\
[model]
name = "pendulum_3d"
dimension = 3
gravity = [0, 0, "-9.81 m/s^2"]

[ground]
points = { O = [0, 0, 0] }

[[body]]
name = "arm"
mass = "1 kg"
inertia = ["1e-4 kg*m^2", "0.02 kg*m^2", "0.02 kg*m^2"]
position = ["250 mm", 0, 0]
orientation = { axis = [0, 0, 1], angle = "0 deg" }
points = { P = ["-250 mm", 0, 0], T = ["250 mm", 0, 0] }

[[joint]]
name = "pivot"
type = "revolute"
body_i = "ground"
point_i = "O"
body_j = "arm"
point_j = "P"
axis = [0, 1, 0]

[[force]]
name = "push"
type = "applied_force"
body = "arm"
point = "T"
force = [0, 0, "2 N"]
frame = "body"

[[marker]]
name = "tip"
body = "arm"
point = "T"
"""


def _load(text: str, tmp_path: Path) -> jointgap.Model:
    path = tmp_path / "model.toml"
    path.write_text(text, encoding="utf-8")
    return jointgap.load(path)


def _error(text: str, tmp_path: Path) -> ModelError:
    with pytest.raises(ModelError) as info:
        _load(text, tmp_path)
    return info.value


# ---------------------------------------------------------------------- loading and running


@pytest.mark.filterwarnings("ignore::jointgap.RunWarning")
@pytest.mark.parametrize("name", SPATIAL_EXAMPLES)
def test_each_spatial_example_loads_checks_and_runs(name: str, engine: None) -> None:
    model = jointgap.load(ROOT / "examples" / f"{name}.toml")
    assert model.spatial and model.dimension == 3
    assert model.check() == []
    result = model.simulate(0.005, rate=2000)
    assert result.ok, result.message
    assert len(result.time) == 11
    for body in model.bodies:
        for q in ("x", "y", "z", "e0", "e1", "e2", "e3", "wx", "alphaz"):
            assert f"{body}.{q}" in result
    # the quaternions stay unit
    e = np.array([result[f"{b}.e{k}"] for b in model.bodies for k in range(4)])
    norms = np.sqrt((e.reshape(len(model.bodies), 4, -1) ** 2).sum(axis=1))
    assert np.abs(norms - 1).max() < 1e-9


def test_the_base_model_runs_with_its_markers_and_loads(tmp_path: Path, engine: None) -> None:
    model = _load(BASE, tmp_path)
    assert model.degrees_of_freedom() == 1
    result = model.simulate(0.01, rate=1000)
    assert result.ok
    assert {"tip.x", "tip.y", "tip.z", "tip.az", "pivot.my", "pivot.angle"} <= set(result.channels)
    # The marker is the arm's tip: 0.5 m from the pivot, in the x-z plane.
    radius = np.hypot(result["tip.x"], result["tip.z"])
    np.testing.assert_allclose(radius, 0.5, rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["tip.y"], 0.0, atol=1e-12)


def test_units_convert_to_si(tmp_path: Path) -> None:
    data = _load(BASE, tmp_path).to_dict()
    assert data["dimension"] == 3
    assert data["gravity"] == [0.0, 0.0, -9.81]
    arm = data["bodies"][0]
    assert arm["inertia"] == {"principal": {"moments": [1e-4, 0.02, 0.02]}}
    assert arm["position"] == [0.25, 0.0, 0.0]
    assert arm["points"] == {"P": [-0.25, 0.0, 0.0], "T": [0.25, 0.0, 0.0]}
    assert arm["orientation"] == {"axis_angle": {"axis": [0.0, 0.0, 1.0], "angle": 0.0}}
    push = data["forces"][0]
    assert push["force"] == [0.0, 0.0, 2.0] and push["frame"] == "body"


def test_orientations_inertia_and_clearance_keys_convert(tmp_path: Path) -> None:
    text = BASE.replace(
        'orientation = { axis = [0, 0, 1], angle = "0 deg" }',
        'orientation = { euler = ["90 deg", 0, "30 deg"], convention = "ZYX" }\n'
        "inertia_frame = { quaternion = [1, 0, 0, 0] }",
    )
    arm = _load(text, tmp_path).bodies["arm"]
    assert arm["orientation"] == {
        "euler": {"convention": "ZYX", "angles": [math.pi / 2, 0.0, math.radians(30)]}
    }
    assert arm["inertia"]["principal"]["frame"] == {"quaternion": [1.0, 0.0, 0.0, 0.0]}
    tensor = BASE.replace(
        'inertia = ["1e-4 kg*m^2", "0.02 kg*m^2", "0.02 kg*m^2"]',
        'inertia = [["1e-4 kg*m^2", 0, 0], [0, "200 kg*cm^2", 0], [0, 0, 0.02]]',
    )
    arm = _load(tensor, tmp_path).bodies["arm"]
    assert arm["inertia"] == {"tensor": [[1e-4, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]}
    ball = jointgap.load(ROOT / "examples" / "spatial_four_bar_clearance.toml")
    clearance = ball.joints["coupler_rocker"]["clearance"]
    assert clearance["bearing_radius"] == 0.01 and clearance["clearance"] == 1e-4
    assert clearance["bearing_material"] == clearance["journal_material"] == "steel"
    journal = jointgap.load(ROOT / "examples" / "slider_crank_clearance_3d.toml")
    joint = journal.joints["rod_slider"]
    assert joint["length"] == 0.02 and joint["axis"] == [0.0, 0.0, 1.0]
    assert joint["clearance"]["bearing_radius"] == 0.0075


def test_a_spatial_model_saves_and_loads_back(tmp_path: Path, engine: None) -> None:
    for name in SPATIAL_EXAMPLES:
        model = jointgap.load(ROOT / "examples" / f"{name}.toml")
        model.save(tmp_path / f"{name}.toml")
        again = jointgap.load(tmp_path / f"{name}.toml")
        assert again == model
        assert again.to_json() == model.to_json()
    # and the engine's own form (summary.json) rebuilds the same model
    model = jointgap.load(ROOT / "examples" / "spatial_four_bar_clearance.toml")
    assert jointgap.Model.from_dict(json.loads(model.to_json())) == model


def test_dimension_2_is_a_planar_file(tmp_path: Path) -> None:
    planar = (ROOT / "examples" / "pendulum.toml").read_text()
    with_two = planar.replace("[model]\n", "[model]\ndimension = 2\n", 1)
    assert "dimension = 2" in with_two
    assert _load(with_two, tmp_path) == jointgap.load(ROOT / "examples" / "pendulum.toml")


# ---------------------------------------------------------------------- located errors


@pytest.mark.parametrize(
    ("old", "new", "line", "element", "key", "words"),
    [
        ("dimension = 3", "dimension = 4", 3, None, "dimension", "dimension = 4"),
        (
            'position = ["250 mm", 0, 0]',
            'position = ["250 mm", 0]',
            13,
            "body 'arm'",
            "position",
            "[x, y, z]",
        ),
        (
            'position = ["250 mm", 0, 0]',
            'position = ["250 kg", 0, 0]',
            13,
            "body 'arm'",
            "position",
            "expected a length",
        ),
        (
            'position = ["250 mm", 0, 0]',
            'angle = "10 deg"',
            13,
            "body 'arm'",
            "angle",
            "unknown key 'angle'",
        ),
        (
            'orientation = { axis = [0, 0, 1], angle = "0 deg" }',
            "orientation = { axis = [0, 0, 1] }",
            14,
            "body 'arm'",
            "orientation",
            "write one of",
        ),
        (
            'inertia = ["1e-4 kg*m^2", "0.02 kg*m^2", "0.02 kg*m^2"]',
            'inertia = "1 kg*m^2"',
            12,
            "body 'arm'",
            "inertia",
            "principal moments [J1, J2, J3] or a 3x3 tensor",
        ),
        (
            'frame = "body"',
            'frame = "world"',
            32,
            "force 'push'",
            "frame",
            "must be one of ground, body",
        ),
        (
            'type = "revolute"',
            'type = "hinge"',
            19,
            "joint 'pivot'",
            "type",
            "unknown joint type 'hinge'",
        ),
        (
            'type = "revolute"',
            'type = "clearance_revolute"',
            19,
            "joint 'pivot'",
            "type",
            "unknown joint type 'clearance_revolute'",
        ),
        # the engine's checks, located by the key it names (the principal frame is part of
        # the engine's inertia)
        (
            'angle = "0 deg" }',
            'angle = "0 deg" }\ninertia_frame = { quaternion = [0, 0, 0, 0] }',
            12,
            "body 'arm'",
            "inertia",
            "quaternion",
        ),
        (
            'orientation = { axis = [0, 0, 1], angle = "0 deg" }',
            "orientation = { quaternion = [0, 0, 0, 0] }",
            14,
            "body 'arm'",
            "orientation",
            "has length 0",
        ),
        (
            '"0.02 kg*m^2", "0.02 kg*m^2"]',
            '"0.02 kg*m^2", "0.03 kg*m^2"]',
            12,
            "body 'arm'",
            "inertia",
            "triangle inequality",
        ),
        ("axis = [0, 1, 0]", "axis = [0, 0, 0]", 24, "joint 'pivot'", "axis", "non-zero"),
        ("axis = [0, 1, 0]\n", "", 18, "joint 'pivot'", "axis", "missing field 'axis'"),
        ('body_j = "arm"', 'body_j = "armm"', 22, "joint 'pivot'", "body_j", "not a body"),
    ],
)
def test_each_bad_input_names_file_line_element_and_key(
    tmp_path: Path,
    engine: None,
    old: str,
    new: str,
    line: int,
    element: str | None,
    key: str,
    words: str,
) -> None:
    assert old in BASE
    error = _error(BASE.replace(old, new, 1), tmp_path)
    assert error.file == str(tmp_path / "model.toml")
    assert error.line == line, str(error)
    assert error.key is not None and error.key.split(".")[0] == key, str(error)
    if element is not None:
        assert error.element == element
    assert words in str(error)
    assert str(error).startswith(f"{tmp_path / 'model.toml'}:{line}: ")


def test_a_ball_larger_than_its_socket_is_named_in_the_files_words(engine: None) -> None:
    text = (ROOT / "examples" / "spatial_four_bar_clearance.toml").read_text()
    text = text.replace('clearance = "0.1 mm"', 'ball_radius = "12 mm"')
    with pytest.raises(ModelError) as info:
        jointgap.loads(text, "ball.toml")
    error = info.value
    assert error.key == "ball_radius" and error.element == "joint 'coupler_rocker'"
    assert error.line == text.splitlines().index('ball_radius = "12 mm"') + 1
    assert "ball_radius = 0.012 m must be smaller than socket_radius = 0.01 m" in str(error)


# ---------------------------------------------------------------------- the command line


def test_jointgap_run_writes_a_spatial_runs_files(tmp_path: Path, engine: None, capsys) -> None:
    out = tmp_path / "out"
    model = ROOT / "examples" / "slider_crank_clearance_3d.toml"
    args = ["run", str(model), "--t-end", "0.01", "--rate", "10000", "--out", str(out)]
    assert main([*args, "--report"]) == 0
    printed = capsys.readouterr().out
    assert "no report" not in printed and (out / "report.html").exists()
    assert "rod_slider.p1: 3 impacts" in printed and "rod_slider.p2: 3 impacts" in printed
    for name in ("results.csv", "summary.json", "impacts.csv", "contact_statistics.csv"):
        assert (out / name).exists()
    result = jointgap.Result.load(out)
    assert {"rod_slider.p1", "rod_slider.p2"} == set(result.impacts)
    assert "slider.z" in result.channels and result.model["dimension"] == 3
    assert main(["check", str(model)]) == 0
    assert "joint equations: 15" in capsys.readouterr().out


# ---------------------------------------------------------------------- the founding case in 3D


def test_the_founding_slider_crank_in_3d_reproduces_the_planar_run(engine: None) -> None:
    """The two engines checking each other: the spatial model of the founding case
    (revolute joints about z, a clearance_cylindrical journal held parallel to its
    bearing) computes the planar clearance joint's force (its two ends share the law),
    so at a tight tolerance the runs agree to the integration error: the same impacts at
    the same onsets, and the slider acceleration's NRMSE below 1e-6 (it was 4e-8)."""
    options = {"rate": 10_000, "rtol": 1e-11, "atol": 1e-14}
    planar = jointgap.load(ROOT / "examples" / "slider_crank_clearance.toml").simulate(
        0.06, **options
    )
    spatial = jointgap.load(ROOT / "examples" / "slider_crank_clearance_3d.toml").simulate(
        0.06, **options
    )
    assert planar.ok and spatial.ok
    flat = planar.impacts["rod_slider"]
    ends = spatial.impacts["rod_slider.p1"], spatial.impacts["rod_slider.p2"]
    assert len(flat) >= 10
    for end in ends:
        assert len(end) == len(flat)
        onset = np.array([i.onset_time for i in end])
        np.testing.assert_allclose(onset, [i.onset_time for i in flat], rtol=0, atol=1e-8)
        # each end carries half of the law: a missing or doubled share shows here
        peak = np.array([i.peak_force for i in end])
        np.testing.assert_allclose(2 * peak, [i.peak_force for i in flat], rtol=1e-5)
    a, b = planar["slider.ax"], spatial["slider.ax"]
    nrmse = np.sqrt(np.mean((a - b) ** 2)) / (a.max() - a.min())
    assert nrmse < 1e-6, nrmse
    # the motion stays in the plane
    assert np.abs(spatial["slider.z"]).max() < 1e-12
    assert np.abs(spatial["rod.z"]).max() < 1e-12


def test_docs_spatial_field_reference_matches_the_schema() -> None:
    from jointgap._schema import reference_markdown

    docs = (ROOT / "docs" / "model-file.md").read_text()
    begin, end = "<!-- spatial-reference:begin -->\n", "<!-- spatial-reference:end -->"
    section = docs[docs.index(begin) + len(begin) : docs.index(end)]
    assert section.strip() == reference_markdown(3).strip(), (
        "docs/model-file.md is out of date: paste jointgap._schema.reference_markdown(3) "
        "between the spatial reference markers"
    )


@pytest.mark.filterwarnings("ignore::jointgap.RunWarning")
def test_a_streamed_spatial_run_reads_back(tmp_path: Path, engine: None) -> None:
    out = tmp_path / "out"
    model = ROOT / "examples" / "spatial_four_bar_clearance.toml"
    args = ["run", str(model), "--t-end", "0.005", "--rate", "5000", "--out", str(out)]
    assert main([*args, "--stream"]) == 0
    streamed = jointgap.Result.load(out)
    assert (out / "results.parquet").exists() and "coupler_rocker" in streamed.impacts
    direct = jointgap.load(model).simulate(0.005, rate=5000)
    np.testing.assert_array_equal(streamed["coupler_rocker.fnz"], direct["coupler_rocker.fnz"])
