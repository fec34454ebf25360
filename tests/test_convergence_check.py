"""The convergence check flags a deliberately loose tolerance and passes a tight one;
its figures are the direct comparison of the runs it reports."""

from __future__ import annotations

import jointgap
import numpy as np
import pytest
from jointgap.cli import EXIT_NOT_CONVERGED, main
from jointgap.convergence import check_convergence


@pytest.fixture(scope="module")
def founding():
    return jointgap.load("examples/slider_crank_clearance.toml")


def test_loose_tolerance_is_flagged(founding, engine) -> None:
    check = check_convergence(founding, 0.5, rtol=1e-4, atol=1e-7)
    assert not check.ok
    verdict = check.verdict()
    assert verdict.startswith("NOT converged: rtol 0.0001 (atol 1e-07) is too loose")
    assert "slider.ax" in verdict
    # The figures are what a direct comparison of the runs gives.
    loose, ref = check.runs[0], check.runs[-1]
    change = {c.channel: c for c in check.changes[0]}
    # Peaks over every accepted step, from the engine (the runs keep only the samples).
    assert change["slider.ax"].peak_change == pytest.approx(
        loose.peaks["slider.ax"] / ref.peaks["slider.ax"] - 1, rel=1e-12
    )
    assert loose.peaks["slider.ax"] >= np.abs(loose["slider.ax"]).max()
    # NRMSE on the 10 kHz samples.
    ax, ax_ref = loose["slider.ax"], ref["slider.ax"]
    assert len(ax) == len(ax_ref) == 5001
    assert change["slider.ax"].nrmse == pytest.approx(
        np.sqrt(np.mean((ax - ax_ref) ** 2)) / np.ptp(ax_ref), rel=1e-12
    )
    assert [r.options["rtol"] for r in check.runs] == pytest.approx([1e-4, 1e-5, 1e-6])


def test_default_tolerance_passes(founding, engine) -> None:
    check = check_convergence(founding, 0.5)
    assert check.ok, check.verdict()
    assert check.verdict().startswith("converged: at rtol 1e-08")
    assert [r.options["rtol"] for r in check.runs] == [1e-8, 1e-9, 1e-10]
    assert check.impacts[0] == check.impacts[-1]
    assert check.onset_shift[0] <= 1e-4


def test_converge_command(capsys, engine) -> None:
    args = ["converge", "examples/slider_crank_clearance.toml", "--t-end", "0.5", "--levels", "1"]
    assert main([*args, "--rtol", "1e-5", "--atol", "1e-8"]) == EXIT_NOT_CONVERGED
    out = capsys.readouterr().out
    assert "NOT converged" in out and "too loose" in out
    assert main([*args, "--rtol", "1e-8", "--atol", "1e-11"]) == 0
    assert "converged: at rtol 1e-08" in capsys.readouterr().out


def test_advice_needs_every_tighter_level_to_pass() -> None:
    """At rtol 1e-5 with four levels, the founding case once passed at 1e-6, failed at
    1e-7 (a sampled peak 1 % low) and passed at 1e-8: the advice is 1e-8, the loosest
    level from which every tighter one passes, not 1e-6."""
    from types import SimpleNamespace

    from jointgap.convergence import Convergence

    levels = range(5, 10)
    runs = [SimpleNamespace(options={"rtol": 10.0**-k, "atol": 10.0 ** (-k - 3)}) for k in levels]
    check = Convergence(
        runs=runs,  # type: ignore[arg-type]
        changes=[[] for _ in range(4)],
        impacts=[{} for _ in range(5)],
        onset_shift=[0.0] * 4,
        converged=[False, True, False, True],
        reasons=[["the peak of x moves by -2 %"], [], ["the peak of x moves by -1.07 %"], []],
        peak_tolerance=0.01,
        nrmse_tolerance=0.01,
        onset_tolerance=1e-4,
    )
    assert check.verdict().endswith("Use rtol 1e-08 (atol 1e-11) or tighter.")
    check.converged[-1] = False
    assert check.verdict().endswith("than were tried (raise --levels).")


def test_converge_exits_3_when_a_run_stops_early(capsys, engine) -> None:
    """A run that stops early (here on its step budget) gives no verdict: exit 3, as
    every other command whose run stops early, with the run's reason."""
    from jointgap.cli import EXIT_RUN_FAILED
    from jointgap.convergence import RunStopped

    args = ["converge", "examples/slider_crank_clearance.toml", "--t-end", "0.05"]
    assert main([*args, "--levels", "1", "--max-steps", "20"]) == EXIT_RUN_FAILED
    err = capsys.readouterr().err
    assert err.startswith("jointgap: error: examples/slider_crank_clearance.toml: the run at rtol")
    assert "step" in err
    founding = jointgap.load("examples/slider_crank_clearance.toml")
    with pytest.raises(RunStopped) as stopped:
        check_convergence(founding, 0.05, levels=1, max_steps=20)
    assert not stopped.value.result.ok and len(stopped.value.result.time) >= 1
