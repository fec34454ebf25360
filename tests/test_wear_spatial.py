"""Wear of the spatial cylindrical clearance joint (docs/wear.md, "The spatial journal"):
its wear tables in the model file, its worn contact against the planar joint's (the
founding case in 3D, whose aligned journal is the planar one), the wear a run
accumulates against the planar run's, and the prediction over life against the planar
one's (Archard's closed form for a pressed journal in 3D: tests/test_wear_life.py)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import jointgap
import numpy as np
import pandas as pd
import pytest
from jointgap.cli import main
from jointgap.wear import predict_wear

ROOT = Path(__file__).resolve().parent.parent
TIGHT = {"rate": 10_000, "rtol": 1e-11, "atol": 1e-14}


def founding_pair(**tables: list[float]) -> tuple[jointgap.Model, jointgap.Model]:
    """The founding slider-crank, planar (its bearing given the 3D journal's 20 mm) and
    in 3D, both worn by ``tables`` (``bearing_wear``, ``journal_wear``)."""
    planar = jointgap.load(ROOT / "examples" / "slider_crank_clearance.toml").to_dict()
    spatial = jointgap.load(ROOT / "examples" / "slider_crank_clearance_3d.toml").to_dict()
    for data in (planar, spatial):
        joint = next(j for j in data["joints"] if j["name"] == "rod_slider")
        joint["clearance"].update(tables)
    next(j for j in planar["joints"] if j["name"] == "rod_slider")["clearance"]["length"] = 0.02
    return jointgap.Model.from_dict(planar), jointgap.Model.from_dict(spatial)


def test_a_cylindrical_joint_takes_wear_tables_with_units(tmp_path: Path) -> None:
    text = (ROOT / "examples" / "slider_crank_clearance_3d.toml").read_text()
    worn = text.replace(
        'length = "20 mm"                             # of the journal\n',
        'length = "20 mm"\nbearing_wear = ["1 um", "2 um", "3 um", "2 um", "1 um", 0, 0, 0]\n',
        1,
    )
    assert worn != text
    model = jointgap.loads(worn)
    joint = model.joints["rod_slider"]
    assert joint["length"] == pytest.approx(0.02)
    assert joint["clearance"]["bearing_wear"] == pytest.approx(
        [1e-6, 2e-6, 3e-6, 2e-6, 1e-6, 0, 0, 0]
    )
    model.save(tmp_path / "worn.toml")
    assert jointgap.load(tmp_path / "worn.toml") == model
    # A lubricated journal, its film carrying the load, has none; nor has a ball.
    lubricated = worn.replace(
        'type = "clearance_cylindrical"', 'type = "lubricated_cylindrical"', 1
    ).replace(
        'length = "20 mm"\n', 'length = "20 mm"\nlubrication = { viscosity = "0.05 Pa*s" }\n', 1
    )
    with pytest.raises(jointgap.ModelError, match="unknown key 'bearing_wear'"):
        jointgap.loads(lubricated)
    ball = (ROOT / "examples" / "spatial_four_bar_clearance.toml").read_text()
    tables = 'clearance = "0.1 mm"\nbearing_wear = [0, 0, 0, 0, 0, 0, 0, 0]\n'
    worn_ball = ball.replace('clearance = "0.1 mm"\n', tables, 1)
    assert worn_ball != ball
    with pytest.raises(jointgap.ModelError, match="bearing_wear"):
        jointgap.loads(worn_ball).simulate(0.01)


def test_the_3d_founding_case_wears_as_the_planar_one() -> None:
    """The same impacts (the runs agree to 1e-6 of the slider's acceleration) lay the
    same wear: each journal end's force over its half of the length is the planar
    joint's over the whole, so a share counted twice or not at all doubles or halves
    the 3D grids. Agreement to the runs' different steps (the wear is a trapezoid over
    each run's own steps)."""
    planar, spatial = founding_pair()
    flat = planar.simulate(0.06, wear_cells=72, **TIGHT).wear["rod_slider"]
    ends = spatial.simulate(0.06, wear_cells=72, **TIGHT).wear["rod_slider"]
    assert flat["load_distance"] > 0.02
    assert ends["load_distance"] == pytest.approx(flat["load_distance"], rel=1e-5)
    for part in ("bearing", "journal"):
        a, b = np.asarray(flat[f"{part}_depth"]), np.asarray(ends[f"{part}_depth"])
        assert np.abs(a - b).max() < 1e-3 * a.max(), part
        assert ends[f"{part}_volume"] == pytest.approx(flat[f"{part}_volume"], rel=1e-5)


def test_a_worn_3d_journal_runs_as_the_planar_one() -> None:
    """A bearing worn into a pocket 20 um deep at 172 deg and a journal worn 10 um at one
    side: the 3D joint's worn ends give the planar worn joint's run (the same impacts,
    the slider's acceleration within 1e-6, the ends' forces summing to the planar
    joint's), and the worn run differs from the round one."""
    theta = np.arange(72) * 2 * math.pi / 72
    tables = {
        "bearing_wear": list(2e-5 * np.maximum(0, np.cos(theta - 3.0)) ** 2),
        "journal_wear": list(1e-5 * np.maximum(0, np.cos(theta - 1.0)) ** 4),
    }
    planar, spatial = (m.simulate(0.06, **TIGHT) for m in founding_pair(**tables))
    assert planar.ok and spatial.ok
    a, b = planar["slider.ax"], spatial["slider.ax"]
    assert np.sqrt(np.mean((a - b) ** 2)) / (a.max() - a.min()) < 1e-6
    f = spatial["rod_slider.p1.fn"] + spatial["rod_slider.p2.fn"]
    assert np.abs(f - planar["rod_slider.fn"]).max() < 1e-5 * planar["rod_slider.fn"].max()
    assert len(spatial.impacts["rod_slider.p1"]) == len(planar.impacts["rod_slider"]) >= 10
    round_ = founding_pair()[1].simulate(0.06, **TIGHT)
    assert np.abs(round_["slider.ax"] - b).max() > 0.01 * (b.max() - b.min())


def test_a_tilted_journal_wears_by_the_load_of_each_end() -> None:
    """The 3D founding case with its journal tilted 10 mrad in the rod: its ends carry
    different loads (one about four times the other's impulse), and the run's `int F_n
    ds` equals the integral of both ends' `fn |slip|` over the output samples (to their
    trapezoid's error), and each part's worn volume per unit `k` equals it (Archard's law
    keeps the volume whatever the pressure's shape)."""
    data = jointgap.load(ROOT / "examples" / "slider_crank_clearance_3d.toml").to_dict()
    next(j for j in data["joints"] if j["name"] == "rod_slider")["axis_j"] = [0.0, 0.01, 1.0]
    r = jointgap.Model.from_dict(data).simulate(
        0.1, rate=200_000, rtol=1e-9, atol=1e-12, wear_cells=72
    )
    assert r.ok
    ends = [(r[f"rod_slider.p{i}.fn"], r[f"rod_slider.p{i}.slip"]) for i in (1, 2)]
    impulses = sorted(np.trapezoid(f, r.time) for f, _ in ends)
    assert impulses[1] > 2 * impulses[0] > 0
    sampled = np.trapezoid(sum(f * slip for f, slip in ends), r.time)
    wear = r.wear["rod_slider"]
    assert wear["load_distance"] == pytest.approx(sampled, rel=1e-3)
    for part in ("bearing", "journal"):
        assert wear[f"{part}_volume"] == pytest.approx(wear["load_distance"], rel=1e-12)


def test_the_command_wears_the_3d_founding_case_as_the_planar_one(tmp_path: Path) -> None:
    """`jointgap wear` on the founding case in 3D, 300 cycles with the default
    coefficient: its files, and the deepest wear of each part within 1 % of the planar
    case's prediction at the journal's length (2.46 um of the bearing, 3.77 um of the
    journal when measured); the peak contact force the sum of the two ends'."""
    out = tmp_path / "wear"
    model = ROOT / "examples" / "slider_crank_clearance_3d.toml"
    assert main(["wear", str(model), "--cycles", "300", "--out", str(out)]) == 0
    for name in (
        "history.csv",
        "profiles_rod_slider.csv",
        "wear_profile_rod_slider.png",
        "report.html",
    ):
        assert (out / name).stat().st_size > 0, name
    joint = json.loads((out / "summary.json").read_text())["joints"]["rod_slider"]
    planar = predict_wear(
        jointgap.load(ROOT / "examples" / "slider_crank_clearance.toml"), 300, length="20 mm"
    )
    _, bearing, journal = planar.profiles["rod_slider"][-1]
    assert joint["max_bearing_depth"] == pytest.approx(bearing.max(), rel=0.01)
    assert joint["max_journal_depth"] == pytest.approx(journal.max(), rel=0.01)
    assert 1e-6 < joint["max_bearing_depth"] < 1e-5
    with pytest.raises(ValueError, match="its own length"):
        predict_wear(jointgap.load(model), 300, length="10 mm")
    history = pd.read_csv(out / "history.csv")
    assert history.peak_contact_force.iloc[0] == pytest.approx(
        planar.history.peak_contact_force.iloc[0], rel=0.01
    )
