"""Wear over life: the clearance of a mechanism's revolute clearance joints grows as it
runs, and the dynamics change with it (docs/wear.md, "Over life").

Each evaluation runs the mechanism with the joints' current worn profiles through its
warm-up and a few steady cycles, the engine accumulating Archard's wear on the parts'
angular grids over the steady cycles only; the wear per cycle, times the coefficient,
is the rate at which the profiles grow. The profiles advance by a number of cycles at a
time (explicit Euler in the cycle count), the step chosen by step doubling: a step of
``n`` cycles is compared with two of ``n/2``, the second half's rate evaluated on the
profile its first half wore, and accepted when the two differ by less than
``tolerance`` of the predicted depth; the two-halves result is kept. ``every_cycle``
runs each simulated cycle's wear into the profiles instead, with no extrapolation, to
check the extrapolation against.

:func:`predict_wear` returns a :class:`WearPrediction`; with ``out`` it writes, after
every accepted update, the state (``state.json``, from which the same call resumes),
the profiles, the history table and, at the end, the figures and a report page.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd  # type: ignore[import-untyped]

from . import units as u
from ._schema import ENGINE_DEFAULTS
from ._wear_prediction import HISTORY_COLUMNS, WearPrediction, WearStep
from .errors import ModelError
from .model import Model, Quantity
from .results import Result

__all__ = [
    "HISTORY_COLUMNS",
    "STEP_BUDGET",
    "WEAR_COEFFICIENT",
    "OutOfRange",
    "WearPrediction",
    "WearStep",
    "effective_clearance",
    "predict_wear",
    "resolve_coefficient",
    "wear_pairs",
    "worn_volume",
    "write_prediction",
]

WEAR_COEFFICIENT = u.PRESSURE**-1
"""The dimension of a dimensional wear coefficient k: m^2/N, e.g. ``"1e-4 mm^3/(N*m)"``."""

STEP_BUDGET = 20.0
"""A run with worn profiles may take this many times the steps of the first (unworn)
run; beyond it the prediction stops (:class:`OutOfRange`)."""


Progress = Callable[[WearStep], object]


def wear_pairs() -> dict[str, dict[str, Any]]:
    """The engine's wear coefficients of common pairs, by name: ``pair`` (in words),
    ``archard_k`` (dimensionless), ``hardness`` [Pa] and ``coefficient`` [1/Pa]."""
    return {p["name"]: dict(p) for p in ENGINE_DEFAULTS["wear_pairs"]}


def resolve_coefficient(value: Quantity | str | None) -> tuple[float, str | None]:
    """A wear coefficient given by pair name (:func:`wear_pairs`), as a quantity with
    units (``"1e-4 mm^3/(N*m)"``) or in 1/Pa; ``None`` takes the engine's default pair."""
    pairs = wear_pairs()
    if value is None:
        value = str(ENGINE_DEFAULTS["wear_pair"])
    if isinstance(value, str) and value in pairs:
        return float(pairs[value]["coefficient"]), value
    try:
        k = u.to_si(value, WEAR_COEFFICIENT)
    except (u.UnitError, ValueError, TypeError) as exc:
        raise ValueError(
            f"wear coefficient {value!r}: give a pair ({', '.join(pairs)}) or a value in "
            f"m^2/N, e.g. '1e-4 mm^3/(N*m)' ({exc})"
        ) from None
    if not (math.isfinite(k) and k > 0):
        raise ValueError(f"wear coefficient {value!r} = {k} 1/Pa: must be positive")
    return k, None


def _period_and_warmup(
    period: Quantity | None, warmup: Quantity | None
) -> tuple[float | None, float | None]:
    p = None if period is None else u.to_si(period, u.TIME)
    w = None if warmup is None else u.to_si(warmup, u.TIME)
    if p is not None and not (math.isfinite(p) and p > 0):
        raise ValueError(f"period = {p} s: must be positive")
    if w is not None and not (math.isfinite(w) and w >= 0):
        raise ValueError(f"warmup = {w} s: must be zero or positive")
    return p, w


def _driver(model: Model) -> tuple[str, dict[str, Any]] | None:
    drivers = list(model.drivers.values())
    if len(drivers) != 1:
        return None
    d = drivers[0]
    return str(d["joint"]), d


WEARING_TYPES = ("clearance_revolute", "clearance_cylindrical")
"""The joints that wear: a planar model's and a spatial model's dry journal in its
bearing (docs/wear.md)."""


@dataclass
class _Setup:
    """What every evaluation shares."""

    model: dict[str, Any]
    joints: list[str]
    cells: int
    warmup: float
    period: float
    cycles_per_run: int
    coefficient: float
    sim: dict[str, Any]
    watch: str | None
    nominal: dict[str, dict[str, float]]
    budget: int | None = None


def _setup(
    model: Model,
    joints: Sequence[str] | None,
    cells: int,
    period: Quantity | None,
    warmup: Quantity | None,
    cycles_per_run: int,
    coefficient: float,
    sim: Mapping[str, Any],
    watch: str | None,
    length: Quantity | None,
) -> _Setup:
    wearing = WEARING_TYPES[1 if model.spatial else 0]
    entries = model.joints
    names = [n for n, j in entries.items() if j["type"] == wearing]
    if joints is not None:
        for name in joints:
            if name not in entries:
                raise ModelError(f"no joint '{name}'", kind="joint", name=name)
            if entries[name]["type"] != wearing:
                raise ModelError(
                    f"joint '{name}' is {entries[name]['type']}: wear is modelled for "
                    f"{' and '.join(WEARING_TYPES)} joints",
                    kind="joint",
                    name=name,
                )
        names = list(joints)
    if not names:
        raise ModelError(f"the model has no {wearing} joint to wear")
    if length is not None and model.spatial:
        raise ValueError(
            f"length = {length}: a spatial joint's journal gives its own length (the joint's "
            "'length' key); the prediction's length fills planar joints only"
        )
    if length is not None:
        data = model.to_dict()
        for joint in data["joints"]:
            if joint["name"] in names and joint["clearance"].get("length") is None:
                joint["clearance"]["length"] = u.to_si(length, u.LENGTH)
        model = Model.from_dict(data)
        entries = model.joints
    for name in names:
        if _length(model, name) is None:
            raise ModelError(
                "wear needs the bearing's length along its axis (the line contact's): "
                "give the joint's 'length' (or the prediction's length)",
                kind="joint",
                name=name,
                key="length",
            )
    if int(cells) != cells or cells < 8:
        raise ValueError(f"cells = {cells}: a wear grid has at least 8 cells")
    if int(cycles_per_run) != cycles_per_run or cycles_per_run < 1:
        raise ValueError(f"cycles_per_run = {cycles_per_run}: must be a whole number >= 1")
    p, w = _period_and_warmup(period, warmup)
    if p is None or w is None:
        found = _driver(model)
        if found is None:
            raise ValueError(
                "give the cycle's period (and the warm-up): the model has no single driver "
                "to take them from"
            )
        joint, driver = found
        profile = driver["profile"]
        ramp = float(profile.get("ramp_time", 0.0))
        if w is None:
            w = ramp
        if p is None:
            probe = model.simulate(max(w, 1e-3), channels=[f"{joint}.omega"], **sim)
            omega = abs(float(probe[f"{joint}.omega"][-1]))
            if not omega > 0:
                raise ValueError(
                    f"driver '{driver['name']}' is at rest after the warm-up: give the period"
                )
            p = 2 * math.pi / omega
        # One cycle more settles what the ramp's end started.
        if warmup is None:
            w += p
    nominal = {
        name: {
            k: float(v)
            for k, v in model.clearance_data()[name].items()
            if k in ("bearing_radius", "journal_radius", "clearance")
        }
        | {"length": float(_length(model, name) or 0.0)}
        for name in names
    }
    if watch is None:
        watch = _default_watch(model)
    return _Setup(
        model=model.to_dict(),
        joints=names,
        cells=int(cells),
        warmup=float(w),
        period=float(p),
        cycles_per_run=int(cycles_per_run),
        coefficient=coefficient,
        sim=dict(sim),
        watch=watch,
        nominal=nominal,
    )


def _length(model: Model, name: str) -> float | None:
    """Joint ``name``'s length along its axis [m]: a planar joint's clearance ``length``,
    a spatial journal's own."""
    joint = model.joints[name]
    value = joint.get("length") if model.spatial else joint.get("clearance", {}).get("length")
    return None if value is None else float(value)


def _default_watch(model: Model) -> str | None:
    """The acceleration along its guide of the first body on a prismatic joint (the
    slider of a slider-crank): ``<body>.ax``, ``ay`` or ``az`` by its axis's largest
    component."""
    for joint in model.joints.values():
        if joint["type"] == "prismatic" and joint["body_j"] != "ground":
            axis = [abs(float(x)) for x in joint.get("axis", [1.0, 0.0])]
            return f"{joint['body_j']}.a{'xyz'[axis.index(max(axis))]}"
    return None


@dataclass
class _Rate:
    """Wear per cycle [m] on each joint's grids at one profile, and what the run showed."""

    bearing: dict[str, np.ndarray]
    journal: dict[str, np.ndarray]
    peak_force: dict[str, float]
    peak_watch: float


def _with_profiles(s: _Setup, profiles: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> Model:
    data = json.loads(json.dumps(s.model))
    for joint in data["joints"]:
        if joint["name"] in profiles:
            bearing, journal = profiles[joint["name"]]
            joint["clearance"]["bearing_wear"] = [float(x) for x in bearing]
            joint["clearance"]["journal_wear"] = [float(x) for x in journal]
    return Model.from_dict(data)


def _force_channels(s: _Setup, joint: str) -> list[str]:
    """The channels of joint ``joint``'s normal force: a spatial journal's two ends'
    (docs/outputs.md), whose sum is the joint's."""
    if s.model.get("dimension") == 3:
        return [f"{joint}.p1.fn", f"{joint}.p2.fn"]
    return [f"{joint}.fn"]


class OutOfRange(Exception):
    """Worn profiles beyond what the contact model follows."""


def _evaluate(s: _Setup, profiles: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> _Rate:
    model = _with_profiles(s, profiles)
    t_end = s.warmup + s.cycles_per_run * s.period
    forces = {j: _force_channels(s, j) for j in s.joints}
    channels = [c for j in s.joints for c in forces[j]] + ([s.watch] if s.watch else [])
    result: Result = model.simulate(
        t_end,
        channels=channels,
        wear_cells=s.cells,
        wear_start=s.warmup,
        max_steps=s.budget,
        **s.sim,
    )
    if result.status != "finished":
        steps = result.stats.get("accepted_steps", 0) + result.stats.get("rejected_steps", 0)
        if s.budget is not None and steps >= s.budget:
            raise OutOfRange(
                f"a run with the worn profiles took more than {s.budget} steps, "
                f"{STEP_BUDGET:g} times the unworn run's: its contact chatters on the worn "
                "profiles, which the contact model does not resolve"
            )
        raise RuntimeError(f"a wear run stopped: {result.message}")
    if s.budget is None:
        s.budget = int(STEP_BUDGET * max(result.stats.get("accepted_steps", 0), 1000))
    steady = result.time >= s.warmup
    scale = s.coefficient / s.cycles_per_run
    return _Rate(
        bearing={j: scale * np.asarray(result.wear[j]["bearing_depth"]) for j in s.joints},
        journal={j: scale * np.asarray(result.wear[j]["journal_depth"]) for j in s.joints},
        peak_force={j: float(np.max(sum(result[c][steady] for c in forces[j]))) for j in s.joints},
        peak_watch=float(np.max(np.abs(result[s.watch][steady]))) if s.watch else math.nan,
    )


def _advance(
    profiles: Mapping[str, tuple[np.ndarray, np.ndarray]], rate: _Rate, n: float
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    return {j: (b + n * rate.bearing[j], w + n * rate.journal[j]) for j, (b, w) in profiles.items()}


def _largest(a: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> float:
    return max(max(float(np.max(np.abs(b))), float(np.max(np.abs(w)))) for b, w in a.values())


def _difference(
    a: Mapping[str, tuple[np.ndarray, np.ndarray]], b: Mapping[str, tuple[np.ndarray, np.ndarray]]
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    return {j: (a[j][0] - b[j][0], a[j][1] - b[j][1]) for j in a}


def effective_clearance(
    nominal: Mapping[str, float], bearing: np.ndarray, journal: np.ndarray
) -> float:
    """The largest radial clearance of a worn joint [m]: the nominal one plus the deepest
    bearing wear plus the deepest journal wear (the gap where both deepest spots face
    each other)."""
    return float(nominal["clearance"] + np.max(bearing) + np.max(journal))


def worn_volume(nominal: Mapping[str, float], depth: np.ndarray, radius_key: str) -> float:
    """The volume [m^3] a part lost: each cell's depth times its arc and the length."""
    arc = nominal[radius_key] * 2 * math.pi / len(depth)
    return float(np.sum(depth) * arc * nominal["length"])


def _rows(
    s: _Setup, cycles: float, profiles: Mapping[str, tuple[np.ndarray, np.ndarray]], rate: _Rate
) -> list[dict[str, Any]]:
    rows = []
    for j, (b, w) in profiles.items():
        n = s.nominal[j]
        rows.append(
            {
                "cycles": cycles,
                "joint": j,
                "max_bearing_depth": float(np.max(b)),
                "max_journal_depth": float(np.max(w)),
                "bearing_volume": worn_volume(n, b, "bearing_radius"),
                "journal_volume": worn_volume(n, w, "journal_radius"),
                "clearance": effective_clearance(n, b, w),
                "peak_contact_force": rate.peak_force[j],
                "peak_watch": rate.peak_watch,
            }
        )
    return rows


def _fingerprint(
    s: _Setup,
    target: float,
    tolerance: float,
    every_cycle: bool,
    limit: float | None,
    first: float | None,
) -> str:
    text = json.dumps(
        [
            s.model,
            s.joints,
            s.cells,
            s.warmup,
            s.period,
            s.cycles_per_run,
            s.coefficient,
            s.sim,
            target,
            tolerance,
            every_cycle,
            limit,
            first,
        ],
        sort_keys=True,
        default=str,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def predict_wear(
    model: Model,
    cycles: float,
    *,
    coefficient: Quantity | str | None = None,
    joints: Sequence[str] | None = None,
    cells: int = 36,
    period: Quantity | None = None,
    warmup: Quantity | None = None,
    cycles_per_run: int = 1,
    tolerance: float = 0.05,
    first_step: float | None = None,
    clearance_limit: Quantity | None = None,
    every_cycle: bool = False,
    watch: str | None = None,
    length: Quantity | None = None,
    out: str | os.PathLike[str] | None = None,
    progress: Progress | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
) -> WearPrediction:
    """Predicts the wear of the model's journals in their bearings over ``cycles`` cycles.

    Args:
        model: a planar model whose ``clearance_revolute`` joints give their ``length``,
            or a spatial model with dry ``clearance_cylindrical`` joints.
        cycles: cycles to wear through (a cycle is ``period``).
        coefficient: Archard's dimensional wear coefficient k: a pair's name
            (:func:`wear_pairs`), a value with units (``"1e-4 mm^3/(N*m)"``) or in 1/Pa;
            by default the engine's pair (steel in brass, dry).
        joints: the joints to wear; by default every one of those.
        cells: cells of each part's angular grid (10 deg by default).
        period, warmup: the cycle's duration and the time before the first steady cycle
            [s]; by default from the model's one driver: the warm-up its ramp plus one
            cycle, the period one turn at the speed it reaches.
        cycles_per_run: steady cycles each evaluation simulates and averages.
        tolerance: the largest difference, as a fraction of the predicted depth, between
            one step and two half steps (step doubling).
        first_step: cycles of the first step; by default those that wear 1 % of the
            nominal clearance.
        clearance_limit: stop when a joint's largest clearance reaches it [m].
        every_cycle: no extrapolation: each evaluation's cycles wear the profiles as they
            were simulated (slow; to check the extrapolation).
        length: the bearing length [m] of the planar joints whose model gives none (the
            founding case's paper does not give one).
        watch: a channel whose largest magnitude over the steady cycles the history keeps
            (by default the slider's acceleration along its guide).
        out: a folder for the state, profiles, history, figures and report; a call with
            the same arguments and folder resumes from its state.
        progress: called with a :class:`WearStep` after each accepted update.
        rtol, atol, method: the runs' integration options.
    """
    k, pair = resolve_coefficient(coefficient)
    if not (math.isfinite(cycles) and cycles > 0):
        raise ValueError(f"cycles = {cycles}: must be positive")
    if not (0 < tolerance < 1):
        raise ValueError(f"tolerance = {tolerance}: must lie in (0, 1)")
    limit = None if clearance_limit is None else u.to_si(clearance_limit, u.LENGTH)
    sim = {
        key: v for key, v in (("rtol", rtol), ("atol", atol), ("method", method)) if v is not None
    }
    s = _setup(model, joints, cells, period, warmup, cycles_per_run, k, sim, watch, length)
    if limit is not None:
        for j in s.joints:
            if limit <= s.nominal[j]["clearance"]:
                raise ValueError(
                    f"clearance_limit = {limit} m is not above joint '{j}''s clearance "
                    f"{s.nominal[j]['clearance']} m"
                )
    folder = None if out is None else Path(out)
    key = _fingerprint(s, cycles, tolerance, every_cycle, limit, first_step)
    zero = np.zeros(s.cells)
    state: dict[str, Any] = {
        "cycles": 0.0,
        "step": first_step,
        "runs": 0,
        "profiles": {j: (zero.copy(), zero.copy()) for j in s.joints},
        "history": [],
        "saved": [],
    }
    if folder is not None:
        state = _resume(folder, key, state)
    profiles: dict[str, tuple[np.ndarray, np.ndarray]] = state["profiles"]
    done: float = state["cycles"]
    runs: int = state["runs"]
    history: list[dict[str, Any]] = state["history"]
    saved: list[tuple[str, float, np.ndarray, np.ndarray]] = state["saved"]
    step: float | None = state["step"]
    status, message, to_limit = "finished", "", None

    def evaluate(p: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> _Rate:
        nonlocal runs
        runs += 1
        return _evaluate(s, p)

    def keep(
        cycles_now: float, p: Mapping[str, tuple[np.ndarray, np.ndarray]], rate: _Rate
    ) -> None:
        history.extend(_rows(s, cycles_now, p, rate))
        saved.extend((j, cycles_now, b.copy(), w.copy()) for j, (b, w) in p.items())

    try:
        rate = evaluate(profiles)
        if not history:
            keep(0.0, profiles, rate)
        smallest = min(n["clearance"] for n in s.nominal.values())
        while done < cycles * (1 - 1e-12):
            if every_cycle:
                n = float(min(s.cycles_per_run, cycles - done))
                new = _advance(profiles, rate, n)
                next_rate = evaluate(new)
            else:
                fastest = _largest({j: (rate.bearing[j], rate.journal[j]) for j in s.joints})
                if step is None:
                    step = 0.01 * smallest / max(fastest, 1e-300)
                n = min(step, cycles - done)
                while True:
                    full = _advance(profiles, rate, n)
                    half = _advance(profiles, rate, n / 2)
                    try:
                        mid_rate = evaluate(half)
                        new = _advance(half, mid_rate, n / 2)
                        error = _largest(_difference(new, full))
                        ratio = error / max(tolerance * _largest(new), 1e-300)
                        # Below the simulated cycles an update extrapolates nothing: the
                        # difference left is the cycles' scatter, not the step's error.
                        if ratio <= 1 or n <= s.cycles_per_run:
                            next_rate = evaluate(new)
                            break
                    except OutOfRange:
                        # A step so long that its extrapolated profiles are ones the
                        # wear itself would not reach: a shorter one.
                        if n <= s.cycles_per_run:
                            raise
                        ratio = 25.0
                    n = max(s.cycles_per_run, n * max(0.2, 0.9 / math.sqrt(ratio)))
                step = n * min(2.0, 0.9 / math.sqrt(max(ratio, 0.25**2)))
            largest = max(effective_clearance(s.nominal[j], *new[j]) for j in s.joints)
            if limit is not None and largest >= limit:
                before = max(effective_clearance(s.nominal[j], *profiles[j]) for j in s.joints)
                to_limit = done + n * (limit - before) / (largest - before)
                status = "limit"
                message = f"a joint's clearance reached {limit} m after {to_limit:.4g} cycles"
            profiles, rate, done = new, next_rate, done + n
            keep(done, profiles, rate)
            if folder is not None:
                _save_state(folder, key, done, step, runs, profiles, history, saved)
            if progress is not None:
                progress(WearStep(done, n, largest, runs))
            if status == "limit":
                break
    except OutOfRange as exc:
        status, message = "out_of_range", f"stopped after {done:.6g} cycles: {exc}"
    except KeyboardInterrupt:
        status, message = "interrupted", f"interrupted after {done:.6g} cycles"
    except (RuntimeError, ModelError, ValueError) as exc:
        status, message = "failed", f"failed after {done:.6g} cycles: {exc}"
    prediction = WearPrediction(
        coefficient=k,
        pair=pair,
        cycles=done,
        status=status,
        message=message,
        cycles_to_limit=to_limit,
        history=pd.DataFrame(history, columns=list(HISTORY_COLUMNS)),
        profiles=_profiles_by_joint(saved),
        angles=2 * math.pi * np.arange(s.cells) / s.cells,
        runs=runs,
        watch=s.watch,
        nominal=s.nominal,
    )
    if folder is not None:
        write_prediction(prediction, folder)
    return prediction


def _profiles_by_joint(
    saved: Sequence[tuple[str, float, np.ndarray, np.ndarray]],
) -> dict[str, list[tuple[float, np.ndarray, np.ndarray]]]:
    out: dict[str, list[tuple[float, np.ndarray, np.ndarray]]] = {}
    for joint, cycles, b, w in saved:
        out.setdefault(joint, []).append((cycles, b, w))
    return out


def _save_state(
    folder: Path,
    key: str,
    cycles: float,
    step: float | None,
    runs: int,
    profiles: Mapping[str, tuple[np.ndarray, np.ndarray]],
    history: Sequence[Mapping[str, Any]],
    saved: Sequence[tuple[str, float, np.ndarray, np.ndarray]],
) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    data = {
        "key": key,
        "cycles": cycles,
        "step": step,
        "runs": runs,
        "profiles": {j: [b.tolist(), w.tolist()] for j, (b, w) in profiles.items()},
        "history": list(history),
        "saved": [[j, c, b.tolist(), w.tolist()] for j, c, b, w in saved],
    }
    partial = folder / "state.json.partial"
    partial.write_text(json.dumps(data), encoding="utf-8")
    partial.replace(folder / "state.json")


def _resume(folder: Path, key: str, fresh: dict[str, Any]) -> dict[str, Any]:
    path = folder / "state.json"
    if not path.exists():
        return fresh
    data = json.loads(path.read_text(encoding="utf-8"))
    if data.get("key") != key:
        raise ValueError(
            f"{path} holds a prediction of other inputs (model, coefficient, options): "
            "give another folder or remove it"
        )
    return {
        "cycles": float(data["cycles"]),
        "step": data["step"],
        "runs": int(data["runs"]),
        "profiles": {j: (np.asarray(b), np.asarray(w)) for j, (b, w) in data["profiles"].items()},
        "history": list(data["history"]),
        "saved": [(j, float(c), np.asarray(b), np.asarray(w)) for j, c, b, w in data["saved"]],
    }


def write_prediction(p: WearPrediction, folder: str | os.PathLike[str]) -> list[Path]:
    """Writes a prediction's tables, figures and report page into ``folder``: the
    history (``history.csv``), each joint's profiles (``profiles_<joint>.csv``: the
    angle [deg], then the bearing's and the journal's depth [m] after each update),
    ``summary.json``, the figures and ``report.html``. Returns the files written."""
    from .report.wear import write_wear_report
    from .wear_plots import wear_figures

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = [folder / "history.csv"]
    p.history.to_csv(written[0], index=False)
    for joint, steps in p.profiles.items():
        table = {"angle_deg": np.degrees(p.angles)}
        for cycles, b, w in steps:
            table[f"bearing_{cycles:.6g}"] = b
            table[f"journal_{cycles:.6g}"] = w
        path = folder / f"profiles_{joint}.csv"
        pd.DataFrame(table).to_csv(path, index=False)
        written.append(path)
    summary = {
        "coefficient": p.coefficient,
        "pair": p.pair,
        "cycles": p.cycles,
        "status": p.status,
        "message": p.message,
        "cycles_to_limit": p.cycles_to_limit,
        "runs": p.runs,
        "watch": p.watch,
        "joints": {
            j: {
                "nominal": p.nominal[j],
                "max_bearing_depth": float(np.max(steps[-1][1])),
                "max_journal_depth": float(np.max(steps[-1][2])),
            }
            for j, steps in p.profiles.items()
        },
    }
    path = folder / "summary.json"
    path.write_text(json.dumps(summary, indent=2), encoding="utf-8")
    written.append(path)
    figures = wear_figures(p, folder)
    written.extend(figures)
    written.append(write_wear_report(p, folder / "report.html", figures))
    return written
