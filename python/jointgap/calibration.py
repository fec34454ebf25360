"""Damping calibration of an ADAMS IMPACT clearance joint (the founding paper's Eq. 10
and 11, docs/physics.md section 3).

For a target restitution r, the hysteresis damping that dissipates as much as r does at
the average onset speed V_avg of the mechanism's impacts is

    H_avg = 3 K (1 - r^2) / (4 V_avg),      C_max = H_avg d_max^n.

V_avg depends on C_max, so the paper iterates: run, average the onset speeds, compute the
new C_max, and repeat until its integer part no longer changes. The mechanism's response
to C_max is not smooth (an impact more or less changes the average), and plain
substitution can then hop around the fixed point forever; :func:`calibrate_damping`
therefore keeps the bracket of C_max values whose update went up and down and bisects
it when the update leaves it or fails to halve it. The stopping rule is the paper's: two
successive runs with the same integer part of C_max (or within a tolerance the user
gives). The answer is Eq. 10-11 applied to the last run's V_avg.

:func:`restitution_from_damping` is the inverse: the restitution implied by C_max and V_avg.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any

from .errors import CalibrationError
from .model import Model
from .results import Impact, Result

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped]

__all__ = [
    "Calibration",
    "CalibrationError",
    "ImpactSelection",
    "Iteration",
    "average_onset_speed",
    "calibrate_damping",
    "damping_from_restitution",
    "iteration_frame",
    "restitution_from_damping",
]


def damping_from_restitution(
    restitution: float, v_avg: float, stiffness: float, d_max: float, exponent: float = 1.5
) -> float:
    """C_max [N s/m] of Eq. 10-11: ``3 K (1 - r^2) / (4 V_avg) * d_max^n``."""
    _check_restitution(restitution)
    _check_positive("average onset speed V_avg", v_avg, "m/s")
    _check_positive("stiffness K", stiffness, "N/m^n")
    _check_positive("d_max", d_max, "m")
    return float(3.0 * stiffness * (1.0 - restitution**2) / (4.0 * v_avg) * d_max**exponent)


def restitution_from_damping(
    c_max: float, v_avg: float, stiffness: float, d_max: float, exponent: float = 1.5
) -> float:
    """The restitution r for which Eq. 10-11 give ``c_max`` at ``v_avg``:
    ``r = sqrt(1 - 4 V_avg C_max / (3 K d_max^n))``. Raises ValueError when C_max is so
    large that no r in [0, 1] matches (the impact would be more than plastic)."""
    if not (math.isfinite(c_max) and c_max >= 0.0):
        raise ValueError(f"C_max = {c_max!r} N*s/m: must be zero or positive")
    _check_positive("average onset speed V_avg", v_avg, "m/s")
    _check_positive("stiffness K", stiffness, "N/m^n")
    _check_positive("d_max", d_max, "m")
    loss = 4.0 * v_avg * c_max / (3.0 * stiffness * d_max**exponent)
    if loss > 1.0:
        raise ValueError(
            f"C_max = {c_max:g} N*s/m at V_avg = {v_avg:g} m/s exceeds the plastic limit "
            f"{3.0 * stiffness * d_max**exponent / (4.0 * v_avg):g} N*s/m (r^2 would be < 0)"
        )
    return math.sqrt(1.0 - loss)


@dataclass(frozen=True)
class ImpactSelection:
    """Which impacts enter V_avg: onsets in ``[start, end]`` [s] (``end=None``: to the
    end of the run) with an onset speed of at least ``min_speed`` [m/s]. The default
    takes every impact, as the paper does; a window such as ``start=0.2`` keeps the
    steady state after a speed ramp, a threshold drops the grazing re-contacts."""

    min_speed: float = 0.0
    start: float = 0.0
    end: float | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.min_speed) and self.min_speed >= 0.0):
            raise ValueError(f"impact selection min_speed = {self.min_speed!r}: must be >= 0")
        if self.end is not None and not self.end > self.start:
            raise ValueError(
                f"impact selection window {self.start:g}..{self.end:g} s: end must follow start"
            )

    def accepts(self, impact: Impact) -> bool:
        """Whether ``impact`` counts."""
        after = impact.onset_time >= self.start
        before = self.end is None or impact.onset_time <= self.end
        return after and before and impact.onset_speed >= self.min_speed

    def describe(self) -> str:
        """The rule in words, for tables and reports."""
        parts = []
        if self.start > 0.0 or self.end is not None:
            end = "end" if self.end is None else f"{self.end:g} s"
            parts.append(f"onsets from {self.start:g} s to {end}")
        if self.min_speed > 0.0:
            parts.append(f"onset speed >= {self.min_speed:g} m/s")
        return "all impacts" if not parts else "impacts with " + " and ".join(parts)


def average_onset_speed(
    result: Result, joint: str, selection: ImpactSelection | None = None
) -> tuple[float, int]:
    """V_avg [m/s] and the number of impacts averaged, for ``joint`` of ``result``.
    Raises CalibrationError when the rule selects no impact."""
    if joint not in result.impacts:
        known = ", ".join(result.impacts) or "none"
        raise CalibrationError(
            f"no clearance joint '{joint}' in the result (clearance joints: {known})"
        )
    selection = selection or ImpactSelection()
    speeds = [i.onset_speed for i in result.impacts[joint] if selection.accepts(i)]
    if not speeds:
        raise CalibrationError(
            f"joint '{joint}': no impact matches the rule ({selection.describe()}) among "
            f"{len(result.impacts[joint])} impacts"
        )
    return sum(speeds) / len(speeds), len(speeds)


@dataclass(frozen=True)
class Iteration:
    """One run of the calibration loop.

    Attributes:
        iteration: 1, 2, ...
        c_max: the damping the run used [N s/m].
        v_avg: average onset speed of the selected impacts [m/s].
        impacts: how many impacts were averaged.
        update: Eq. 10-11 at this V_avg, the next C_max of plain substitution [N s/m].
    """

    iteration: int
    c_max: float
    v_avg: float
    impacts: int
    update: float


@dataclass(frozen=True)
class Calibration:
    """The outcome of :func:`calibrate_damping`.

    Attributes:
        joint, restitution: what was calibrated, for which target.
        c_max: the calibrated damping: Eq. 10-11 at the last run's V_avg [N s/m].
        converged: whether the stopping rule was met.
        iterations: the table of runs.
        model: the model with ``c_max`` set on the joint.
        result: the last run (its impact list gives the last V_avg).
        selection: the rule that chose the impacts.
        stiffness, d_max, exponent: K, d_max and n of the joint.
    """

    joint: str
    restitution: float
    c_max: float
    converged: bool
    iterations: list[Iteration]
    model: Model
    result: Result
    selection: ImpactSelection
    stiffness: float
    d_max: float
    exponent: float
    notes: list[str] = field(default_factory=list)

    def table(self) -> str:
        """The iteration table as text, one run per line."""
        lines = [
            f"damping calibration of '{self.joint}' for restitution {self.restitution:g} "
            f"(K = {self.stiffness:.4g} N/m^{self.exponent:g}, d_max = {self.d_max:g} m, "
            f"V_avg over {self.selection.describe()})",
            f"{'iteration':>9} {'C_max [N s/m]':>14} {'impacts':>8} {'V_avg [m/s]':>12} "
            f"{'Eq. 10-11 C_max':>16}",
        ]
        for it in self.iterations:
            lines.append(
                f"{it.iteration:>9d} {it.c_max:>14.2f} {it.impacts:>8d} {it.v_avg:>12.6f} "
                f"{it.update:>16.2f}"
            )
        verdict = "converged" if self.converged else "NOT converged"
        lines.append(f"{verdict}: C_max = {self.c_max:.2f} N*s/m after {len(self.iterations)} runs")
        lines += self.notes
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        """The iteration table as a pandas DataFrame (SI units)."""
        return iteration_frame(self.iterations)


def iteration_frame(iterations: Sequence[Iteration]) -> pd.DataFrame:
    """Iterations as a table (SI units), one row each: also the table so far of a
    calibration that Ctrl-C stopped."""
    import pandas as pd

    return pd.DataFrame(
        [vars(it) for it in iterations], columns=[f.name for f in fields(Iteration)]
    )


def calibrate_damping(
    model: Model,
    joint: str,
    restitution: float,
    t_end: float | str,
    *,
    c_max: float | None = None,
    selection: ImpactSelection | None = None,
    tolerance: float | None = None,
    max_iterations: int = 40,
    progress: Callable[[Iteration], None] | None = None,
    run_progress: Callable[[float, int, int], object] | None = None,
    **run_options: Any,
) -> Calibration:
    """Iterates C_max of ``joint`` (an ``adams_impact`` clearance joint) until the
    mechanism's average onset speed and Eq. 10-11 agree for ``restitution``.

    Args:
        model: the mechanism; it is not changed.
        joint: the clearance joint to calibrate.
        restitution: target coefficient of restitution, in (0, 1].
        t_end: simulated time of each run [s]; ``run_options`` (rate, rtol, method, ...)
            go to :meth:`Model.simulate` too.
        c_max: starting damping [N s/m]; by default the model's.
        selection: which impacts enter V_avg; all by default.
        tolerance: stop when two successive runs' C_max differ by less than this
            [N s/m]; by default the paper's rule, the same integer part.
        max_iterations: most runs before giving up (``converged`` False).
        progress: called with each finished iteration (e.g. to print the table live).
        run_progress: ``progress(t, steps, impacts)`` of each run
            (:meth:`Model.simulate`), e.g. a live line.

    Raises:
        KeyboardInterrupt: Ctrl-C stopped a run; ``progress`` has had every iteration
            that finished before.
    """
    _check_restitution(restitution)
    selection = selection or ImpactSelection()
    if tolerance is not None:
        _check_positive("tolerance", tolerance, "N*s/m")
    if max_iterations < 1:
        raise ValueError(f"max_iterations = {max_iterations}: must be at least 1")
    data = model.to_dict()
    law = _impact_law(data, joint)
    resolved = model.clearance_data()[joint]  # the engine's d_max and n, defaults included
    d_max, exponent = resolved["d_max"], resolved["exponent"]
    current = float(law["c_max"] if c_max is None else c_max)
    _check_positive("starting C_max", current, "N*s/m")

    def settled(a: float, b: float) -> bool:
        if tolerance is not None:
            return abs(a - b) < tolerance
        return math.floor(a) == math.floor(b)

    iterations: list[Iteration] = []
    below: float | None = None  # largest C_max whose update went up
    above: float | None = None  # smallest C_max whose update went down
    width = math.inf
    result: Result | None = None
    stiffness = math.nan
    converged = False
    for k in range(1, max_iterations + 1):
        law["c_max"] = current
        result = Model.from_dict(data).simulate(t_end, progress=run_progress, **run_options)
        if result.interrupted:
            raise KeyboardInterrupt
        if not result.ok:
            raise CalibrationError(f"run {k} (C_max = {current:g} N*s/m) {result.message}")
        stiffness = result.clearances[joint]["stiffness"]
        try:
            v_avg, count = average_onset_speed(result, joint, selection)
        except CalibrationError as exc:
            raise CalibrationError(f"run {k} (C_max = {current:g} N*s/m): {exc}") from None
        update = damping_from_restitution(restitution, v_avg, stiffness, d_max, exponent)
        it = Iteration(k, current, v_avg, count, update)
        iterations.append(it)
        if progress is not None:
            progress(it)
        if update >= current:
            below = current if below is None else max(below, current)
        else:
            above = current if above is None else min(above, current)
        following = update
        if below is not None and above is not None:
            new_width = above - below
            if not below < update < above or new_width > 0.5 * width:
                following = 0.5 * (below + above)
            width = new_width
        if settled(current, update) or (k > 1 and settled(iterations[-2].c_max, current)):
            converged = True
            break
        current = following
    assert result is not None
    calibrated = iterations[-1].update
    law["c_max"] = calibrated
    notes = []
    last = iterations[-1]
    if converged and not settled(last.c_max, calibrated):
        implied = restitution_from_damping(last.c_max, last.v_avg, stiffness, d_max, exponent)
        notes.append(
            f"note: V_avg jumps with C_max here (an impact more or less): the last run, at "
            f"C_max = {last.c_max:.2f} N*s/m, corresponds to r = {implied:.4f}"
        )
    return Calibration(
        joint=joint,
        restitution=restitution,
        c_max=calibrated,
        converged=converged,
        iterations=iterations,
        model=Model.from_dict(data),
        result=result,
        selection=selection,
        stiffness=stiffness,
        d_max=d_max,
        exponent=exponent,
        notes=notes,
    )


def _impact_law(data: dict[str, Any], joint: str) -> dict[str, Any]:
    """The normal law dictionary (mutable, inside ``data``) of an adams_impact joint."""
    for j in data["joints"]:
        if j["name"] != joint:
            continue
        if j.get("type") != "clearance_revolute":
            raise CalibrationError(
                f"joint '{joint}' is a {j.get('type')} joint, not a clearance joint"
            )
        law: dict[str, Any] = j["clearance"]["normal_law"]
        if law.get("type") != "adams_impact":
            raise CalibrationError(
                f"joint '{joint}' uses the {law.get('type')} law: damping calibration sets the "
                "c_max of an adams_impact law (the hysteresis laws take the restitution directly)"
            )
        return law
    clearance = [j["name"] for j in data["joints"] if j.get("type") == "clearance_revolute"]
    raise CalibrationError(
        f"no joint '{joint}' in the model (clearance joints: {', '.join(clearance) or 'none'})"
    )


def _check_restitution(r: float) -> None:
    if not (math.isfinite(r) and 0.0 < r <= 1.0):
        raise ValueError(f"restitution = {r!r}: must be in (0, 1]")


def _check_positive(name: str, value: float, unit: str) -> None:
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} = {value!r} {unit}: must be positive")
