"""Is a result converged? Run the model again at tighter tolerances and compare.

:func:`check_convergence` runs the model at the chosen tolerances and at ``levels``
tighter ones (each ten times tighter in rtol and atol), all sampled at the same rate, and
takes the tightest run as the reference. The chosen run has converged when, against it,

- every clearance joint has the same number of impacts, with onset times that agree to
  one output sample (``1 / rate``);
- the peak (largest absolute value) of every main output moves by at most
  ``peak_tolerance`` (1 % by default); peaks are taken over every accepted step as well
  as the samples, because an impact's spike can be narrower than the sampling interval
  and the samples would catch it by chance;
- the NRMSE of every main output, RMS difference over the reference's range, is at most
  ``nrmse_tolerance`` (1 % by default), on the samples at ``rate``.

Each run keeps only what the test reads: the compared channels at ``rate`` and the
engine's peaks over every step (``step_peaks``), not every step of every channel, so a
60 s run of the two-clearance model needs the memory of its samples alone.

The main outputs are the slider motion along its guide, the driver efforts and the
contact force of each clearance joint (:func:`jointgap.results.main_channels`). The
same test applied to the next tighter run tells the user which tolerance would do.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._engine import DEFAULT_OPTIONS
from .errors import RunStopped
from .model import Model
from .results import Result, channel_unit, clearance_joints, main_channels, model_channels

__all__ = [
    "ChannelChange",
    "Convergence",
    "LARGE_MEMORY",
    "RunStopped",
    "TIGHTEN",
    "check_convergence",
    "memory_need",
]

TIGHTEN = 10.0
"""Factor between successive tolerances."""


@dataclass(frozen=True)
class ChannelChange:
    """How one output moves between a run and the reference.

    Attributes:
        channel: the output.
        peak: the run's largest absolute value.
        peak_change: relative change of that peak against the reference's.
        nrmse: RMS difference over the reference's range (max - min).
    """

    channel: str
    peak: float
    peak_change: float
    nrmse: float


@dataclass(frozen=True)
class Convergence:
    """The outcome of :func:`check_convergence`.

    Attributes:
        runs: the results, loosest (the chosen tolerance) first, the reference last.
        changes: per run but the reference, the change of each main output.
        impacts: per run, the impact count of each clearance joint.
        onset_shift: per run, the largest onset-time difference [s] against the
            reference over matched impacts (NaN when the counts differ).
        converged: per run but the reference, whether it passes the test.
        reasons: per run but the reference, why it fails (empty when it passes).
        peak_tolerance, nrmse_tolerance, onset_tolerance: the limits applied.
    """

    runs: list[Result]
    changes: list[list[ChannelChange]]
    impacts: list[dict[str, int]]
    onset_shift: list[float]
    converged: list[bool]
    reasons: list[list[str]]
    peak_tolerance: float
    nrmse_tolerance: float
    onset_tolerance: float
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """Whether the run at the chosen tolerance has converged."""
        return self.converged[0]

    def verdict(self) -> str:
        """One plain sentence or two about the chosen tolerance."""
        chosen = _tolerance(self.runs[0])
        reference = _tolerance(self.runs[-1])
        if self.ok:
            worst_peak = max((abs(c.peak_change) for c in self.changes[0]), default=0.0)
            worst_nrmse = max((c.nrmse for c in self.changes[0]), default=0.0)
            return (
                f"converged: at {chosen} the peaks move by at most {100 * worst_peak:.2g} % "
                f"and the NRMSE of the main outputs is at most {worst_nrmse:.2g} against "
                f"{reference}."
            )
        text = f"NOT converged: {chosen} is too loose: " + "; ".join(self.reasons[0]) + "."
        # The loosest level from which every tighter one passes too.
        better = [k for k in range(1, len(self.converged)) if all(self.converged[k:])]
        if better:
            text += f" Use {_tolerance(self.runs[better[0]])} or tighter."
        elif self.diverging:
            text += (
                " The differences do not shrink as the tolerance tightens: the response is"
                " chaotic here (which impact comes when depends on rounding), so no tolerance"
                " makes this run repeat. What can help: check convergence over a shorter"
                " --t-end (up to where the tightest runs still agree), and judge a long run"
                " by its statistics (contact time fractions, impacts per turn, peak ranges)"
                " rather than its time history."
            )
        else:
            text += " Tighter tolerances are needed than were tried (raise --levels)."
        return text

    @property
    def diverging(self) -> bool:
        """Whether tightening did not bring the runs closer: the next-to-tightest run
        differs from the reference by at least half as much as the chosen one (largest
        NRMSE over the main outputs), as a chaotic response does. False with one level,
        where there is nothing to compare."""
        if len(self.changes) < 2:
            return False

        def worst(changes: list[ChannelChange]) -> float:
            return max((c.nrmse for c in changes), default=0.0)

        first, last = worst(self.changes[0]), worst(self.changes[-1])
        return first > self.nrmse_tolerance and last >= 0.5 * first

    def table(self) -> str:
        """Runs, their cost and impacts, and each main output's change, as text."""
        lines = [
            f"{'rtol':>8} {'atol':>8} {'steps':>7} {'wall [s]':>9} {'impacts':>8} "
            f"{'onset shift [s]':>16}  converged"
        ]
        for k, run in enumerate(self.runs):
            stats = run.stats
            steps = stats.get("accepted_steps", 0) + stats.get("rejected_steps", 0)
            shift = self.onset_shift[k]
            flag = "reference" if k == len(self.runs) - 1 else str(self.converged[k]).lower()
            lines.append(
                f"{run.options['rtol']:>8.0e} {run.options['atol']:>8.0e} {steps:>7d} "
                f"{stats.get('wall_time', math.nan):>9.3f} {sum(self.impacts[k].values()):>8d} "
                f"{shift:>16.3g}  {flag}"
            )
        lines.append("")
        lines.append(f"{'channel':<24} {'rtol':>8} {'peak':>12} {'peak change':>12} {'NRMSE':>9}")
        for k, changes in enumerate(self.changes):
            for c in changes:
                unit = channel_unit(c.channel)
                lines.append(
                    f"{c.channel:<24} {self.runs[k].options['rtol']:>8.0e} "
                    f"{c.peak:>12.6g} {100 * c.peak_change:>+11.3g}% {c.nrmse:>9.2g}  {unit}"
                )
        return "\n".join(lines + self.notes)


def check_convergence(
    model: Model,
    t_end: float | str,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    rate: float | str = 10_000.0,
    levels: int = 2,
    peak_tolerance: float = 0.01,
    nrmse_tolerance: float = 0.01,
    level: Callable[[int, int, float, float], object] | None = None,
    **run_options: Any,
) -> Convergence:
    """Runs ``model`` at ``rtol``/``atol`` (by default the engine's,
    :data:`jointgap._engine.DEFAULT_OPTIONS`) and ``levels`` tenfold tighter tolerances, all
    sampled at ``rate``, and tests each against the tightest (see the module docs).
    ``level(k, runs, rtol, atol)`` is called as the k-th of the ``levels + 1`` runs
    starts (k = 1, 2, ...), e.g. to name it on a progress line; ``run_options`` (method,
    max_step, progress, ...) go to every run; Ctrl-C during a run raises
    KeyboardInterrupt."""
    if levels < 1:
        raise ValueError(f"levels = {levels}: must be at least 1")
    for name, value in (("peak_tolerance", peak_tolerance), ("nrmse_tolerance", nrmse_tolerance)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} = {value!r}: must be positive")
    rtol = DEFAULT_OPTIONS["rtol"] if rtol is None else rtol
    atol = DEFAULT_OPTIONS["atol"] if atol is None else atol
    channels = _compared_channels(model)
    runs = []
    for k in range(levels + 1):
        # Decimal tolerances: 1e-5 / 10 as a float is not 1e-6, and runs differ by it.
        tight_rtol, tight_atol = (float(f"{x / TIGHTEN**k:.12g}") for x in (rtol, atol))
        if level is not None:
            level(k + 1, levels + 1, tight_rtol, tight_atol)
        run = model.simulate(
            t_end,
            rate=rate,
            rtol=tight_rtol,
            atol=tight_atol,
            channels=channels,
            step_peaks=True,
            **run_options,
        )
        if run.interrupted:
            raise KeyboardInterrupt
        if not run.ok:
            raise RunStopped(f"the run at rtol {tight_rtol:g} {run.message}", run)
        runs.append(run)
    reference = runs[-1]
    onset_tolerance = 1.0 / float(reference.options["rate"])
    impacts = [{j: len(lst) for j, lst in run.impacts.items()} for run in runs]
    shifts = [_onset_shift(run, reference) for run in runs]
    changes, converged, reasons = [], [], []
    for k, run in enumerate(runs[:-1]):
        run_changes = [_change(run, reference, c) for c in channels]
        why = []
        for joint, count in impacts[k].items():
            if count != impacts[-1][joint]:
                why.append(f"{joint} has {count} impacts, {impacts[-1][joint]} at the reference")
        if math.isfinite(shifts[k]) and shifts[k] > onset_tolerance:
            why.append(f"impact onsets move by up to {shifts[k]:.3g} s")
        for c in run_changes:
            if abs(c.peak_change) > peak_tolerance:
                why.append(f"the peak of {c.channel} moves by {100 * c.peak_change:+.3g} %")
            if c.nrmse > nrmse_tolerance:
                why.append(f"{c.channel} differs by NRMSE {c.nrmse:.2g}")
        changes.append(run_changes)
        converged.append(not why)
        reasons.append(why)
    return Convergence(
        runs=runs,
        changes=changes,
        impacts=impacts,
        onset_shift=shifts,
        converged=converged,
        reasons=reasons,
        peak_tolerance=peak_tolerance,
        nrmse_tolerance=nrmse_tolerance,
        onset_tolerance=onset_tolerance,
    )


LARGE_MEMORY = 256e6
"""Bytes of samples above which ``jointgap converge`` states what its runs will keep."""


def memory_need(model: Model, t_end: float | str, rate: float | str, levels: int) -> int:
    """Bytes of samples that :func:`check_convergence` keeps: ``levels + 1`` runs of the
    compared channels and the time at ``rate`` (each 8 bytes a sample), the end state
    included."""
    from . import units as u

    samples = math.floor(u.to_si(t_end, u.TIME) * u.to_si(rate, u.FREQUENCY)) + 2
    return 8 * (levels + 1) * samples * (len(_compared_channels(model)) + 1)


def _compared_channels(model: Model) -> list[str]:
    """The main outputs of ``model`` (not the constraint error) and the contact force of
    each clearance joint, named before any run so that the runs record only these."""
    data = model.to_dict()
    names = model_channels(data)
    probe = Result(time=np.zeros(0), channels=names, data=np.zeros((len(names), 0)), model=data)
    chosen = [c for c in main_channels(probe) if c != "system.constraint_error"]
    chosen += [f"{j}.fn" for j in clearance_joints(probe) if f"{j}.fn" in probe]
    return chosen


def _change(run: Result, reference: Result, channel: str) -> ChannelChange:
    peak = run.peaks[channel]
    peak_ref = reference.peaks[channel]
    a, b = run[channel][run.sample_index], reference[channel][reference.sample_index]
    if len(a) != len(b):
        raise ValueError(f"{channel}: the runs have {len(a)} and {len(b)} samples")
    span = float(np.ptp(b))
    change = peak / peak_ref - 1.0 if peak_ref > 0 else (0.0 if peak == 0 else math.inf)
    rms = float(np.sqrt(np.mean((a - b) ** 2)))
    nrmse = rms / span if span > 0 else (0.0 if rms == 0 else math.inf)
    return ChannelChange(channel, peak, change, nrmse)


def _onset_shift(run: Result, reference: Result) -> float:
    """Largest onset-time difference over all joints; NaN when any count differs."""
    shift = 0.0
    for joint, impacts in reference.impacts.items():
        mine = run.impacts.get(joint, [])
        if len(mine) != len(impacts):
            return math.nan
        for a, b in zip(mine, impacts, strict=True):
            shift = max(shift, abs(a.onset_time - b.onset_time))
    return shift


def _tolerance(run: Result) -> str:
    return f"rtol {run.options['rtol']:g} (atol {run.options['atol']:g})"
