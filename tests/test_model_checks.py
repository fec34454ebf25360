"""Absurd models stopped or flagged before they run: each reproducer of the founding
example, edited as a user might, against the command's message and exit status."""

from __future__ import annotations

from pathlib import Path

import jointgap
import pytest
from jointgap.cli import EXIT_INVALID, main

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"


def edited(tmp_path: Path, old: str, new: str, name: str = "model.toml") -> Path:
    """The founding clearance example with one text edit, written to ``tmp_path``."""
    text = EXAMPLE.read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / name
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def line_of(path: Path, text: str) -> int:
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_a_joint_point_left_out_is_an_error_not_the_centre_of_mass(
    tmp_path, capsys, engine
) -> None:
    """Deleting ``point_i = "A"`` of joint crank_rod used to put the joint at the crank's
    centre of mass, 39.5 mm outside the 0.5 mm clearance (2.5e8 N), and the run finished."""
    model = edited(
        tmp_path,
        'body_i = "crank"\npoint_i = "A"\n',
        'body_i = "crank"\n',
    )
    assert main(["check", str(model)]) == EXIT_INVALID
    err = capsys.readouterr().err
    line = line_of(model, 'name = "crank_rod"')
    assert err == f"jointgap: error: {model}:{line}: joint 'crank_rod': missing field 'point_i'\n"
    assert main(["run", str(model), "--t-end", "0.01", "--out", str(tmp_path / "o")]) == 1
    assert "missing field 'point_i'" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_a_point_left_out_is_an_error_in_the_builder_and_the_engine(engine) -> None:
    model = jointgap.Model().add_body("a", 1, 1)
    with pytest.raises(TypeError):
        model.add_revolute("pin", "ground", "a")  # type: ignore[call-arg]
    with pytest.raises(jointgap.ModelError, match=r"^force 'spring': missing field 'point_i'$"):
        model.add_spring_damper("spring", "ground", "a", stiffness=1.0)
    from jointgap._jointgap import check_model

    with pytest.raises(ValueError, match="missing field `point_i`"):
        check_model(
            '{"bodies": [{"name": "a", "mass": 1, "inertia": 1}], "joints": [{"name": "j", '
            '"type": "revolute", "body_i": "ground", "body_j": "a", "point_j": [0, 0]}]}'
        )


@pytest.mark.parametrize(
    ("old", "new", "warning"),
    [
        (
            'bearing_radius = "7.5 mm"',
            "bearing_radius = 7.5",
            "joint 'rod_slider': bearing_radius = 7.5 m is 23.4 times the longest link "
            "(0.32 m, body 'rod'); a plain number is in metres: check the unit",
        ),
        (
            'speed = "300 rpm"',
            "speed = 300",
            "driver 'motor': speed = 300 rad/s (2865 rpm) moves the points of the driven body "
            "at up to 24 m/s, faster than 20 m/s, unusual for a linkage; a plain number is in "
            'rad/s or m/s: check the unit (e.g. "300 rpm")',
        ),
        (
            'mass = "2.37 kg"',
            "mass = 2370",
            "body 'crank': mass = 2370 kg is more than a solid osmium cube as large as the "
            "longest link (0.32 m, body 'rod') would weigh (740 kg); a plain number is in kg: "
            "check the unit",
        ),
        (
            'inertia = "0.0006926 kg*m^2"',
            "inertia = 692.6",
            "body 'rod': inertia = 692.6 kg*m^2 puts the radius of gyration sqrt(inertia/mass) "
            "at 31 m, beyond the longest link (0.32 m, body 'rod'); a plain number is in "
            "kg*m^2: check the unit",
        ),
        (
            'clearance = "0.5 mm"',
            'clearance = "2 mm"',
            "joint 'rod_slider': clearance = 0.002 m is 26.7 % of the bearing radius "
            "(0.0075 m); radial clearances are usually below 1 %: check the unit",
        ),
    ],
)
def test_implausible_magnitudes_are_warned_by_check_and_run(
    tmp_path, capsys, engine, old: str, new: str, warning: str
) -> None:
    """A plain number is SI: ``bearing_radius = 7.5`` is 7.5 m, ``speed = 300`` is
    300 rad/s (2865 rpm). Both are legal and used to run without a word."""
    model = edited(tmp_path, old, new)
    assert main(["check", str(model)]) == 0
    assert f"  warning: {warning}\n" in capsys.readouterr().out
    out = tmp_path / "run"
    status = main(["run", str(model), "--t-end", "1 ms", "--rate", "1 kHz", "--out", str(out)])
    assert status in (0, 3)  # warned, not refused (an absurd model may still stop early)
    assert f"warning    {warning}\n" in capsys.readouterr().out


def test_the_examples_raise_no_magnitude_warning(examples, engine) -> None:
    """No false alarm on the models the project ships (their warnings are about
    redundant constraints only)."""
    for path in sorted(examples.glob("*.toml")):
        if "[[body]]" not in path.read_text(encoding="utf-8"):
            continue  # a study or calibration file
        for warning in jointgap.load(path).check():
            assert "redundant constraint" in warning, (path.name, warning)


def test_an_empty_model_file_is_an_error(tmp_path, capsys, engine) -> None:
    path = tmp_path / "empty.toml"
    path.write_text("# nothing yet\n", encoding="utf-8")
    assert main(["check", str(path)]) == EXIT_INVALID
    assert capsys.readouterr().err == (
        f"jointgap: error: {path}: the model has no bodies: a mechanism needs at least one "
        "[[body]] (is the file empty?)\n"
    )


def test_a_model_file_that_is_not_utf8_names_the_file(tmp_path, capsys) -> None:
    path = tmp_path / "latin1.toml"
    text = EXAMPLE.read_text(encoding="utf-8").replace("Haroun", "Hároun", 1)
    path.write_bytes(text.encode("latin-1"))
    assert main(["check", str(path)]) == EXIT_INVALID
    offset = text.encode("latin-1").index(b"\xe1")
    assert capsys.readouterr().err == (
        f"jointgap: error: {path}:1: not a UTF-8 text file (byte 0xe1 at offset {offset}): "
        "save the model file as UTF-8\n"
    )


def test_a_single_body_table_gets_the_array_hint(tmp_path, capsys) -> None:
    """``[body]`` for ``[[body]]``: three bodies then declare one table three times, which
    the TOML reader reports without saying why."""
    model = tmp_path / "model.toml"
    model.write_text(EXAMPLE.read_text(encoding="utf-8").replace("[[body]]", "[body]"))
    assert main(["check", str(model)]) == EXIT_INVALID
    line = line_of(model, "[body]")
    assert capsys.readouterr().err == (
        f"jointgap: error: {model}:{line}: write [[body]] (one table per body), not [body]\n"
    )
    one = tmp_path / "one.toml"
    one.write_text('[body]\nname = "crank"\nmass = "1 kg"\ninertia = "1 kg*m^2"\n')
    assert main(["check", str(one)]) == EXIT_INVALID
    assert capsys.readouterr().err == (
        f"jointgap: error: {one}:1: write [[body]] (one table per body), not [body]\n"
    )


def test_a_clearance_larger_than_the_bearing_says_so(tmp_path, capsys, engine) -> None:
    model = edited(tmp_path, 'clearance = "0.5 mm"', 'clearance = "10 mm"')
    assert main(["check", str(model)]) == EXIT_INVALID
    line = line_of(model, 'clearance = "10 mm"')
    assert capsys.readouterr().err == (
        f"jointgap: error: {model}:{line}: joint 'rod_slider': clearance = 0.01 m is not "
        "smaller than bearing_radius = 0.0075 m: the clearance is the radial gap between "
        "bearing and journal, a small fraction of the bearing radius (check the units)\n"
    )


def test_a_dynamic_friction_above_the_static_one_is_warned(tmp_path, capsys, engine) -> None:
    model = edited(tmp_path, "mu_s = 0.08, mu_d = 0.05", "mu_s = 0.05, mu_d = 0.08")
    assert main(["check", str(model)]) == 0
    assert (
        "  warning: joint 'rod_slider': friction mu_d = 0.08 is larger than mu_s = 0.05: the "
        "dynamic coefficient is usually the smaller, so the friction force will rise once "
        "sliding starts\n"
    ) in capsys.readouterr().out
