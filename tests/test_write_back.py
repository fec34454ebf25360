"""Models written back by ``calibrate --write`` and ``identify --write`` are the user's
own file: every comment and line kept, only the changed values replaced, each in the
unit the user wrote it in; and they load to the calibrated (or fitted) model."""

from __future__ import annotations

import difflib
import re
from pathlib import Path

import jointgap
import pytest
from jointgap.cli import main
from jointgap.units import written_like
from jointgap.variants import with_parameters
from jointgap.writeback import write_back

EXAMPLE = Path("examples/slider_crank_clearance.toml")


def _changed_lines(before: str, after: str) -> list[tuple[str, str]]:
    """(old, new) of each replaced line; fails on lines added or removed."""
    a, b = before.splitlines(), after.splitlines()
    pairs = []
    for op, i1, i2, j1, j2 in difflib.SequenceMatcher(None, a, b).get_opcodes():
        if op == "equal":
            continue
        assert op == "replace" and i2 - i1 == j2 - j1, (op, a[i1:i2], b[j1:j2])
        pairs += list(zip(a[i1:i2], b[j1:j2], strict=True))
    return pairs


def test_written_like_keeps_the_unit() -> None:
    assert written_like(17155.65, "27960 N*s/m") == "17155.65 N*s/m"
    # as many digits as it takes to read back the same number, 12 at least
    assert written_like(17155.685224057655, "27960 N*s/m") == "17155.685224057655 N*s/m"
    assert written_like(0.0075 - 0.0004, "7 mm") == "7.0999999999999996 mm"
    assert written_like(2e-5, "0.01 mm") == "0.02 mm"
    assert written_like(3.2e10, "3.136e10 N/m^1.5") == "32000000000 N/m^1.5"
    assert written_like(0.047, 0.05) == 0.047
    assert written_like(0.047, "0.05") == "0.047"
    assert written_like(0.4, None) == 0.4


def test_changed_values_replace_the_users_in_their_units(tmp_path, engine) -> None:
    model = jointgap.load(EXAMPLE)
    fitted = with_parameters(
        model,
        {"rod_slider.c_max": 17155.685224, "rod_slider.d_max": 2e-5, "rod_slider.mu_d": 0.047},
    )
    out = tmp_path / "deep" / "fitted.toml"
    changes = write_back(EXAMPLE, fitted, out)
    assert changes == [
        "rod_slider.normal_law.c_max = 17155.685224 N*s/m",
        "rod_slider.normal_law.d_max = 2e-05 m",
        "rod_slider.friction.mu_d = 0.047",
    ]
    before, after = EXAMPLE.read_text(encoding="utf-8"), out.read_text(encoding="utf-8")
    [(old_law, new_law), (old_friction, new_friction)] = _changed_lines(before, after)
    assert (
        old_law.replace('c_max = "27960 N*s/m"', 'c_max = "17155.685224 N*s/m"').replace(
            'd_max = "1e-5 m"', 'd_max = "2e-05 m"'
        )
        == new_law
    )
    assert old_friction.replace("mu_d = 0.05,", "mu_d = 0.047,") == new_friction
    assert jointgap.load(out).to_dict() == fitted.to_dict()


def test_a_value_the_file_lacks_is_added_and_a_radius_kept(write_model, tmp_path, engine) -> None:
    """A value the file does not give (the stiffness, from the materials) is added in
    SI; the clearance of a file that gives both radii moves the journal radius, written
    in the file's unit, its comment kept."""
    text = EXAMPLE.read_text(encoding="utf-8")
    text = text.replace('clearance = "0.5 mm"', 'journal_radius = "7 mm"   # the pin')
    source = write_model(text, "user.toml")
    model = jointgap.load(source)
    fitted = with_parameters(model, {"rod_slider.stiffness": 3.2e10, "rod_slider.clearance": 4e-4})
    journal = fitted.joints["rod_slider"]["clearance"]["journal_radius"]  # 0.0075 - 0.0004
    assert write_back(source, fitted, tmp_path / "out.toml") == [
        f"rod_slider.journal_radius = {written_like(journal, '7 mm')}",
        "rod_slider.stiffness = 32000000000.0",
    ]
    written = (tmp_path / "out.toml").read_text(encoding="utf-8")
    assert re.search(r'journal_radius = "7\.(1|09+\d*) mm"   # the pin', written)
    assert "stiffness = 32000000000.0" in written
    assert jointgap.load(tmp_path / "out.toml").to_dict() == fitted.to_dict()


def test_other_changes_are_refused(tmp_path, engine) -> None:
    model = jointgap.load(EXAMPLE)
    data = model.to_dict()
    data["bodies"][0]["mass"] = 3.0
    with pytest.raises(ValueError, match="cannot write back a model whose bodies changed"):
        write_back(EXAMPLE, jointgap.Model.from_dict(data), tmp_path / "x.toml")


def test_calibrate_write_keeps_the_users_file(tmp_path, capsys, engine) -> None:
    out = tmp_path / "calibrated.toml"
    status = main(
        [
            "calibrate",
            str(EXAMPLE),
            "--restitution",
            "0.55",
            "--t-end",
            "0.15",
            "--rate",
            "1000",
            "--max-iterations",
            "2",
            "--write",
            str(out),
        ]
    )
    assert status in (0, 4)  # two iterations need not converge; the file is written
    printed = capsys.readouterr().out
    before, after = EXAMPLE.read_text(encoding="utf-8"), out.read_text(encoding="utf-8")
    [(old, new)] = _changed_lines(before, after)
    assert 'c_max = "27960 N*s/m"' in old
    c_max = jointgap.load(out).joints["rod_slider"]["clearance"]["normal_law"]["c_max"]
    text = written_like(c_max, "27960 N*s/m")
    assert new == old.replace('"27960 N*s/m"', f'"{text}"')
    assert f"changed    rod_slider.normal_law.c_max = {text}" in printed
    assert f"written    {out}" in printed
