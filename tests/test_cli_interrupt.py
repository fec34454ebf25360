"""Ctrl-C on every command that runs simulations: it stops at once, writes what it has
(results up to the stop with status "interrupted", the calibration or fit table so
far), prints one line and exits with status 130; and the progress line of the commands
of many runs.

The Ctrl-C is sent when the command has shown a progress line (tests/terminal.py: one
every 16 steps), in runs of 1000 s of simulated time that cannot end in between; or,
in-process, by the test's own progress callable at a chosen run or trial. No test
waits for a time or a delay.
"""

from __future__ import annotations

import io
import json
import re
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import jointgap
import jointgap.cli.commands
import pandas as pd
import pytest
from jointgap.cli import main
from jointgap.cli.progress import ProgressLine
from terminal import PROGRESS, Session, in_terminal, last_line

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
CLEARANCE = str(EXAMPLES / "slider_crank_clearance.toml")
LONG = "1000"  # s of simulated time: no run ends between a progress line and Ctrl-C
PAST_A_TENTH = re.compile(r"t = (0\.[1-9]|[1-9])[0-9.e+-]* / ")
"""A progress line at t >= 0.1 s: the samples at 100 Hz up to there are ten."""


def interrupted_line(session: Session) -> str:
    """The one line of an interrupted command (checked: status 130, no traceback)."""
    assert session.returncode == 130, session.screen
    assert "Traceback" not in session.screen and "KeyboardInterrupt" not in session.screen
    line = last_line(session.screen)
    assert line.startswith("jointgap: interrupted: "), session.screen
    assert session.screen.count("jointgap:") == 1
    return line


def stop_time(line: str) -> float:
    """The simulated time an interrupted run reports."""
    found = re.search(r"interrupted at t = ([0-9.e+-]+) s", line)
    assert found, line
    return float(found.group(1))


@pytest.fixture
def record(tmp_path: Path) -> Path:
    """A synthetic accelerometer record of the founding case (0.1 s, 5 kHz)."""
    from jointgap.measured import synthetic_record

    result = jointgap.load(CLEARANCE).simulate(0.12, rate=20_000)
    path = tmp_path / "accelerometer.csv"
    synthetic_record(result, "slider.ax", lag=0.005, noise=1.0, duration=0.1).to_csv(path)
    return path


def test_run_keeps_the_results_up_to_the_stop(tmp_path, engine) -> None:
    out = tmp_path / "out"
    args = ["run", CLEARANCE, "--t-end", LONG, "--rate", "100", "--out", str(out)]
    line = interrupted_line(in_terminal(*args, interrupt_after=PAST_A_TENTH))
    assert f"the results up to there are in {out}" in line
    t = stop_time(line)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert summary["message"] == f"interrupted at t = {t:.6g} s"
    table = pd.read_csv(out / "results.csv")
    assert 0.1 <= table["time"].iloc[-1] <= t < float(LONG)
    assert (out / "impacts.csv").exists()
    loaded = jointgap.Result.load(out)
    assert loaded.interrupted and not loaded.ok


def test_calibrate_in_its_first_run(tmp_path, engine) -> None:
    table = tmp_path / "calibration.csv"
    args = ["calibrate", CLEARANCE, "--restitution", "0.55", "--t-end", LONG, "--rate", "100"]
    session = in_terminal(*args, "--table", str(table), interrupt_after=PROGRESS)
    assert "\rrun 1: t = " in session.screen  # the progress line names the run
    line = interrupted_line(session)
    assert f"calibration run 1 stopped, 0 done; the table so far is in {table}" in line
    assert list(pd.read_csv(table).columns) == ["iteration", "c_max", "v_avg", "impacts", "update"]


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@contextmanager
def press_ctrl_c_in(monkeypatch, module, when) -> Iterator[None]:
    """The command's progress line presses Ctrl-C (a real SIGINT to this process's
    main thread) at the first report for which ``when(line)`` holds. A run on another
    thread that reports after that waits until the main thread has taken the Ctrl-C,
    then stops: what ends after the press is only what was within its last 16 steps.
    While it waits it presses again: a SIGINT that lands just as the main thread starts
    to wait on a lock is only seen at the lock's release, which would never come; the
    handler takes the first and ignores the others."""
    taken = threading.Event()

    def ctrl_c(signum: int, frame: object) -> None:  # Python's own, and a mark
        if taken.is_set():
            return
        taken.set()
        raise KeyboardInterrupt

    def press() -> None:
        signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)

    class Line(ProgressLine):
        pressed = False

        def __call__(self, t: float, steps: int, impacts: int) -> None:
            if Line.pressed and threading.current_thread() is not threading.main_thread():
                while not taken.wait(0.1):
                    press()
                raise KeyboardInterrupt
            if not Line.pressed and when(self):
                Line.pressed = True
                press()
            super().__call__(t, steps, impacts)

    @contextmanager
    def progress_line(t_end, label="", stream=None) -> Iterator[ProgressLine]:
        yield Line(t_end, Terminal(), label)

    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "0")
    monkeypatch.setattr(module, "progress_line", progress_line)
    previous = signal.signal(signal.SIGINT, ctrl_c)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def test_calibrate_keeps_the_table_so_far(tmp_path, monkeypatch, capsys, engine) -> None:
    table = tmp_path / "calibration.csv"
    args = ["calibrate", CLEARANCE, "--restitution", "0.55", "--c-max", "10"]
    args += ["--t-end", "0.3", "--rate", "1000", "--table", str(table)]
    with press_ctrl_c_in(monkeypatch, jointgap.cli.commands, lambda line: line.label == "run 2: "):
        assert main(args) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("jointgap: interrupted: calibration run 2 stopped, 1 done")
    assert f"the table so far is in {table}" in err[0]
    rows = pd.read_csv(table)
    assert list(rows["iteration"]) == [1] and rows["c_max"][0] == 10.0
    assert rows["impacts"][0] > 0 and rows["update"][0] > 10.0


def test_identify_keeps_the_trials_so_far(tmp_path, record, monkeypatch, capsys, engine) -> None:
    import jointgap.cli.progress

    table = tmp_path / "trials.csv"
    # Ctrl-C once two trials are done: the runs of the other thread stop too.
    args = ["identify", CLEARANCE, "--measured", str(record), "--signal", "slider.ax"]
    args += ["--param", "rod_slider.c_max=200:5000", "--scan", "12", "--workers", "2"]
    # a lag search well inside the 0.1 s record: no warning line beside the one asserted
    args += ["--rate", "5000", "--max-lag", "0.01", "--table", str(table)]
    # Pressed at the first report once two or more trials are done: two trials may end
    # between two reports, so the count at the press is read off the line, not assumed.
    at_press: list[int] = []

    def two_done(line: ProgressLine) -> bool:
        found = re.match(r"trials: (\d+) done", line.label)
        if found is None or int(found.group(1)) < 2:
            return False
        at_press.append(int(found.group(1)))
        return True

    with press_ctrl_c_in(monkeypatch, jointgap.cli.progress, two_done):
        assert main(args) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("jointgap: interrupted: the fit stopped after ")
    trials = pd.read_csv(table)
    # the trial running on the other thread at the press ends only if it was within its
    # last 16 steps; every run after stops
    assert at_press[0] <= len(trials) <= at_press[0] + 1
    assert sorted(trials["trial"]) == list(range(1, len(trials) + 1))
    best = trials.loc[trials["nrmse"].idxmin()]
    c_max = best["rod_slider.c_max"]
    assert f"best so far trial {best['trial']}: rod_slider.c_max = {c_max:.6g}" in err[0]
    assert f"the table so far is in {table}" in err[0]


def test_identify_in_its_first_trials(tmp_path, record, engine) -> None:
    table = tmp_path / "trials.csv"
    args = ["identify", CLEARANCE, "--measured", str(record), "--signal", "slider.ax"]
    args += ["--param", "rod_slider.c_max=200:5000", "--scan", "4", "--workers", "2"]
    args += ["--t-end", LONG, "--rate", "100", "--table", str(table)]
    session = in_terminal(*args, interrupt_after=PROGRESS)
    assert "\rtrials: 0 done; t = " in session.screen
    line = interrupted_line(session)
    assert "the fit stopped after 0 trials" in line
    assert pd.read_csv(table).empty


def test_converge_stops_and_says_so(engine) -> None:
    session = in_terminal("converge", CLEARANCE, "--t-end", LONG, interrupt_after=PROGRESS)
    assert "nothing compared" in interrupted_line(session)


def test_compare_keeps_the_simulation(tmp_path, record, engine) -> None:
    out = tmp_path / "cmp"
    args = ["compare", CLEARANCE, "--measured", str(record), "--signal", "slider.ax"]
    args += ["--t-end", LONG, "--rate", "100", "--out", str(out)]
    line = interrupted_line(in_terminal(*args, interrupt_after=PROGRESS))
    assert f"nothing compared; the simulation up to there is in {out / 'simulation'}" in line
    summary = json.loads((out / "simulation" / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert not (out / "comparison.json").exists()


def test_synthesize_writes_no_record(tmp_path, engine) -> None:
    path = tmp_path / "m.csv"
    args = ["synthesize", CLEARANCE, "--signal", "slider.ax", "--t-end", LONG]
    args += ["--rate", "1000", "--out", str(path)]
    line = interrupted_line(in_terminal(*args, interrupt_after=PROGRESS))
    assert f"no record written ({path})" in line and not path.exists()


def test_a_progress_callable_can_interrupt_a_run(engine, monkeypatch) -> None:
    """A KeyboardInterrupt from ``progress`` is Ctrl-C: the run returns what it computed;
    any other exception propagates."""
    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "0")
    model = jointgap.load(CLEARANCE)
    calls: list[float] = []

    def third(t: float, steps: int, impacts: int) -> None:
        calls.append(t)
        if len(calls) == 3:
            raise KeyboardInterrupt

    result = model.simulate(5.0, rate=1000, progress=third)
    assert result.interrupted and not result.ok
    assert result.message == f"interrupted at t = {calls[-1]:.6g} s"
    assert 0 < result.time[-1] <= calls[-1] < 5.0
    # the samples up to the stop are those of a run that goes on
    longer = model.simulate(2 * calls[-1], rate=1000).to_pandas()
    pd.testing.assert_frame_equal(result.to_pandas(), longer.iloc[: len(result.time)])

    def broken(t: float, steps: int, impacts: int) -> None:
        raise RuntimeError("display gone")

    with pytest.raises(RuntimeError, match="display gone"):
        model.simulate(5.0, rate=1000, progress=broken)


def test_progress_interval_variable_is_checked(engine, monkeypatch) -> None:
    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "soon")
    with pytest.raises(ValueError, match="JOINTGAP_PROGRESS_INTERVAL = 'soon'"):
        jointgap.load(CLEARANCE).simulate(0.01)


def test_report_of_a_model_draws_the_run_so_far(tmp_path, engine) -> None:
    out = tmp_path / "report.html"
    args = ["report", CLEARANCE, "--t-end", LONG, "--rate", "100", "--out", str(out)]
    line = interrupted_line(in_terminal(*args, interrupt_after=PAST_A_TENTH))
    assert f"the report of the run is {out}" in line and "interrupted at t = " in line
    assert out.stat().st_size > 10_000
