"""Runs longer than the examples (issue 21, section 8): sample marks, options kept for the
ideal run, the end state, the step budget and the drift test, bulk reading and writing,
time-weighted statistics, the report and the comparison of long runs.

The tests marked ``slow`` run the founding case over 20 s and 60 s (100 and 300 crank
turns) through the commands of the CLI (run with --ideal, plot, report, check, converge,
calibrate, synthesize, compare, identify, study, study-plot); they run in ``make test``
too, at 1 kHz, a loose tolerance and few runs per command, so that what only shows on
long runs is caught there."""

from __future__ import annotations

import json
import math
import re
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from jointgap.cli import EXIT_NOT_CONVERGED, main
from jointgap.results import CSV_BLOCK, Result

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
CLEARANCE = str(EXAMPLES / "slider_crank_clearance.toml")
IDEAL = str(EXAMPLES / "slider_crank_ideal.toml")


def _model(name: str = "slider_crank_clearance.toml"):  # type: ignore[no-untyped-def]
    import jointgap

    return jointgap.load(EXAMPLES / name)


# --- 1. sample marks -------------------------------------------------------------------


def test_the_engine_marks_the_rate_samples_among_every_step(engine) -> None:
    model = _model()
    sampled = model.simulate(0.2, rate=1000)
    both = model.simulate(0.2, rate=1000, every_step=True)
    assert sampled.samples is None and len(sampled.sample_index) == 201
    assert both.samples is not None and len(both.time) > 2 * len(sampled.time)
    # The marked records are the rate samples, bit for bit: the same steps, the same
    # interpolation; nothing picks them by their time.
    k = both.sample_index
    assert np.array_equal(both.time[k], sampled.time)
    assert np.array_equal(both["slider.ax"][k], sampled["slider.ax"])
    # The marks survive saving and loading.
    loaded = Result.load(both.save(Path(pytest.importorskip("tempfile").mkdtemp())))
    assert np.array_equal(loaded.sample_index, k)


def test_converge_keeps_the_compared_channels_and_the_step_peaks(engine) -> None:
    from jointgap.convergence import check_convergence

    check = check_convergence(_model(), 0.1, rtol=1e-6, atol=1e-9, levels=1, rate=1000)
    run = check.runs[0]
    assert run.channels == ["slider.x", "slider.vx", "slider.ax", "rod_slider.fn", "motor.torque"]
    assert len(run.time) == 101 and run.options["step_peaks"]
    # The engine's peak over every step is at least the sampled one, and above it where
    # an impact's spike falls between samples.
    for c in run.channels:
        assert run.peaks[c] >= np.max(np.abs(run[c]))
    assert run.peaks["rod_slider.fn"] > 1.01 * np.max(run["rod_slider.fn"])


def test_converge_states_its_memory_need_when_large(capsys, engine) -> None:
    from jointgap.convergence import LARGE_MEMORY, memory_need

    model = _model()
    # 5 compared channels and the time, 600 002 samples (the end state too), 3 runs.
    assert memory_need(model, 60, "10 kHz", 2) == 8 * 3 * 600_002 * 6
    assert memory_need(model, 0.01, 1e9, 1) == 8 * 2 * 10_000_002 * 6 > LARGE_MEMORY
    args = ["converge", CLEARANCE, "--t-end", "0.01", "--rate", "1e9", "--levels", "1"]
    # A bad --peak-tol stops the command before any run: the statement comes first.
    assert main([*args, "--peak-tol", "-1"]) == 1
    assert "converge: the 2 runs keep about 960 MB of samples" in capsys.readouterr().err
    assert main([*args[:5], "1e7", "--levels", "1", "--peak-tol", "-1"]) == 1
    assert "keep about" not in capsys.readouterr().err


# --- 2. options lost or wrong ----------------------------------------------------------


def test_ideal_run_takes_stream_every_step_and_decimate(tmp_path, capsys, engine) -> None:
    out = tmp_path / "o"
    args = ["run", CLEARANCE, "--t-end", "0.05", "--rate", "10000", "--every-step"]
    args += ["--decimate", "7", "--stream", "--out", str(out), "--ideal", IDEAL]
    assert main(args) == 0
    for folder in (out, out / "ideal"):
        assert (folder / "results.parquet").exists() and not (folder / "results.csv").exists()
        summary = json.loads((folder / "summary.json").read_text())
        assert summary["options"]["every_step"] and summary["options"]["decimate"] == 7
        r = Result.load(folder)
        assert r.time[-1] == 0.05  # the end state is kept whatever the decimation
    text = capsys.readouterr().out
    assert "(every step and 10000 Hz, 1 record in 7 kept)" in text


@pytest.mark.parametrize("t_end, decimate", [(0.1, 7), (0.1234, 1), (0.1234, 3)])
def test_the_end_state_is_the_last_record(t_end, decimate, engine) -> None:
    model = _model()
    r = model.simulate(t_end, rate=1000, decimate=decimate)
    assert r.time[-1] == t_end
    # On the grid otherwise: every decimate-th sample of k / rate, then the end.
    grid = np.arange(0, math.floor(t_end * 1000 + 1e-9) + 1, decimate) / 1000
    assert np.allclose(r.time[: len(grid)], grid, rtol=0, atol=1e-15)
    assert len(r.time) == len(grid) + (0 if grid[-1] == t_end else 1)
    # The end state is the run's own: it agrees with a run sampled at the end time.
    end = model.simulate(t_end, rate=1.0 / t_end)
    assert r["slider.x"][-1] == pytest.approx(end["slider.x"][-1], abs=1e-12)


def test_the_default_step_budget_scales_with_the_run_and_says_how_to_raise_it(engine) -> None:
    from jointgap import _jointgap  # noqa: F401

    model = _model()
    short = model.simulate(0.05, rate=1000, max_steps=30)
    assert not short.ok and "--max-steps" in short.message and "max_steps" in short.message
    assert model.simulate(0.01, rate=1000).options["max_steps"] is None


def test_the_drift_test_follows_the_size_of_the_crank_angle(engine) -> None:
    # The founding case at 0.5 s as before the drift test became relative to the
    # coordinates' size (a fixed threshold of 0.01 atol: 21 impacts, peak force 3052.51 N,
    # 1400 projections in 8600 steps): the crank angle is 16 rad there, its rounding
    # below 0.01 atol, so the run stays essentially the same.
    r = _model().simulate(0.5, rate=1000)
    assert len(r.impacts["rod_slider"]) == 21
    peak = max(i.peak_force for i in r.impacts["rod_slider"])
    assert peak == pytest.approx(3052.51, rel=1e-4)
    assert r.stats["projections"] == pytest.approx(1400, rel=0.1)
    assert r.stats["accepted_steps"] == pytest.approx(8600, rel=0.01)


# --- 3. memory -------------------------------------------------------------------------


def test_load_reads_the_csv_in_bulk(tmp_path, engine) -> None:
    r = _model().simulate(1.0, rate=10_000)
    r.save(tmp_path)
    size = (tmp_path / "results.csv").stat().st_size
    tracemalloc.start()
    loaded = Result.load(tmp_path)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert np.array_equal(loaded.time, r.time) and np.array_equal(loaded.data, r.data)
    assert loaded.channels == r.channels
    # The values as doubles (8 bytes each) and nothing per value besides: the lists of
    # Python floats took 3.2 times the file's size.
    values = 8 * (r.data.size + len(r.time))
    assert peak < 1.2 * values + 1e6 and values < 0.5 * size


def test_calibrate_and_synthesize_record_only_what_they_use(tmp_path, monkeypatch, engine):
    import jointgap

    recorded: list[object] = []
    simulate = jointgap.Model.simulate

    def spy(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        result = simulate(self, *args, **kwargs)
        recorded.append(result.channels)
        return result

    monkeypatch.setattr(jointgap.Model, "simulate", spy)
    args = ["calibrate", CLEARANCE, "--restitution", "0.55", "--t-end", "0.1"]
    assert main([*args, "--rate", "1000", "--max-iterations", "2"]) in (0, EXIT_NOT_CONVERGED)
    assert recorded and all(c == ["rod_slider.fn"] for c in recorded)
    recorded.clear()
    out = tmp_path / "m.csv"
    args = ["synthesize", CLEARANCE, "--signal", "slider.ax", "--t-end", "0.1"]
    assert main([*args, "--out", str(out)]) == 0
    assert recorded == [["slider.ax"]]


def test_identify_records_only_what_it_uses(monkeypatch, engine) -> None:
    import jointgap
    from jointgap.identify import Parameter, identify
    from jointgap.measured import synthetic_record

    model = _model()
    record = synthetic_record(model.simulate(0.1, rate=10_000), "slider.ax", rate=5000, lag=0.0)
    recorded: list[object] = []
    simulate = jointgap.Model.simulate

    def spy(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        result = simulate(self, *args, **kwargs)
        recorded.append(result.channels)
        return result

    monkeypatch.setattr(jointgap.Model, "simulate", spy)
    reported: list[int] = []
    restitution = [Parameter.parse("rod_slider.restitution=0.3:0.95")]
    with pytest.raises(KeyError, match="no channel 'slider.acc'; close matches: .*slider.ax"):
        identify(model, record, "slider.acc", restitution, rate=1000)
    assert recorded == []  # named before any run
    fit = identify(
        model,
        record,
        "slider.ax",
        restitution,
        rate=1000,
        scan=2,
        max_evaluations=3,
        compare_options={"max_lag": 0.01},
        progress=lambda t: reported.append(t.trial),
    )
    # The bounds of the restitution's C_max read the impact list of runs recording the
    # contact mode at 10 Hz; every trial records the compared channel alone.
    assert set(map(tuple, recorded)) == {("rod_slider.mode",), ("slider.ax",)}
    assert recorded.count(["slider.ax"]) == len(fit.trials) <= 2 + 3 + 8
    # Each trial is reported once, even where the profile lands on a point run before.
    assert sorted(reported) == [t.trial for t in fit.trials]


# --- 4. writing ------------------------------------------------------------------------


def test_to_csv_writes_exact_values_in_blocks_with_progress(tmp_path, engine) -> None:
    r = _model().simulate(0.2, rate=2 * CSV_BLOCK / 0.2)
    calls: list[tuple[int, int]] = []
    r.to_csv(tmp_path / "r.csv", progress=lambda done, rows: calls.append((done, rows)))
    rows = len(r.time)
    assert calls[-1] == (rows, rows) and len(calls) == math.ceil(rows / CSV_BLOCK)
    header = (tmp_path / "r.csv").read_text().split("\n", 1)[0]
    assert header == ",".join(["time", *r.channels])
    back = np.loadtxt(tmp_path / "r.csv", delimiter=",", skiprows=1)
    assert np.array_equal(back[:, 0], r.time) and np.array_equal(back[:, 1:].T, r.data)


def test_writing_shows_its_progress_in_a_terminal(tmp_path, engine) -> None:
    from terminal import in_terminal

    # Three blocks of rows: a line after each, erased before the summary; the same line
    # for the simulation that compare writes beside its comparison.
    rows = 2 * CSV_BLOCK + 1
    out = tmp_path / "run"
    args = ["run", CLEARANCE, "--t-end", "0.2", "--rate", str(2 * CSV_BLOCK / 0.2)]
    session = in_terminal(*args, "--channel", "slider.ax", "--out", str(out))
    assert session.returncode == 0, session.screen
    path = re.escape(str(out / "results.csv"))
    shown = re.findall(rf"\rwriting {path}: +([0-9.]+) % of {rows} rows", session.screen)
    done = [100 * min(rows, k * CSV_BLOCK) / rows for k in (1, 2, 3)]
    assert [float(x) for x in shown] == pytest.approx(done, abs=0.05)
    assert session.screen.endswith("\r") and " rows" not in session.stdout
    record = tmp_path / "m.csv"
    args = ["synthesize", CLEARANCE, "--signal", "slider.ax", "--t-end", "0.2"]
    assert main([*args, "--out", str(record)]) == 0
    compared = tmp_path / "cmp"
    args = ["compare", CLEARANCE, "--measured", str(record), "--signal", "slider.ax"]
    args += ["--rate", "1000"]
    session = in_terminal(*args, "--max-lag", "0.02", "--out", str(compared), "--format", "svg")
    assert session.returncode == 0, session.screen
    path = re.escape(str(compared / "simulation" / "results.csv"))
    assert re.search(rf"\rwriting {path}: 100.0 % of \d+ rows", session.screen)


# --- 5. statistics from uneven samples -------------------------------------------------


def test_contact_fractions_do_not_depend_on_the_rate(engine) -> None:
    from jointgap.statistics import contact_statistics

    model = _model()
    [fine] = contact_statistics(model.simulate(0.5, rate=10_000))
    [coarse] = contact_statistics(model.simulate(0.5, rate=100))
    [steps] = contact_statistics(model.simulate(0.5))
    # Onsets and separations end steps: free flight is exact at any rate.
    for s in (coarse, steps):
        assert s.free_flight == pytest.approx(fine.free_flight, abs=1e-9)
        assert s.impact + s.contact == pytest.approx(fine.impact + fine.contact, abs=1e-9)
        assert s.impact == pytest.approx(fine.impact, abs=2e-3)
    assert fine.impact > 0.005  # what 100 Hz samples read as 0
    # Against the exact intervals of the impact list.
    r = model.simulate(0.5, rate=100)
    contact = sum(i.duration for i in r.impacts["rod_slider"] if math.isfinite(i.duration))
    open_end = [0.5 - i.onset_time for i in r.impacts["rod_slider"] if math.isnan(i.duration)]
    assert coarse.impact + coarse.contact == pytest.approx((contact + sum(open_end)) / 0.5)


def test_rms_deviation_is_weighted_by_time(engine) -> None:
    from jointgap.statistics import deviation_from_ideal

    model, ideal_model = _model(), _model("slider_crank_ideal.toml")
    ideal = ideal_model.simulate(0.5, rate=10_000)
    [uniform] = deviation_from_ideal(model.simulate(0.5, rate=10_000), ideal, ["slider.ax"])
    [steps] = deviation_from_ideal(model.simulate(0.5), ideal, ["slider.ax"])
    # Every step clusters at impacts: a plain mean read 63.9 % against 27.8 %.
    assert steps.rms_relative == pytest.approx(uniform.rms_relative, rel=0.05)


# --- 6. report on long runs ------------------------------------------------------------


def test_report_thins_by_shape(engine) -> None:
    from jointgap.report.run import impact_samples, run_section

    r = _model().simulate(1.0, rate=10_000)
    section = run_section(r, max_points=2000)
    [orbit] = section["orbits"]
    c = orbit["clearance"]
    assert 0 < len(orbit["ex"]) < len(r.time) and orbit["thinned"] == len(r.time)
    ex, ey = np.array(orbit["ex"]), np.array(orbit["ey"])
    # No chord through the circle: the midpoints of consecutive points in contact stay
    # near the wall (evenly in time they reached 0.67 c).
    wall = (np.array(orbit["mode"][:-1]) > 0) & (np.array(orbit["mode"][1:]) > 0)
    mid = np.hypot(0.5 * (ex[1:] + ex[:-1]), 0.5 * (ey[1:] + ey[:-1]))
    assert np.min(mid[wall]) > 0.97 * c
    # Every series is thinned: the page holds no full time vector, says so in the
    # title, and keeps the samples of every impact.
    assert section["times"]["run"] == []
    [fn] = [p for p in section["plots"] if p["id"] == "rod_slider.fn"]
    assert "thinned from" in fn["title"]
    kept = np.array(fn["series"][0]["x"])
    spikes = np.round(r.time[impact_samples(r)], 9)
    assert np.isin(spikes, kept).all()
    assert max(fn["series"][0]["y"]) == pytest.approx(np.max(r["rod_slider.fn"]), rel=1e-6)


# --- 7. compare and converge on long runs ----------------------------------------------


def test_compare_summarises_many_turns() -> None:
    from jointgap.comparison import CYCLE_LINES, WORST_CYCLES, CycleRow, cycle_lines

    rows = [
        CycleRow(k, 0.2 * k, 0.2 * (k + 1), 10.0 + k % 7, 10.0, (k % 7) / 10.0) for k in range(300)
    ]
    lines = cycle_lines(rows, "crank.angle", "m/s^2")
    assert len(lines) == WORST_CYCLES + 3 <= CYCLE_LINES
    assert "300 turns" in lines[0] and "from +0.00 to +60.00 %" in lines[0]
    assert all(line.endswith("60.00 %") for line in lines[3:])
    few = cycle_lines(rows[:CYCLE_LINES], "crank.angle", "m/s^2")
    assert len(few) == CYCLE_LINES + 2


def test_converge_names_its_level_on_the_progress_line(engine) -> None:
    from terminal import in_terminal

    # Every run reports every 16 steps (tests/terminal.py): each level shows, in order,
    # with its own tolerance, however fast the machine is.
    args = ["converge", CLEARANCE, "--t-end", "0.1", "--rate", "1000", "--rtol", "1e-5"]
    session = in_terminal(*args, "--atol", "1e-8", "--levels", "2")
    assert session.returncode in (0, EXIT_NOT_CONVERGED), session.screen
    shown = re.findall(r"\rlevel (\d)/3 rtol ([0-9e.+-]+): t = [0-9.e+-]+ / 0.1 s", session.screen)
    assert list(dict.fromkeys(shown)) == [("1", "1e-05"), ("2", "1e-06"), ("3", "1e-07")]
    # The line is cleared when the runs end; only the runs' warnings follow it.
    after = session.screen[session.screen.rfind("\rlevel") + 1 :]
    cleared = re.search(r"\r +\r", after)
    assert cleared is not None and "level" not in session.stdout
    rest = [line for line in after[cleared.end() :].splitlines() if line.strip()]
    assert all(line.startswith("jointgap: warning: ") for line in rest), rest


def test_converge_says_what_helps_when_tightening_does_not() -> None:
    from jointgap.convergence import ChannelChange, Convergence

    def check(nrmse: list[float]) -> Convergence:
        runs = [
            Result(np.zeros(0), [], np.zeros((0, 0)), options={"rtol": r, "atol": r * 1e-3})
            for r in (1e-8, 1e-9, 1e-10)
        ]
        changes = [[ChannelChange("slider.ax", 1.0, 0.0, x)] for x in nrmse]
        return Convergence(
            runs,
            changes,
            [{}] * 3,
            [0.0] * 3,
            [x <= 0.01 for x in nrmse],
            [[] if x <= 0.01 else ["slider.ax differs"] for x in nrmse],
            0.01,
            0.01,
            1e-4,
        )

    chaotic = check([0.3, 0.25])
    assert chaotic.diverging and "chaotic" in chaotic.verdict()
    assert "raise --levels" not in chaotic.verdict()
    settling = check([0.3, 0.05])
    assert not settling.diverging and "raise --levels" in settling.verdict()


# --- every command on a 20 s and a 60 s founding case ----------------------------------

LONG_RUN = ["--rate", "1000", "--rtol", "1e-5", "--atol", "1e-8"]
"""Options of the long runs: 1 kHz and a looser tolerance keep the time of the slow tests
small; what breaks on long runs (sizes, counts, sample marks) breaks there as well."""


@pytest.fixture(scope="module", params=[20, 60], ids=["20s", "60s"])
def long_folder(request, tmp_path_factory):  # type: ignore[no-untyped-def]
    """A folder with the founding case run over 20 s or 60 s with its ideal run, and a
    synthetic measurement of it, written by the CLI."""
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    t_end = str(request.param)
    folder = tmp_path_factory.mktemp(f"long{t_end}")
    args = ["run", CLEARANCE, "--t-end", t_end, *LONG_RUN, "--out", str(folder / "run")]
    assert main([*args, "--ideal", IDEAL]) == 0
    measured = folder / "m.csv"
    args = ["synthesize", CLEARANCE, "--signal", "slider.ax", "--t-end", t_end, *LONG_RUN]
    assert main([*args, "--out", str(measured), "--noise", "5", "--seed", "1"]) == 0
    return folder, float(t_end)


@pytest.mark.slow
def test_long_run_writes_and_reads_back(long_folder, capsys) -> None:
    folder, t_end = long_folder
    r = Result.load(folder / "run")
    assert r.ok and r.time[-1] == t_end and len(r.time) == 1000 * t_end + 1
    turns = t_end * 5  # 300 rpm
    assert 3 * turns < len(r.impacts["rod_slider"]) < 6 * turns
    assert main(["plot", str(folder / "run"), "--format", "png"]) == 0
    assert main(["report", str(folder / "run"), "--out", str(folder / "r.html")]) == 0
    assert main(["check", CLEARANCE]) == 0


@pytest.mark.slow
def test_long_converge_and_calibrate(long_folder, capsys) -> None:
    folder, t_end = long_folder
    args = ["converge", CLEARANCE, "--t-end", str(t_end), *LONG_RUN, "--levels", "1"]
    assert main(args) in (0, EXIT_NOT_CONVERGED)
    text = capsys.readouterr().out
    assert "converged" in text and "samples" not in text.split("\n")[-2]
    args = ["calibrate", CLEARANCE, "--restitution", "0.55", "--t-end", str(t_end), *LONG_RUN]
    assert main([*args, "--max-iterations", "1"]) in (0, EXIT_NOT_CONVERGED)


@pytest.mark.slow
def test_long_compare(long_folder, capsys) -> None:
    folder, t_end = long_folder
    # The lag estimated over the whole record (the synthetic record's is 10 ms): the
    # search correlates it at 500 shifts by FFT.
    measured = ["--measured", str(folder / "m.csv"), "--signal", "slider.ax"]
    args = ["compare", CLEARANCE, *measured, *LONG_RUN, "--out", str(folder / "cmp")]
    assert main([*args, "--format", "png"]) == 0
    text = capsys.readouterr().out
    assert len(text.splitlines()) < 30 and " turns, difference mean " in text
    lag = json.loads((folder / "cmp" / "comparison.json").read_text())["lag"]
    assert lag == pytest.approx(0.01, abs=1 / 5000)  # within a sample of the record


@pytest.mark.slow
def test_long_identify(long_folder, capsys) -> None:
    import pandas as pd
    from jointgap.measured import read_measured

    folder, t_end = long_folder
    record = folder / "m.csv"
    if t_end == 20:
        # The reproducer on the founding case: a restitution, searched through
        # C_max (5 runs place the bounds), a scan of 3 and a short refinement.
        param, scan, refine = "rod_slider.restitution=0.3:0.95", "3", "6"
    else:
        # C_max itself around the record's 27960 N s/m: no bound runs, a run per trial
        # (4 s each) is all the time of this test.
        param, scan, refine = "rod_slider.c_max=20000:36000", "2", "4"
    table = folder / f"trials{t_end:g}.csv"
    args = ["identify", CLEARANCE, "--measured", str(record), "--signal", "slider.ax"]
    args += ["--param", param, "--scan", scan, "--max-evaluations", refine]
    args += ["--t-end", str(t_end), *LONG_RUN, "--table", str(table)]
    assert main(args) == 0
    text = capsys.readouterr().out
    trials = pd.read_csv(table)
    assert len(trials) <= int(scan) + int(refine) + 8  # and at most 4 profile rounds of 2
    # The best trial is the lowest of its own table, and it is the one the fit reports.
    best = trials.loc[trials["nrmse"].idxmin()]
    assert f"best (trial {best['trial']}), nrmse = " in text
    # Its values are physical: a restitution in (0, 1], a C_max within its bounds.
    c_max = best["rod_slider.c_max"]
    if t_end == 20:
        assert 0.0 < best["rod_slider.restitution"] <= 1.0 and c_max > 0.0
    else:
        assert 20000.0 <= c_max <= 36000.0
    # No fit beats the record's own noise (5 m/s^2 standard deviation against its range),
    # and the lag is the record's 10 ms to a sample (5 kHz).
    values = read_measured(record, "slider.ax").values
    assert best["nrmse"] >= 0.9 * 5.0 / float(np.ptp(values))
    assert best["lag"] == pytest.approx(0.01, abs=1 / 5000)


@pytest.mark.slow
def test_long_study(long_folder, capsys) -> None:
    folder, t_end = long_folder
    study = folder / "study.toml"
    study.write_text(
        f"""[study]
model = "{CLEARANCE}"
t_end = "{t_end} s"
rate = "1 kHz"
rtol = 1e-5
atol = 1e-8

[parameters]
"rod_slider.clearance" = ["0.5 mm"]

[metrics]
peak = {{ stat = "peak", channel = "slider.ax" }}
"""
    )
    out = folder / "study"
    assert main(["study", str(study), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    assert main(["study-plot", str(out)]) == 0
