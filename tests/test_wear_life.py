"""Wear over life (:func:`jointgap.wear.predict_wear`, ``jointgap wear``): the loop that
scales simulated cycles' wear into worn profiles, against Archard's closed form for a
pressed journal, against simulating every cycle, converging as its tolerance tightens,
resuming where it was interrupted; the command's files (docs/wear.md, "Over life")."""

from __future__ import annotations

import json
import math
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap.cli import main
from jointgap.wear import WearStep, predict_wear, resolve_coefficient, wear_pairs
from pressed_journal import LENGTH, LOAD, PERIOD, R_B, R_J, pressed_journal


def test_coefficients_by_name_and_with_units() -> None:
    pairs = wear_pairs()
    assert {"steel_brass_dry", "steel_bronze_dry", "steel_steel_dry"} <= set(pairs)
    assert resolve_coefficient("steel_steel_dry") == (
        pairs["steel_steel_dry"]["coefficient"],
        "steel_steel_dry",
    )
    assert resolve_coefficient(None)[1] == "steel_brass_dry"
    assert resolve_coefficient("1e-4 mm^3/(N*m)")[0] == pytest.approx(1e-13)
    with pytest.raises(ValueError, match="steel_brass_dry"):
        resolve_coefficient("5 N")


@pytest.mark.parametrize("dimension", [2, 3])
def test_a_pressed_journal_wears_as_archards_closed_form(dimension: int) -> None:
    """Constant load and speed: the wear rate does not change as the bearing wears (the
    pocket stays under the load, the pressure is the nominal Hertz one), so the loop's
    steps grow while its estimate stays exact. After N cycles, 36 cells of 10 deg, the
    loaded cell (270 deg) holds the pressure averaged over its arc times the sliding
    distance, `N k F / (L R_B dtheta) 2 pi R_J`; the journal wears uniformly `N k F / L`;
    each part loses the volume `N k F 2 pi R_J`. The same in 3D, a clearance_cylindrical
    joint along z: its two ends' halves add up to the whole journal."""
    k, cycles, cells = 3.7e-15, 2000.0, 36
    p = predict_wear(
        pressed_journal(dimension), cycles, coefficient=k, cells=cells, period=PERIOD, warmup=PERIOD
    )
    assert p.status == "finished", p.message
    assert p.cycles == pytest.approx(cycles)
    _, bearing, journal = p.profiles["bearing"][-1]
    dtheta = 2 * math.pi / cells
    spot = cycles * k * LOAD / (LENGTH * R_B * dtheta) * 2 * math.pi * R_J
    assert bearing[27] == pytest.approx(spot, rel=2e-3)
    assert bearing.max() == bearing[27]
    assert journal == pytest.approx(cycles * k * LOAD / LENGTH, rel=2e-3)
    last = p.history[p.history.cycles == p.history.cycles.max()].iloc[0]
    volume = cycles * k * LOAD * 2 * math.pi * R_J
    assert last.bearing_volume == pytest.approx(volume, rel=2e-3)
    assert last.journal_volume == pytest.approx(volume, rel=2e-3)
    assert last.clearance == pytest.approx(0.5e-3 + bearing.max() + journal.max())
    # The steps grew: far fewer runs than cycles.
    assert p.runs < 40


def test_extrapolation_agrees_with_every_cycle_on_the_founding_case(examples) -> None:
    """The founding slider-crank (10 mm bearing length), a coefficient large enough to
    wear the brass bearing by about a micrometre in 10 cycles: extrapolating the wear of
    simulated cycles agrees with wearing the profiles cycle by cycle, to within the
    cycle-to-cycle scatter of the impacts (a few per cent of the wear); the history keeps
    the peak contact force and the slider's peak acceleration."""
    model = jointgap.load(examples / "slider_crank_clearance.toml")
    kwargs = {"coefficient": 3e-12, "cells": 90, "length": "10 mm"}
    every = predict_wear(model, 10, every_cycle=True, **kwargs)
    assert every.status == "finished" and every.runs == 11
    deepest = every.profiles["rod_slider"][-1][1].max()
    assert 2e-7 < deepest < 5e-6
    for tolerance in (0.2, 0.05):
        p = predict_wear(model, 10, tolerance=tolerance, **kwargs)
        assert p.profiles["rod_slider"][-1][1].max() == pytest.approx(deepest, rel=0.05)
    # A hundred times the cycles at a hundredth of the coefficient: the same wear, and
    # the steps grow with the predicted depth, so about the same number of runs.
    many = predict_wear(model, 1000, tolerance=0.05, **{**kwargs, "coefficient": 3e-14})
    assert many.profiles["rod_slider"][-1][1].max() == pytest.approx(deepest, rel=0.05)
    assert many.runs < 40
    assert every.watch == "slider.ax"
    first = every.history.iloc[0]
    assert first.peak_contact_force > 1000 and first.peak_watch > 500


def test_the_founding_case_wears_through_a_tenth_of_its_clearance(examples) -> None:
    """The founding slider-crank with the default coefficient (dry steel in brass), grid
    and tolerance through 1500 cycles: it finishes (the worn journal rests on each rim of
    its worn pockets, so the runs do not chatter), the clearance grows by about a tenth,
    the wear lies where the rod pushes and pulls the slider along its guide (the
    bearing's 0 and 180 deg) and not across it, and the peak contact force grows with
    the wear (docs/wear.md, "Over life")."""
    model = jointgap.load(examples / "slider_crank_clearance.toml")
    p = predict_wear(model, 1500, length="10 mm")
    assert p.status == "finished", p.message
    history = p.history
    growth = history.clearance.iloc[-1] / history.clearance.iloc[0] - 1
    assert 0.03 < growth < 0.3
    angles, (_, bearing, _) = np.degrees(p.angles), p.profiles["rod_slider"][-1]
    along = bearing[(np.abs(((angles + 180) % 360) - 180) < 20) | (np.abs(angles - 180) < 20)]
    across = bearing[(np.abs(angles - 90) < 20) | (np.abs(angles - 270) < 20)]
    assert across.max() < 0.2 * along.min()
    assert history.peak_contact_force.iloc[-1] > 1.2 * history.peak_contact_force.iloc[0]


def test_an_interrupted_prediction_resumes_where_it_stopped(tmp_path: Path) -> None:
    kwargs = {
        "coefficient": 3.7e-15,
        "cells": 36,
        "period": PERIOD,
        "warmup": PERIOD,
        "first_step": 100,
        "out": tmp_path,
    }
    whole = predict_wear(pressed_journal(), 2000.0, **{**kwargs, "out": tmp_path / "whole"})
    seen: list[WearStep] = []

    def stop_after_two(step: WearStep) -> None:
        seen.append(step)
        if len(seen) == 2:
            raise KeyboardInterrupt

    first = predict_wear(pressed_journal(), 2000.0, progress=stop_after_two, **kwargs)
    assert first.status == "interrupted" and first.cycles == pytest.approx(seen[-1].cycles)
    state = json.loads((tmp_path / "state.json").read_text())
    assert state["cycles"] == pytest.approx(seen[-1].cycles)
    resumed = predict_wear(pressed_journal(), 2000.0, **kwargs)
    assert resumed.status == "finished"
    np.testing.assert_allclose(
        resumed.profiles["bearing"][-1][1], whole.profiles["bearing"][-1][1], rtol=1e-12
    )
    assert list(resumed.history.cycles) == list(whole.history.cycles)
    with pytest.raises(ValueError, match="other inputs"):
        predict_wear(pressed_journal(), 1000.0, **kwargs)


def test_a_clearance_limit_stops_the_prediction() -> None:
    p = predict_wear(
        pressed_journal(),
        1e6,
        coefficient=3.7e-15,
        cells=36,
        period=PERIOD,
        warmup=PERIOD,
        clearance_limit="0.505 mm",
    )
    assert p.status == "limit"
    # The clearance grows by the spot's and the journal's wear per cycle.
    dtheta = 2 * math.pi / 36
    per_cycle = 3.7e-15 * LOAD * (2 * math.pi * R_J / (LENGTH * R_B * dtheta) + 1 / LENGTH)
    assert p.cycles_to_limit == pytest.approx(5e-6 / per_cycle, rel=5e-3)


def test_bad_input_is_named() -> None:
    model = pressed_journal()
    with pytest.raises(ValueError, match="cycles"):
        predict_wear(model, -1)
    data = model.to_dict()
    del data["joints"][2]["clearance"]["length"]
    with pytest.raises(jointgap.ModelError, match="length"):
        predict_wear(jointgap.Model.from_dict(data), 10, period=PERIOD, warmup=PERIOD)
    with pytest.raises(jointgap.ModelError, match="clearance_revolute"):
        predict_wear(model, 10, joints=["spin"], period=PERIOD, warmup=PERIOD)
    with pytest.raises(ValueError, match="not above"):
        predict_wear(model, 10, clearance_limit="0.4 mm", period=PERIOD, warmup=PERIOD)


def test_the_command_writes_its_tables_figures_and_report(tmp_path: Path, capsys) -> None:
    path = tmp_path / "pressed.toml"
    pressed_journal().save(path)
    out = tmp_path / "wear"
    status = main(
        [
            "wear",
            str(path),
            "--cycles",
            "500",
            "--coefficient",
            "3.7e-6 mm^3/(N*m)",
            "--cells",
            "36",
            "--period",
            f"{PERIOD} s",
            "--warmup",
            f"{PERIOD} s",
            "--out",
            str(out),
        ]
    )
    assert status == 0, capsys.readouterr().err
    for name in (
        "history.csv",
        "profiles_bearing.csv",
        "summary.json",
        "wear_history.png",
        "wear_profile_bearing.png",
        "report.html",
        "state.json",
    ):
        assert (out / name).stat().st_size > 0, name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["cycles"] == pytest.approx(500)
    assert summary["coefficient"] == pytest.approx(3.7e-15)
    page = (out / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 2
    printed = capsys.readouterr().out
    assert "deepest wear bearing" in printed
