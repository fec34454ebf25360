"""Running a study locally: the tables, metrics equal to those computed from each case's
own time series, failed cases with their reasons, restarts that run only what is
missing, and the figures."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import jointgap
import numpy as np
import pandas as pd
import pytest
from jointgap.cli import main
from jointgap.study import Case, Outcome, load_results, load_series, load_study, run_study
from jointgap.study.metrics import ideal_counterpart
from jointgap.study.plots import sensitivity
from jointgap.study.store import Store
from study_files import CLEARANCE, SMALL, grid_study, tiny, write_study

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
    # The written tables carry each column's SI unit in its header.
    csv = pd.read_csv(out / "cases.csv", keep_default_na=False, na_values=[""])
    parquet = pd.read_parquet(out / "cases.parquet")
    headers = [
        "case",
        "rod_slider.clearance [m]",
        "motor.speed [rad/s]",
        "rod_slider.mu_d",
        "peak_contact_force [N]",
        "impacts",
        "peak_slider_acceleration [m/s^2]",
        "rms_slider_acceleration [m/s^2]",
        "max_torque [N*m]",
        "min_torque [N*m]",
        "mean_slider_x [m]",
        "deviation_rms [m/s^2]",
        "deviation_peak [m/s^2]",
        "free_flight",
        "contact",
        "status",
        "reason",
        "run_time_s [s]",
    ]
    assert list(csv.columns) == list(parquet.columns) == headers
    assert list(study["units"]) == [*PARAMETERS, *METRICS, "run_time_s"]
    pd.testing.assert_frame_equal(parquet.set_axis(table.columns, axis=1), table)
    numeric = [*PARAMETERS, *METRICS, "run_time_s"]
    csv = csv.set_axis(table.columns, axis=1)
    np.testing.assert_array_equal(csv[numeric].to_numpy(float), table[numeric].to_numpy(float))
    assert list(csv["reason"].fillna("")) == list(table["reason"])
    pd.testing.assert_frame_equal(load_results(out), table)
    copy = out.parent / "tables_only"  # the table alone, without the log
    copy.mkdir()
    (copy / "cases.parquet").write_bytes((out / "cases.parquet").read_bytes())
    pd.testing.assert_frame_equal(load_results(copy), table)
    # A table written before headers carried units reads the same.
    old = out.parent / "old_table"
    old.mkdir()
    table.to_parquet(old / "cases.parquet", index=False)
    pd.testing.assert_frame_equal(load_results(old), table)


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
        # mode fractions: the engine's time in each mode over the steps, which the
        # samples held from one to the next resolve to a sample per change of mode
        mode, dt = s["rod_slider.mode"].to_numpy()[:-1], np.diff(t)
        within = np.count_nonzero(np.diff(s["rod_slider.mode"].to_numpy())) * dt.max() / dt.sum()
        assert row["free_flight"] == pytest.approx(dt[mode == 0].sum() / dt.sum(), abs=within)
        assert row["contact"] == pytest.approx(dt[mode == 2].sum() / dt.sum(), abs=within)
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
        # (RMS over time: the trapezoidal mean of d^2 over the samples)
        mean = np.sum(np.diff(t) * (d[:-1] ** 2 + d[1:] ** 2)) / (2 * (t[-1] - t[0]))
        assert row["deviation_rms"] == pytest.approx(np.sqrt(mean), rel=1e-12)
        assert row["deviation_peak"] == pytest.approx(np.max(np.abs(d)), rel=1e-12)


def test_interrupted_study_runs_only_the_missing_cases(
    tmp_path, engine, monkeypatch, capsys
) -> None:
    """Ctrl-C, then a crash, then a rerun: each case runs exactly once. The Ctrl-C and
    the crash come at a stored case the test chooses (its store does them), never after
    a delay."""
    path = write_study(tmp_path, grid_study(12))
    out = tmp_path / "out"
    log = out / "cases.jsonl"
    add = Store.add

    def ctrl_c_at_third(self: Store, outcome: Outcome) -> None:
        add(self, outcome)
        if len(self.done) == 3:
            signal.raise_signal(signal.SIGINT)

    # Ctrl-C: the case running is finished and stored, the table written, exit 130
    monkeypatch.setattr(Store, "add", ctrl_c_at_third)
    command = ["study", str(path), "--out", str(out), "--workers", "1", "--no-progress"]
    assert main(command) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("jointgap: interrupted: the cases that ended are stored")
    first = _lines(log)
    assert 3 <= first <= 4  # the one worker may have started a fourth case
    assert len(pd.read_csv(out / "cases.csv")) == first
    monkeypatch.setattr(Store, "add", add)
    # the process killed outright after two more cases, then a line cut short as by a crash
    crash = f"""
import os, signal
from jointgap.study import store, run_study
add = store.Store.add
def add_then_die(self, outcome):
    add(self, outcome)
    if len(self.done) == {first + 2}:
        os.kill(os.getpid(), signal.SIGKILL)
store.Store.add = add_then_die
run_study({str(path)!r}, {str(out)!r}, workers=1, progress=None)
"""
    killed = subprocess.run([sys.executable, "-c", crash], timeout=600)
    assert killed.returncode == -signal.SIGKILL
    stored = _lines(log)
    assert stored == first + 2
    with open(log, "a") as f:
        f.write('{"case": 11, "values": {"rod_slider.cl')

    run = run_study(path, out, progress=None)  # the killed run's lock is gone with it
    assert (run.skipped, run.ran) == (stored, 12 - stored)
    lines = log.read_text().splitlines()
    assert lines[stored].startswith('{"case": 11, "values"')  # skipped when read
    logged = [json.loads(line)["case"] for k, line in enumerate(lines) if k != stored]
    assert sorted(logged) == list(range(12))  # each case run exactly once
    whole = run_study(path, tmp_path / "whole", progress=None).table
    pd.testing.assert_frame_equal(
        run.table.drop(columns="run_time_s"), whole.drop(columns="run_time_s")
    )


def test_a_second_ctrl_c_keeps_the_running_cases(monkeypatch, capsys) -> None:
    """Ctrl-C while cases run drops the cases not started and stores those running;
    Ctrl-C again while they end drops none of them. The cases here wait for the test's
    events (released once the study waits for them), so what runs when is fixed."""
    from jointgap.study import execute

    started = {k: threading.Event() for k in range(6)}
    release = threading.Event()

    def case(c: Case) -> Outcome:
        started[c.case].set()
        if c.case != 0:
            release.wait()
        return Outcome(c.case, {}, {}, "finished", "", 0.0)

    stored: list[int] = []

    def store(outcome: Outcome) -> None:
        stored.append(outcome.case)
        if outcome.case == 0:  # cases 1 and 2 run on the other threads
            started[1].wait()
            started[2].wait()
            signal.raise_signal(signal.SIGINT)
        elif len(stored) == 2:
            signal.raise_signal(signal.SIGINT)  # again, while the others end

    waiting = execute._interrupts_wait

    @contextmanager
    def release_when_waiting(running: int) -> Iterator[None]:
        with waiting(running):  # the cases not started are dropped by now
            release.set()
            yield

    monkeypatch.setattr(execute, "run_case", case)
    monkeypatch.setattr(execute, "_interrupts_wait", release_when_waiting)
    cases = [Case(k, {}, {}, {}, ()) for k in range(6)]
    with pytest.raises(KeyboardInterrupt):
        execute.run_local(cases, 3, store)
    ran = sorted(k for k, e in started.items() if e.is_set())
    assert sorted(stored) == ran and {0, 1, 2} <= set(ran) and len(ran) < 6
    assert "waiting for the" in capsys.readouterr().err
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_two_runs_on_one_folder_are_refused(tmp_path, engine) -> None:
    path = write_study(tmp_path, grid_study(2))
    study = load_study(path)
    first = Store(tmp_path / "out", study.to_dict())
    try:
        holder = (tmp_path / "out" / "study.lock").read_text()
        assert f"process {os.getpid()}" in holder
        with pytest.raises(ValueError, match=r"out is in use by another study run \(host "):
            run_study(study, tmp_path / "out", progress=None)
    finally:
        first.close()
    assert run_study(study, tmp_path / "out", progress=None).complete


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
