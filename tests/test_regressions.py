"""Regression tests, one per fixed bug, named after it."""

from __future__ import annotations

import importlib

import jointgap
import numpy as np
import pytest
from jointgap.cli import main


def test_jointgap_identify_stays_the_function_after_its_module_is_imported() -> None:
    importlib.import_module("jointgap.identify")
    assert callable(jointgap.identify) and jointgap.identify.__name__ == "identify"
    assert jointgap.Parameter.parse("rod_slider.mu_d=0.01:0.1").high == 0.1


def test_saving_a_model_creates_its_folder(tmp_path) -> None:
    model = jointgap.load("examples/slider_crank_ideal.toml")
    path = tmp_path / "new" / "deeper" / "model.toml"
    model.save(path)
    assert jointgap.load(path).to_dict() == model.to_dict()


def test_calibrate_inverse_runs_at_the_given_c_max(capsys, engine) -> None:
    """It used to take V_avg from a run at the model's own C_max, whatever --c-max said."""
    v_avg = []
    for c_max in ("15000", "20000"):
        args = ["calibrate", "examples/slider_crank_clearance.toml", "--c-max", c_max]
        assert main([*args, "--t-end", "0.5", "--rtol", "1e-6", "--atol", "1e-9"]) == 0
        v_avg.append(float(capsys.readouterr().out.split("V_avg")[1].split()[0]))
    assert v_avg[0] != pytest.approx(v_avg[1], rel=1e-3)


def test_mode_channel_shows_impact_at_a_located_onset_after_projection(engine) -> None:
    """Right after an onset, projection may leave the penetration at -1e-13: the mode
    channel follows the located contact state, so the onset sample reads 1 (impact)."""
    r = jointgap.load("examples/slider_crank_clearance.toml").simulate(
        0.5, rate=10_000, every_step=True, rtol=1e-6, atol=1e-9
    )
    mode = r["rod_slider.mode"]
    for impact in r.impacts["rod_slider"]:
        k = int(abs(r.time - impact.onset_time).argmin())
        assert r.time[k] == pytest.approx(impact.onset_time, abs=1e-12)
        assert mode[k] == 1, impact


def test_measured_record_and_tables_create_their_folders(tmp_path) -> None:
    from jointgap.measured import MeasuredSignal, read_measured

    signal = MeasuredSignal(np.array([0.0, 1.0, 2.0]), np.array([1.0, 2.0, 3.0]), "a", "m", "test")
    path = tmp_path / "new" / "record.csv"
    signal.to_csv(path)
    assert np.array_equal(read_measured(path, "a").values, signal.values)
