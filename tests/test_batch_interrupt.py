"""Ctrl-C on a batch (jointgap.simulate_batch): the runs that ended are kept, the one
going stops with status "interrupted" and what it computed, the ones not started do not
start, and the batch raises BatchInterrupted (a KeyboardInterrupt) holding them all.

The Ctrl-C is a real SIGINT to this process, sent by the batch's own progress callable
once it reports one run ended and one going; the run going cannot end meanwhile (10,000
s of the founding case, hours of computing). No test waits for a time or a delay."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap.errors import BatchInterrupted

FOUNDING = Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"
T_END = 10_000.0
"""s: the founding case cannot end in a test; the body at rest ends in a few steps."""


def at_rest() -> jointgap.Model:
    """A free body at rest without gravity: its run to any end takes a few steps."""
    model = jointgap.Model(name="at_rest", gravity=(0.0, 0.0))
    model.add_body("block", 1.0, 0.01)
    return model


@pytest.fixture
def checked_often(monkeypatch) -> None:
    """Progress (and Ctrl-C checks) every millisecond, however fast the machine."""
    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "0")


def test_ctrl_c_keeps_what_ended_and_stops_the_run_going(checked_often, engine) -> None:
    founding = jointgap.load(FOUNDING)
    sent: list[tuple[int, int]] = []

    def progress(running: int, ended: int) -> None:
        if not sent and (running, ended) == (1, 1):  # one thread: the second run goes
            sent.append((running, ended))
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt) as caught:
        jointgap.simulate_batch(
            [at_rest(), founding, founding], T_END, threads=1, progress=progress
        )
    assert isinstance(caught.value, BatchInterrupted)
    ended, going, waiting = caught.value.results
    assert "1 of 3 runs ended, 1 stopped with status interrupted, 1 not started" in str(
        caught.value
    )

    serial = at_rest().simulate(T_END)
    assert isinstance(ended, jointgap.Result) and ended.ok
    assert np.array_equal(ended.time, serial.time) and np.array_equal(ended.data, serial.data)

    assert isinstance(going, jointgap.Result) and going.interrupted and not going.ok
    stopped_at = going.time[-1]
    assert 0.0 < stopped_at < T_END
    assert going.message == f"interrupted at t = {going.message.split('t = ')[1]}"
    assert np.all(np.isfinite(going.data))
    # What it computed is the start of the founding case's own run to T_END: the same
    # run alone, stopped a few steps later by its step budget, begins with it.
    steps = going.stats["accepted_steps"] + going.stats["rejected_steps"]
    alone = founding.simulate(T_END, max_steps=steps + 20)
    assert alone.status == "failed" and len(alone.time) > len(going.time)
    assert np.array_equal(going.time, alone.time[: len(going.time)])
    assert np.array_equal(going.data, alone.data[:, : len(going.time)])

    assert waiting is None


def test_an_error_of_progress_stops_the_batch_and_propagates(checked_often, engine) -> None:
    founding = jointgap.load(FOUNDING)

    def progress(running: int, ended: int) -> None:
        if running:
            raise RuntimeError(f"display failed with {running} running")

    with pytest.raises(RuntimeError, match="display failed with 1 running"):
        jointgap.simulate_batch([founding, founding], T_END, threads=1, progress=progress)


def test_progress_counts_every_run(engine) -> None:
    reports: list[tuple[int, int]] = []
    out = jointgap.simulate_batch(
        [at_rest()] * 3, 1.0, progress=lambda running, ended: reports.append((running, ended))
    )
    assert [r.ok for r in out] == [True] * 3  # type: ignore[union-attr]
    assert reports[-1] == (0, 3)  # called once more at the end
