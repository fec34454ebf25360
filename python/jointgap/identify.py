"""Identification of uncertain contact parameters from a measured signal.

The founding paper found its restitution by re-running the simulation by hand until the
error against the accelerometer was smallest (its Table IV). :func:`identify` does the
same search automatically: each candidate set of parameter values is written into the
model, simulated, aligned with the measurement (:func:`jointgap.comparison.compare`,
lag estimated per trial) and scored by one error measure.

Parameters are named ``<joint>.<quantity>`` with bounds, e.g.
``rod_slider.restitution=0.3:0.95``:

- ``restitution``: for a hysteresis law its ``restitution``; for ``adams_impact`` it is
  searched through C_max, and each trial reports the restitution that Eq. 10-11 (the
  damping calibration's relation) give for its C_max at its own V_avg: the pair is then
  exactly what ``jointgap calibrate`` converges to, with one run per trial. The
  restitution bounds become C_max bounds through the V_avg of one run with the
  model's C_max, so the trials' restitutions fall close to, not exactly on, them;
- ``c_max``, ``d_max``, ``damping`` (Kelvin-Voigt): the normal law's value;
- ``stiffness``: the contact stiffness K;
- ``mu_s``, ``mu_d``, ``mu``, ``viscous``: the friction law's value;
- ``clearance``: the radial clearance (the bearing radius is kept).

The search: a scan of the bounds (``scan`` points per parameter, a grid) evaluated in
parallel on the available cores (the engine releases the GIL), then a local refinement
from the best point: a bounded Brent search between its neighbours for one parameter,
bounded Nelder-Mead for several. The uncertainty of each parameter is the half-width of
the interval where a parabola through the best trial and its two neighbours along that
parameter stays within ``1 + tolerance`` of the minimum error (5 % by default): how far
the parameter can move before the fit is visibly worse.
"""

from __future__ import annotations

import copy
import itertools
import math
import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_EXCEPTION, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .calibration import average_onset_speed, damping_from_restitution, restitution_from_damping
from .model import Model
from .results import model_channels, require_channel
from .variants import (
    QUANTITIES,
    clearance_joint,
    parameter_value,
    set_clearance_parameter,
    with_parameters,
)

__all__ = ["Fit", "Parameter", "Trial", "identify", "trial_frame", "MEASURES"]

MEASURES = ("nrmse", "rms", "max_abs", "max_percent")
"""Error measures that can be minimised (see docs/comparison.md)."""

PROFILE_ROUNDS = 4
"""How many times the uncertainty profile is taken again around a lower trial it found."""


@dataclass(frozen=True)
class Parameter:
    """One parameter to fit: ``joint.quantity`` between ``low`` and ``high`` (SI)."""

    joint: str
    quantity: str
    low: float
    high: float
    start: float | None = None

    @property
    def name(self) -> str:
        """``joint.quantity``."""
        return f"{self.joint}.{self.quantity}"

    @classmethod
    def parse(cls, text: str) -> Parameter:
        """From ``joint.quantity=low:high`` or ``joint.quantity=low:high@start`` (numbers
        in SI, or with units); the start value, if any, is the first trial."""
        try:
            name, bounds = text.split("=", 1)
            joint, quantity = name.strip().rsplit(".", 1)
            bounds, _, start_text = bounds.partition("@")
            low_text, high_text = bounds.split(":", 1)
        except ValueError:
            raise ValueError(
                f"parameter {text!r}: write joint.quantity=low:high, "
                "e.g. rod_slider.restitution=0.3:0.95"
            ) from None
        path = f"{joint.strip()}.{quantity}"
        low, high = (parameter_value(path, v) for v in (low_text, high_text))
        start = parameter_value(path, start_text) if start_text.strip() else None
        return cls(joint.strip(), quantity, low, high, start)

    def __post_init__(self) -> None:
        if self.quantity not in QUANTITIES:
            raise ValueError(
                f"parameter {self.name}: unknown quantity '{self.quantity}' "
                f"(known: {', '.join(sorted(QUANTITIES))})"
            )
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(f"parameter {self.name}: bounds {self.low:g}:{self.high:g} must rise")
        if self.quantity == "restitution" and not (0.0 < self.low and self.high <= 1.0):
            raise ValueError(f"parameter {self.name}: restitution bounds must lie in (0, 1]")
        if self.start is not None and not self.low <= self.start <= self.high:
            raise ValueError(
                f"parameter {self.name}: start {self.start:g} outside {self.low:g}:{self.high:g}"
            )


@dataclass(frozen=True)
class Trial:
    """One evaluated candidate.

    Attributes:
        trial: 1, 2, ... in evaluation order.
        values: parameter values (SI), in the order of the parameters.
        error: the minimised measure; inf when the run failed.
        lag: the estimated lag of this trial [s].
        measures: every error measure of the comparison.
        derived: values that follow from the parameters (e.g. the calibrated C_max).
        phase: "start", "scan", "refine" or "profile".
        by_name: the parameter values (SI) by parameter name, e.g.
            ``trial.by_name["rod_slider.restitution"]``, in the order of the parameters.
    """

    trial: int
    values: tuple[float, ...]
    error: float
    lag: float
    measures: dict[str, float]
    derived: dict[str, float]
    phase: str
    by_name: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Fit:
    """The outcome of :func:`identify`."""

    parameters: list[Parameter]
    best: Trial
    uncertainty: list[float]
    trials: list[Trial]
    model: Model
    measure: str
    notes: list[str] = field(default_factory=list)

    def table(self) -> str:
        """The trial table in the style of the paper's Table IV, then the best values."""
        names = [p.name for p in self.parameters]
        derived = sorted({k for t in self.trials for k in t.derived})
        head = ["trial", *names, *derived, self.measure, "lag [ms]", "phase"]
        widths = [max(9, len(h)) for h in head]
        lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
        for t in self.trials:
            cells = [str(t.trial), *(f"{v:.6g}" for v in t.values)]
            cells += [f"{t.derived.get(k, math.nan):.6g}" for k in derived]
            cells += [f"{t.error:.5g}", f"{1e3 * t.lag:.3f}", t.phase]
            lines.append("  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True)))
        lines.append("")
        lines.append(f"best (trial {self.best.trial}), {self.measure} = {self.best.error:.5g}:")
        for p, v, s in zip(self.parameters, self.best.values, self.uncertainty, strict=True):
            lines.append(f"  {p.name} = {v:.6g} +/- {s:.2g}")
        for k, v in self.best.derived.items():
            lines.append(f"  {k} = {v:.6g}")
        lines.append(f"  lag = {1e3 * self.best.lag:.3f} ms")
        return "\n".join(lines + self.notes)

    def to_frame(self) -> Any:
        """The trial table as a pandas DataFrame."""
        return trial_frame(self.parameters, self.measure, self.trials)


def trial_frame(parameters: Sequence[Parameter], measure: str, trials: Sequence[Trial]) -> Any:
    """Trials as a pandas DataFrame, one row each: also the table so far of a fit that
    Ctrl-C stopped."""
    import pandas as pd  # type: ignore[import-untyped]

    rows = []
    for t in trials:
        row: dict[str, Any] = {"trial": t.trial, "phase": t.phase}
        row.update({p.name: v for p, v in zip(parameters, t.values, strict=True)})
        row.update(t.derived)
        row.update({measure: t.error, "lag": t.lag})
        rows.append(row)
    columns = ["trial", "phase", *(p.name for p in parameters), measure, "lag"]
    return pd.DataFrame(rows) if rows else pd.DataFrame(columns=columns)


class _Objective:
    """Evaluates candidates (thread-safe), remembering every trial.

    Candidates are in search coordinates: a restitution of an ``adams_impact`` joint is
    searched through its C_max (``mapped``), and each trial reports the restitution that
    Eq. 10-11 give for that C_max at the trial's own V_avg, which is what the damping
    calibration's fixed point means; one run per trial, no calibration loop.
    """

    def __init__(
        self,
        model: Model,
        parameters: Sequence[Parameter],
        mapped: Sequence[bool],
        score: Callable[[Any], tuple[float, float, dict[str, float]]],
        t_end: float,
        run_options: dict[str, Any],
        progress: Callable[[Trial], None] | None = None,
    ) -> None:
        self.base = model.to_dict()
        self.resolved = model.clearance_data()  # d_max and n of the mapped joints
        self.parameters = list(parameters)
        self.mapped = list(mapped)
        self.score = score
        self.t_end = t_end
        self.run_options = run_options
        self.progress = progress
        self.trials: list[Trial] = []
        self.lock = threading.Lock()
        self.cache: dict[tuple[float, ...], Trial] = {}

    def model_data(self, x: Sequence[float]) -> dict[str, Any]:
        """The model dictionary with the search coordinates ``x`` written in."""
        data = copy.deepcopy(self.base)
        for p, m, v in zip(self.parameters, self.mapped, x, strict=True):
            set_clearance_parameter(data, p.joint, "c_max" if m else p.quantity, float(v))
        return data

    def __call__(self, x: Sequence[float], phase: str) -> Trial:
        key = tuple(float(v) for v in x)
        with self.lock:
            if key in self.cache:
                return self.cache[key]
        values = list(key)
        derived: dict[str, float] = {}
        error, lag = math.inf, math.nan
        measures: dict[str, float] = {}
        try:
            result = Model.from_dict(self.model_data(key)).simulate(self.t_end, **self.run_options)
            if result.interrupted:
                raise KeyboardInterrupt
            for i, (p, m) in enumerate(zip(self.parameters, self.mapped, strict=True)):
                if m:
                    derived[f"{p.joint}.c_max"] = key[i]
                    resolved = self.resolved[p.joint]
                    values[i] = _restitution_of(result, p.joint, key[i], resolved)
            if result.ok:
                error, lag, measures = self.score(result)
        except (ValueError, ArithmeticError):
            pass  # an infeasible candidate (no impact, no overlap...) scores inf
        with self.lock:
            names = {p.name: v for p, v in zip(self.parameters, values, strict=True)}
            trial = Trial(
                len(self.trials) + 1, tuple(values), error, lag, measures, derived, phase, names
            )
            self.trials.append(trial)
            self.cache[key] = trial
        if self.progress is not None:  # each new trial once; a repeated point is cached
            self.progress(trial)
        return trial


def _restitution_of(result: Any, joint: str, c_max: float, resolved: dict[str, Any]) -> float:
    """Eq. 10-11 inverted at the run's own V_avg (NaN if more than plastic); ``resolved``
    is the joint's data as the engine resolves them (:meth:`Model.clearance_data`)."""
    v_avg, _ = average_onset_speed(result, joint)
    k = result.clearances[joint]["stiffness"]
    d_max, n = resolved["d_max"], resolved["exponent"]
    try:
        return restitution_from_damping(c_max, v_avg, k, d_max, n)
    except ValueError:
        return math.nan


def identify(
    model: Model,
    measured: Any,
    channel: str,
    parameters: Sequence[Parameter],
    *,
    t_end: float | None = None,
    measure: str = "nrmse",
    scan: int | Sequence[int] | None = None,
    max_evaluations: int = 60,
    tolerance: float = 0.05,
    workers: int | None = None,
    compare_options: dict[str, Any] | None = None,
    progress: Callable[[Trial], None] | None = None,
    run_progress: Callable[[float, int, int], object] | None = None,
    **run_options: Any,
) -> Fit:
    """Fits ``parameters`` of ``model`` so that ``channel`` matches ``measured`` best.

    Args:
        model: the mechanism (not changed).
        measured: the measured signal (``.time``, ``.values``; see
            :func:`jointgap.measured.read_measured`).
        channel: the simulated channel it measures, e.g. ``"slider.ax"``.
        parameters: what to fit, with bounds (:meth:`Parameter.parse`).
        t_end: simulated time; default the end of the measurement. A restitution's
            C_max depends on it: V_avg averages the impacts of the whole run, as in
            ``jointgap calibrate`` over the same time.
        measure: the error measure minimised, one of :data:`MEASURES`.
        scan: scan points per parameter, or one count per parameter (default 16 for
            one parameter, 6 each for several): fine enough to land in the basin of the
            best fit, which for a restitution is narrow (impact times move with it).
        max_evaluations: budget of the local refinement.
        tolerance: relative rise of the error that defines the uncertainty.
        workers: parallel runs (default: the number of cores).
        compare_options: passed to :func:`jointgap.comparison.compare` (``lowpass``,
            ``offset``, ``max_lag``, ...).
        progress: called with each new trial as it finishes (from the worker threads
            too); a point evaluated before is not run nor reported again.
        run_progress: ``progress(t, steps, impacts)`` of every run, from every thread
            (:meth:`Model.simulate`), e.g. a live line.
        run_options: passed to :meth:`Model.simulate` (``rate`` defaults to 10 kHz);
            each run records ``channel`` alone (and its impact list).

    Raises:
        KeyError: ``channel`` is not an output of the model (close matches listed).
        KeyboardInterrupt: Ctrl-C; the runs on every thread stop within their next
            progress check, and ``progress`` has had every trial that finished before.
    """
    from scipy.optimize import minimize, minimize_scalar  # type: ignore[import-untyped]

    from .comparison import compare

    if measure not in MEASURES:
        raise ValueError(f"measure {measure!r}: choose one of {', '.join(MEASURES)}")
    if not parameters:
        raise ValueError("nothing to fit: give at least one parameter")
    if max_evaluations < 1:
        raise ValueError(f"max_evaluations = {max_evaluations}: at least 1 refinement trial")
    data = model.to_dict()
    for p in parameters:  # a quantity the joint's laws lack is named before any run
        probe = copy.deepcopy(data)
        mapped_here = p.quantity == "restitution" and (
            clearance_joint(probe, p.joint)["clearance"]["normal_law"]["type"] == "adams_impact"
        )
        set_clearance_parameter(probe, p.joint, "c_max" if mapped_here else p.quantity, p.low)
    times = np.asarray(measured.time, dtype=float)
    end = float(t_end) if t_end is not None else float(times[-1])
    stop = threading.Event()  # Ctrl-C reaches the engine on the main thread only

    def watch(t: float, steps: int, impacts: int) -> None:
        """Each run's progress callable: ends the runs of the other threads too."""
        if stop.is_set():
            raise KeyboardInterrupt
        if run_progress is not None:
            run_progress(t, steps, impacts)

    # Each trial keeps what its score reads: the channel compared (checked here, before
    # any run) and the impact list, which every run has: a trial of the two-clearance
    # model over 20 s at 10 kHz holds 1.6 MB of samples instead of 102 MB.
    require_channel(model_channels(data), channel)
    options = {"rate": 10_000.0, **run_options, "channels": [channel], "progress": watch}
    cmp_options = dict(compare_options or {})

    def score(result: Any) -> tuple[float, float, dict[str, float]]:
        comparison = compare(result, measured, channel, **cmp_options)
        values = {m: float(getattr(comparison.measures, m)) for m in MEASURES}
        return values[measure], float(comparison.lag), values

    mapped = [
        p.quantity == "restitution"
        and clearance_joint(data, p.joint)["clearance"]["normal_law"]["type"] == "adams_impact"
        for p in parameters
    ]
    search = [
        _search_bounds(model, p, end, options) if m else p
        for p, m in zip(parameters, mapped, strict=True)
    ]
    objective = _Objective(model, parameters, mapped, score, end, options, progress)
    n = len(parameters)
    if scan is None:
        counts = [16 if n == 1 else 6] * n
    elif isinstance(scan, int):
        counts = [scan] * n
    else:
        counts = [int(c) for c in scan]
    if len(counts) != n or min(counts) < 2:
        raise ValueError(f"scan = {scan}: at least 2 points for each of the {n} parameters")
    grids = [np.linspace(p.low, p.high, c) for p, c in zip(search, counts, strict=True)]
    candidates = [tuple(float(v) for v in c) for c in itertools.product(*grids)]
    threads = workers or os.cpu_count() or 1

    if all(p.start is not None for p in search):
        objective(tuple(float(p.start) for p in search if p.start is not None), "start")
    _parallel(threads, stop, lambda c: objective(c, "scan"), candidates)
    best = min(objective.trials, key=lambda t: t.error)
    if not math.isfinite(best.error):
        raise ValueError("every scanned candidate failed to run or to compare; check the bounds")
    steps = [(p.high - p.low) / (c - 1) for p, c in zip(search, counts, strict=True)]
    x_best = _coordinates(best, parameters, mapped)
    if n == 1:
        p = search[0]
        centre = x_best[0]
        lo, hi = max(p.low, centre - steps[0]), min(p.high, centre + steps[0])
        minimize_scalar(
            lambda x: objective((float(x),), "refine").error,
            bounds=(lo, hi),
            method="bounded",
            options={"xatol": 1e-3 * (p.high - p.low), "maxiter": max_evaluations},
        )
    else:
        # Nelder-Mead in coordinates scaled to the scan step, so one tolerance fits all.
        scale = np.array(steps)
        origin = np.array(x_best)
        simplex = [np.zeros(n)] + [0.5 * np.eye(n)[i] for i in range(n)]
        minimize(
            lambda z: objective(tuple(float(v) for v in origin + z * scale), "refine").error,
            np.zeros(n),
            method="Nelder-Mead",
            bounds=[
                ((p.low - o) / h, (p.high - o) / h)
                for p, o, h in zip(search, origin, scale, strict=True)
            ],
            options={
                "initial_simplex": np.array(simplex),
                "maxfev": max_evaluations,
                "xatol": 0.02,
                "fatol": 1e-3 * best.error,
            },
        )
    # The profile trials around the best may find a lower error (the error of a
    # restitution is rough at that scale: impacts come and go): the best is then the
    # lowest of the table and the profile is taken again around it, a few times at most.
    notes: list[str] = []
    best = min(objective.trials, key=lambda t: t.error)
    for _ in range(PROFILE_ROUNDS):
        x_best = _coordinates(best, parameters, mapped)
        uncertainty = _uncertainty(
            objective, search, mapped, best, x_best, steps, tolerance, threads, stop
        )
        lowest = min(objective.trials, key=lambda t: t.error)
        if lowest is best:
            break
        best = lowest
    else:
        x_best = _coordinates(best, parameters, mapped)
        uncertainty = [math.nan] * n
        notes.append(
            f"note: the profile trials found lower errors {PROFILE_ROUNDS} times in a row; "
            "the best is the lowest trial, its uncertainty is unknown (NaN): the error "
            "is rough near the minimum (scan finer or narrow the bounds)"
        )
    fitted = objective.model_data(x_best)
    return Fit(
        parameters=list(parameters),
        best=best,
        uncertainty=uncertainty,
        trials=sorted(objective.trials, key=lambda t: t.trial),
        model=Model.from_dict(fitted),
        measure=measure,
        notes=notes,
    )


def _parallel(
    threads: int,
    stop: threading.Event,
    trial: Callable[[tuple[float, ...]], Trial],
    candidates: Sequence[tuple[float, ...]],
) -> list[Trial]:
    """``trial`` of each candidate on ``threads`` threads, in order. On Ctrl-C (or any
    error) the candidates not started are dropped and ``stop`` ends the runs going on
    (:func:`identify`'s ``watch``) before it goes on."""
    pool = ThreadPoolExecutor(max_workers=threads)
    try:
        futures = [pool.submit(trial, c) for c in candidates]
        # Waited for in slices, not in one blocking wait: the main thread then returns to
        # Python between slices and runs its signal handlers, so that Ctrl-C stops the
        # trials even when the signal was delivered to a thread busy in the engine (one
        # blocking wait is not interrupted then, and the runs went on to their end).
        pending = set(futures)
        while pending:
            _, pending = wait(pending, timeout=0.05, return_when=FIRST_EXCEPTION)
            failed = [f for f in futures if f.done() and f.exception() is not None]
            if failed:
                failed[0].result()  # raises it: the runs going on stop (below)
        return [f.result() for f in futures]
    except BaseException:
        stop.set()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _coordinates(
    trial: Trial, parameters: Sequence[Parameter], mapped: Sequence[bool]
) -> list[float]:
    """A trial's search coordinates (C_max in place of a mapped restitution)."""
    return [
        trial.derived[f"{p.joint}.c_max"] if m else v
        for p, m, v in zip(parameters, mapped, trial.values, strict=True)
    ]


def _search_bounds(model: Model, p: Parameter, t_end: float, options: dict[str, Any]) -> Parameter:
    """The C_max bounds (and start) of a restitution of an adams_impact joint: each bound
    is Eq. 10-11 iterated twice from the model's V_avg (V_avg moves with C_max, by 20 %
    across the founding case's range), then widened by 5 % so that the trials'
    restitutions cover the bounds asked for."""
    resolved = model.clearance_data()[p.joint]
    d_max, n = resolved["d_max"], resolved["exponent"]
    quiet = {**options, "rate": 10.0, "channels": [f"{p.joint}.mode"]}

    def v_avg_and_k(c_max: float | None) -> tuple[float, float]:
        m = model if c_max is None else with_parameters(model, {f"{p.joint}.c_max": c_max})
        run = m.simulate(t_end, **quiet)
        if run.interrupted:
            raise KeyboardInterrupt
        if not run.ok:
            raise ValueError(f"the run for {p.name}'s C_max bounds {run.message}")
        return average_onset_speed(run, p.joint)[0], run.clearances[p.joint]["stiffness"]

    v_model, k = v_avg_and_k(None)

    def c_max(r: float) -> float:
        c = damping_from_restitution(r, v_model, k, d_max, n)
        for _ in range(2):
            c = damping_from_restitution(r, v_avg_and_k(c)[0], k, d_max, n)
        return c

    low = 0.95 * c_max(p.high) if p.high < 1.0 else 0.0
    high = 1.05 * c_max(p.low)
    start = None if p.start is None else min(high, max(low, c_max(p.start)))
    return Parameter(p.joint, "c_max", low, high, start)


def _uncertainty(
    run: Callable[[Sequence[float], str], Trial],
    search: Sequence[Parameter],
    mapped: Sequence[bool],
    best: Trial,
    x_best: Sequence[float],
    steps: Sequence[float],
    tolerance: float,
    threads: int,
    stop: threading.Event,
) -> list[float]:
    """Per parameter: the half-width where a parabola through the best trial and two
    neighbours along that parameter stays within ``1 + tolerance`` of the minimum; for a
    restitution searched through C_max, converted by the neighbours' restitutions."""
    probes = []
    for i, p in enumerate(search):
        h = 0.1 * steps[i]
        for sign in (-1.0, 1.0):
            v = list(x_best)
            v[i] = min(p.high, max(p.low, v[i] + sign * h))
            probes.append(tuple(v))
    trials = _parallel(threads, stop, lambda c: run(c, "profile"), probes)
    out = []
    for i in range(len(search)):
        lo, hi = trials[2 * i], trials[2 * i + 1]
        x = np.array([probes[2 * i][i], x_best[i], probes[2 * i + 1][i]])
        y = np.array([lo.error, best.error, hi.error])
        if len(set(x)) < 3 or not np.all(np.isfinite(y)):
            out.append(math.nan)
            continue
        a = np.polyfit(x, y, 2)[0]
        width = math.sqrt(tolerance * best.error / a) if a > 0 else math.inf
        if mapped[i]:  # C_max -> restitution through the neighbours' own restitutions
            width *= abs(hi.values[i] - lo.values[i]) / (x[2] - x[0])
        out.append(width)
    return out
