"""Running a study locally: the tables, metrics equal to those computed from each case's
own time series, failed cases with their reasons, restarts that run only what is
missing, and the figures."""

from __future__ import annotations

import json
import math
import signal
import subprocess
import sys
import time
from pathlib import Path

import jointgap
import numpy as np
import pandas as pd
import pytest
from jointgap.cli import main
from jointgap.study import load_results, load_series, load_study, run_study
from jointgap.study.metrics import ideal_counterpart
from jointgap.study.plots import sensitivity
from study_files import CLEARANCE, SMALL, grid_study, tiny, write_study

JOINTGAP = Path(sys.executable).parent / "jointgap"
PARAMETERS = ["rod_slider.clearance", "motor.speed", "rod_slider.mu_d"]
METRICS = [
    "peak_contact_force",
    "impacts",
    "peak_slider_acceleration",
    "rms_slider_acceleration",
    "max_torque",
    "min_torque",
    "mean_slider_x",
    "deviation_rms",
    "deviation_peak",
    "free_flight",
    "contact",
]


@pytest.fixture(scope="module")
def small(tmp_path_factory) -> tuple[Path, pd.DataFrame]:
    """The small study (tests/study_files.py), run once on 2 threads."""
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    folder = tmp_path_factory.mktemp("small")
    path = write_study(folder, SMALL)
    run = run_study(path, folder / "out", workers=2, progress=None)
    assert run.ran == 12 and run.skipped == 0 and run.complete
    return folder / "out", run.table


def test_table_columns_and_files(small) -> None:
    out, table = small
    assert list(table.columns) == ["case", *PARAMETERS, *METRICS, "status", "reason", "run_time_s"]
    assert list(table["case"]) == list(range(12))
    assert table["impacts"].dtype == "Int64"
    study = json.loads((out / "study.json").read_text())
    assert {k: study[k] for k in ("name", "sampling", "n_cases", "metrics")} == {
        "name": "small",
        "sampling": "monte_carlo",
        "n_cases": 12,
        "metrics": METRICS,
    }
    assert [(p["path"], p["kind"]) for p in study["parameters"]] == [
        ("rod_slider.clearance", "values"),
        ("motor.speed", "values"),
        ("rod_slider.mu_d", "uniform"),
    ]
    assert study["base_model"] == str(CLEARANCE)
    csv = pd.read_csv(out / "cases.csv", keep_default_na=False, na_values=[""])
    parquet = pd.read_parquet(out / "cases.parquet")
    pd.testing.assert_frame_equal(parquet, table)
    numeric = [*PARAMETERS, *METRICS, "run_time_s"]
    np.testing.assert_array_equal(csv[numeric].to_numpy(float), table[numeric].to_numpy(float))
    assert list(csv["reason"].fillna("")) == list(table["reason"])
    pd.testing.assert_frame_equal(load_results(out), table)
    copy = out.parent / "tables_only"  # the table alone, without the log
    copy.mkdir()
    (copy / "cases.parquet").write_bytes((out / "cases.parquet").read_bytes())
    pd.testing.assert_frame_equal(load_results(copy), table)


def test_failed_cases_keep_their_reason_and_the_others_finish(small) -> None:
    _, table = small
    bad = table["rod_slider.clearance"] == 8e-3
    assert list(table.loc[bad, "status"]) == ["failed"] * 4
    assert list(table.loc[~bad, "status"]) == ["finished"] * 8
    for reason in table.loc[bad, "reason"]:
        assert "clearance = 0.008 m is not smaller than bearing_radius = 0.0075 m" in reason
    assert set(table.loc[~bad, "reason"]) == {""}
    assert table.loc[bad, METRICS].isna().all().all()
    assert table.loc[~bad, METRICS].notna().all().all()
    # a faster crank hits harder
    finished = table[~bad]
    by_speed = finished.groupby("motor.speed")["peak_contact_force"].max()
    assert by_speed.iloc[1] > by_speed.iloc[0] > 100.0


def test_integrator_giving_up_is_a_failed_case(tmp_path, engine) -> None:
    text = f"""
    [study]
    model = "{CLEARANCE}"
    t_end = "0.2 s"
    max_steps = 5000
    [parameters]
    "motor.speed" = ["100 rpm", "3000 rpm"]
    [metrics]
    impacts = "impacts"
    """
    run = run_study(write_study(tmp_path, text), tmp_path / "out", progress=None)
    assert list(run.table["status"]) == ["finished", "failed"]
    assert run.failed == 1
    assert run.table.loc[1, "reason"].startswith("failed at t = ")
    assert "step budget of 5000 steps spent" in run.table.loc[1, "reason"]
    assert run.table.loc[0, "impacts"] > 0


def test_metrics_equal_those_of_the_cases_own_time_series(tmp_path, engine) -> None:
    path = write_study(tmp_path, grid_study(3, extra="time_series = true"))
    study = load_study(path)
    table = run_study(study, tmp_path / "out", progress=None).table
    for case, values in enumerate(study.cases()):
        row = table.loc[case]
        s = load_series(tmp_path / "out", case)
        t = s["time"].to_numpy()
        ax = s["slider.ax"].to_numpy()
        torque = s["motor.torque"].to_numpy()
        assert row["peak_slider_acceleration"] == np.max(np.abs(ax))
        late = t >= 0.02
        assert row["rms_slider_acceleration"] == np.sqrt(np.mean(ax[late] ** 2))
        assert row["max_torque"] == torque.max() and row["min_torque"] == torque.min()
        middle = (t >= 0.01) & (t <= 0.03)
        assert row["mean_slider_x"] == np.mean(s["slider.x"].to_numpy()[middle])
        # mode fractions: sample-and-hold over the samples
        mode, dt = s["rod_slider.mode"].to_numpy()[:-1], np.diff(t)
        assert row["free_flight"] == pytest.approx(dt[mode == 0].sum() / dt.sum(), rel=1e-12)
        assert row["contact"] == pytest.approx(dt[mode == 2].sum() / dt.sum(), rel=1e-12)
        # the contact force peak and the impacts include what happens between samples
        fn = s["rod_slider.fn"].to_numpy()
        assert row["peak_contact_force"] >= fn.max() > 0.0
        onsets = np.count_nonzero((mode[:-1] == 0) & (mode[1:] != 0))
        assert row["impacts"] >= onsets > 0
        # the deviation against the ideal mechanism, run here directly
        model = jointgap.variants.with_parameters(
            jointgap.Model.from_dict(study.model_of(values)), values
        )
        ideal = jointgap.Model.from_dict(ideal_counterpart(model.to_dict()))
        d = ax - ideal.simulate(0.05, rate=2000)["slider.ax"]
        assert row["deviation_rms"] == pytest.approx(np.sqrt(np.mean(d**2)), rel=1e-12)
        assert row["deviation_peak"] == pytest.approx(np.max(np.abs(d)), rel=1e-12)


def test_interrupted_study_runs_only_the_missing_cases(tmp_path, engine) -> None:
    path = write_study(tmp_path, grid_study(12, t_end="0.1 s"))
    out = tmp_path / "out"
    log = out / "cases.jsonl"
    command = [str(JOINTGAP), "study", str(path), "--out", str(out), "--workers", "1"]

    def interrupt(sig: int, after: int) -> subprocess.Popen[str]:
        """Starts the study and sends ``sig`` once ``after`` more cases are logged."""
        before = _lines(log)
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 60
        while _lines(log) < before + after and time.monotonic() < deadline:
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.01)
        proc.send_signal(sig)
        proc.wait(timeout=60)
        return proc

    # Ctrl-C: the case running is finished and stored, the table written, exit 130
    stopped = interrupt(signal.SIGINT, 2)
    assert stopped.returncode == 130
    assert "interrupted: the cases that ended are stored" in stopped.stderr.read()
    first = _lines(log)
    assert 3 <= first < 12
    assert len(pd.read_csv(out / "cases.csv")) == first
    # the client killed outright, then a line cut short as by a crash
    interrupt(signal.SIGKILL, 2)
    stored = _lines(log)
    assert first + 2 <= stored < 12
    with open(log, "a") as f:
        f.write('{"case": 11, "values": {"rod_slider.cl')

    run = run_study(path, out, progress=None)
    assert (run.skipped, run.ran) == (stored, 12 - stored)
    lines = log.read_text().splitlines()
    assert lines[stored].startswith('{"case": 11, "values"')  # skipped when read
    logged = [json.loads(line)["case"] for k, line in enumerate(lines) if k != stored]
    assert sorted(logged) == list(range(12))  # each case run exactly once
    whole = run_study(path, tmp_path / "whole", progress=None).table
    pd.testing.assert_frame_equal(
        run.table.drop(columns="run_time_s"), whole.drop(columns="run_time_s")
    )


def test_another_study_in_the_same_folder_is_refused(tmp_path, engine) -> None:
    run_study(write_study(tmp_path, grid_study(2)), tmp_path / "out", progress=None)
    with pytest.raises(ValueError, match="holds another study .*differs in n_cases, parameters"):
        run_study(write_study(tmp_path, grid_study(3)), tmp_path / "out", progress=None)


def test_cli_study_and_study_plot(tmp_path, capsys, engine) -> None:
    grid = tiny('"rod_slider.clearance" = ["0.2 mm", "0.5 mm"]\n"motor.speed" = [300, 600]')
    path = write_study(tmp_path, grid)
    assert main(["study", str(path), "--out", str(tmp_path / "g"), "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "study      study (" in printed
    assert "4 cases, rod_slider.clearance (2) x motor.speed (2)" in printed
    assert "ran        4 cases" in printed
    assert main(["study-plot", str(tmp_path / "g"), "--format", "png", "svg"]) == 0
    names = sorted(p.name for p in (tmp_path / "g" / "figures").iterdir())
    stems = [
        f"{m}_{kind}" for m in METRICS[:4:3] for kind in ("heatmap", "vs_rod_slider_clearance")
    ]
    assert names == sorted(f"{s}.{f}" for s in stems for f in ("png", "svg"))
    assert main(["study", str(path), "--out", str(tmp_path / "g")]) == 0  # nothing to run
    assert "ran        0 cases" in capsys.readouterr().out
    assert main(["study-plot", str(tmp_path / "g"), "--x", "gravity"]) == 1
    assert "--x gravity: not a grid parameter" in capsys.readouterr().err

    drawn = '"rod_slider.clearance" = { distribution = "uniform", low = "0.2 mm", high = "0.5 mm" }'
    path = write_study(tmp_path, tiny(drawn, "samples = 4"), "mc.toml")
    assert main(["study", str(path), "--out", str(tmp_path / "mc"), "--no-progress"]) == 0
    assert (
        "4 cases, 4 monte carlo draws of rod_slider.clearance (uniform)" in capsys.readouterr().out
    )
    assert main(["study-plot", str(tmp_path / "mc")]) == 0
    names = sorted(p.name for p in (tmp_path / "mc" / "figures").iterdir())
    assert names == [
        f"{METRICS[0]}_histogram.png",
        f"{METRICS[3]}_histogram.png",
        "sensitivity.png",
    ]


def test_sensitivity_is_the_rank_correlation() -> None:
    study = {
        "parameters": [{"path": "a", "kind": "uniform"}, {"path": "b", "kind": "normal"}],
        "metrics": ["m"],
    }
    a = np.linspace(0.0, 1.0, 9)
    b = np.array([3.0, 1.0, 4.0, 1.5, 5.0, 9.0, 2.0, 6.0, 5.5])
    table = pd.DataFrame({"a": a, "b": b, "m": np.exp(5 * a), "status": "finished"})
    rho = sensitivity(table, study)
    assert rho.loc["a", "m"] == pytest.approx(1.0)
    ranks_b = pd.Series(b).rank().to_numpy()
    expected = np.corrcoef(ranks_b, np.arange(1, 10))[0, 1]
    assert rho.loc["b", "m"] == pytest.approx(expected)
    table.loc[0, "status"] = "failed"
    table.loc[0, "m"] = math.nan
    assert sensitivity(table, study).loc["a", "m"] == pytest.approx(1.0)


def _lines(path: Path) -> int:
    """Complete lines in a file (0 when it does not exist)."""
    return path.read_text().count("\n") if path.exists() else 0
