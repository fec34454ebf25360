"""One run of the engine: options in SI, the compiled core called, a Result out."""

from __future__ import annotations

import json
import math
import os
import threading
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from os import PathLike
from pathlib import Path
from typing import Any, cast

import numpy as np

from . import units as u
from ._output_size import OUTPUT_MEMORY_FRACTION, OutputSize
from ._schema import ENGINE_DEFAULTS
from .errors import OutputTooLarge, RunWarning
from .results import Result, RunStats, contact_name

__all__ = [
    "DEFAULT_OPTIONS",
    "METHODS",
    "check_output_size",
    "collect_warnings",
    "collecting_warnings",
    "machine_memory",
    "output_size",
    "run_options",
    "simulate",
    "simulate_many",
]

METHODS = ("auto", "dopri5", "sdirk4", "radau5")
"""Integration methods: automatic choice, explicit Dormand-Prince 5(4), implicit SDIRK4,
implicit Radau IIA of order 5."""

DEFAULT_OPTIONS: dict[str, Any] = dict(ENGINE_DEFAULTS["options"])
"""Defaults of the run options, the engine's own (:data:`jointgap._schema.ENGINE_DEFAULTS`),
written out in every result; ``max_steps`` None is the engine's budget for the run's
length: 1e7 steps, or 1e6 per simulated second when that is more."""


def _quantity(name: str, value: Any, dim: u.Dimension) -> float:
    try:
        return u.to_si(value, dim)
    except u.UnitError as exc:
        raise ValueError(f"option {name} {exc}") from None


def run_options(
    t_end: float | str,
    *,
    rate: float | str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    every_step: bool | None = None,
    max_step: float | str | None = None,
    channels: Sequence[str] | None = None,
    max_steps: int | None = None,
    decimate: int | None = None,
    step_peaks: bool | None = None,
    energy: bool | None = None,
    profile: bool | None = None,
    compiled: bool | None = None,
    exact_jacobian: bool | None = None,
    wear_cells: int | None = None,
    wear_start: float | str | None = None,
) -> dict[str, Any]:
    """The options of a run as the engine reads them, every key present, SI units.

    Times and rates may carry units (``"0.5 s"``, ``"10 kHz"``). ``None`` takes the
    default from :data:`DEFAULT_OPTIONS`. Raises ValueError naming a bad option.
    """
    options = dict(DEFAULT_OPTIONS)
    options["t_end"] = _quantity("t_end", t_end, u.TIME)
    if rate is not None:
        options["rate"] = _quantity("rate", rate, u.FREQUENCY)
    if max_step is not None:
        options["max_step"] = _quantity("max_step", max_step, u.TIME)
    for name, value in (("rtol", rtol), ("atol", atol)):
        if value is not None:
            options[name] = _quantity(name, value, u.DIMENSIONLESS)
    if method is not None:
        if method not in METHODS:
            raise ValueError(f"option method {method!r}: must be one of {', '.join(METHODS)}")
        options["method"] = method
    if every_step is not None:
        options["every_step"] = bool(every_step)
    if max_steps is not None:
        if int(max_steps) != max_steps or max_steps < 1:
            raise ValueError(f"option max_steps = {max_steps}: must be a whole number >= 1")
        options["max_steps"] = int(max_steps)
    if profile is not None:
        options["profile"] = bool(profile)
    if compiled is not None:
        options["compiled"] = bool(compiled)
    if exact_jacobian is not None:
        options["exact_jacobian"] = bool(exact_jacobian)
    if step_peaks is not None:
        options["step_peaks"] = bool(step_peaks)
    if energy is not None:
        options["energy"] = bool(energy)
    if wear_cells is not None:
        if int(wear_cells) != wear_cells or wear_cells < 1:
            raise ValueError(f"option wear_cells = {wear_cells}: must be a whole number")
        options["wear"] = {"cells": int(wear_cells)}
        if wear_start is not None:
            options["wear"]["start"] = _quantity("wear_start", wear_start, u.TIME)
    if decimate is not None:
        if int(decimate) != decimate or decimate < 1:
            raise ValueError(f"option decimate = {decimate}: must be a whole number >= 1")
        options["decimate"] = int(decimate)
    if channels is not None:
        if isinstance(channels, str):
            channels = [channels]
        options["channels"] = [str(c) for c in channels]
    for name in ("t_end", "rate", "max_step"):
        value = options[name]
        if value is not None and not (math.isfinite(value) and value > 0):
            raise ValueError(f"option {name} = {value:g}: must be positive")
    return options


def machine_memory() -> int | None:
    """The memory this process may use [bytes], read from the OS: the physical memory,
    or the control group's limit where that is lower (a container); None where the OS
    does not say (the output size is then not limited)."""
    try:
        memory = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None
    for limit_file in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            text = Path(limit_file).read_text().strip()
        except OSError:
            continue
        if text.isdigit():
            memory = min(memory, int(text))
    return memory if memory > 0 else None


def output_size(model: Mapping[str, Any], options: Mapping[str, Any]) -> OutputSize | None:
    """The expected output of a run of ``model`` (SI dictionary) with complete
    ``options``: samples at the output rate to ``t_end``, thinned by ``decimate``, times
    the channels the engine records; None without a rate (every accepted step is
    recorded, a number known only after the run). Raises the engine's ValueError for an
    invalid model (one that does not assemble included: the engine prepares the model
    here and keeps it for its run) or channel selection."""
    if options.get("rate") is None:
        return None
    from . import _jointgap

    channels = _jointgap.channel_names(json.dumps(model), json.dumps(options))
    return OutputSize(_samples(options), len(channels))


def _samples(options: Mapping[str, Any]) -> int:
    """Output samples of a run with complete ``options`` that have a rate."""
    samples = math.floor(float(options["t_end"]) * float(options["rate"]) * (1 + 1e-12)) + 1
    return -(-samples // int(options.get("decimate") or 1))


def check_output_size(models: Sequence[Mapping[str, Any]], options: Mapping[str, Any]) -> None:
    """Refuses runs whose samples, held in memory together, would take more than
    :data:`OUTPUT_MEMORY_FRACTION` of :func:`machine_memory`: raises
    :class:`OutputTooLarge` with the figure and the ways out. The engine counts each
    model's channels (none for a model it refuses: its run says why), preparing the
    models and keeping them for their runs."""
    memory = machine_memory()
    if memory is None or not models or options.get("rate") is None:
        return
    from . import _jointgap

    counts = _jointgap.channel_counts([json.dumps(m) for m in models], json.dumps(options))
    known = [c for c in counts if c is not None]
    if not known:
        return
    total = OutputSize(_samples(options), max(known), len(models))
    limit = int(OUTPUT_MEMORY_FRACTION * memory)
    if total.memory > limit:
        raise OutputTooLarge(total, limit, memory, options)


Progress = Callable[[float, int, int], object]
"""``progress(t, steps, impacts)``: simulated time [s], steps taken, impacts so far."""

STREAM_CHUNK = 8192
"""Samples per chunk (and Parquet row group) of a streamed run."""

PROGRESS_INTERVAL_VARIABLE = "JOINTGAP_PROGRESS_INTERVAL"
"""Environment variable: wall-clock seconds between progress reports (and Ctrl-C checks)
of every run, instead of the engine's 0.2 s; 0 reports at every check (every 16
accepted steps). For tests that must see progress however fast the machine is."""


def _interval() -> dict[str, Any]:
    """The binding's ``interval`` keyword from :data:`PROGRESS_INTERVAL_VARIABLE`, if set."""
    text = os.environ.get(PROGRESS_INTERVAL_VARIABLE)
    if text is None:
        return {}
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{PROGRESS_INTERVAL_VARIABLE} = {text!r}: must be seconds >= 0")
    return {"interval": value}


def simulate(
    model: Mapping[str, Any],
    options: Mapping[str, Any],
    progress: Progress | None = None,
    stream: str | PathLike[str] | None = None,
) -> Result:
    """Runs the engine on a model dictionary (SI) with complete options.

    ``progress`` is called about every 0.2 s of wall time (see
    :data:`PROGRESS_INTERVAL_VARIABLE`). With ``stream``, the samples go to that Parquet
    file in chunks as the run goes, and the Result reads them from there. Raises the
    engine's ValueError when the model or the options are invalid; a run that stops
    early returns a Result with status ``failed``, one stopped by Ctrl-C (or by a
    KeyboardInterrupt raised in ``progress``) with status ``interrupted``, each with
    what it computed.
    """
    from . import _jointgap

    if stream is None:
        check_output_size([model], options)
        arrays = _jointgap.simulate(json.dumps(model), json.dumps(options), progress, **_interval())
        return _warned(_result(arrays, model, options))
    from ._stream import ParquetSink, StoredChannels, read_time

    sink = ParquetSink(stream)
    names: list[str] = []
    try:
        _, names, _, summary = _jointgap.simulate(
            json.dumps(model), json.dumps(options), progress, sink, STREAM_CHUNK, **_interval()
        )
    finally:
        sink.close(names)
    times = read_time(stream)
    data = StoredChannels(stream, list(names), len(times))
    return _warned(_result((times, names, data, summary), model, options))


BatchProgress = Callable[[int, int], object]
"""``progress(running, ended)``: runs of a batch going now, runs ended."""


def simulate_many(
    models: Sequence[Mapping[str, Any]],
    options: Mapping[str, Any],
    threads: int | None = None,
    progress: BatchProgress | None = None,
) -> tuple[list[Result | ValueError | None], bool]:
    """Runs model dictionaries (SI) with the same complete options on ``threads`` threads
    in the engine (all cores by default, the GIL released). Returns, in order, each one's
    Result (bit for bit the one :func:`simulate` gives) or the ValueError that model
    raised, and whether Ctrl-C stopped the batch: the runs going then end with status
    ``interrupted`` and what they computed, and the models not started are None.
    ``progress`` is called, and Ctrl-C checked, about every 0.2 s of wall time (see
    :data:`PROGRESS_INTERVAL_VARIABLE`); a KeyboardInterrupt it raises stops the batch as
    Ctrl-C does, any other exception stops it and propagates. The runs' notes
    (:func:`impacts_between_samples`) go to each Result's ``warnings`` only, not to
    Python's warnings."""
    from . import _jointgap

    if threads is not None and threads < 1:
        raise ValueError(f"threads = {threads}: must be at least 1")
    check_output_size(models, options)
    texts = [json.dumps(m) for m in models]
    out: list[Result | ValueError | None] = []
    batch, interrupted = _jointgap.simulate_batch(
        texts, json.dumps(options), threads, progress, **_interval()
    )
    for model, (arrays, error) in zip(models, batch, strict=True):
        out.append(error if arrays is None else _result(arrays, model, options))
    return out, interrupted


def _result(arrays: Any, model: Mapping[str, Any], options: Mapping[str, Any]) -> Result:
    time, names, data, summary_json = arrays
    # The engine's arrays are the Result's own: frozen here, they are not copied there.
    for array in (time, data):
        if isinstance(array, np.ndarray):
            array.flags.writeable = False
    summary = json.loads(summary_json)
    status = summary["status"]
    message = ""
    if status["status"] == "interrupted":
        message = f"interrupted at t = {status['time']:.6g} s"
    elif status["status"] != "finished":
        message = f"failed at t = {status.get('time', math.nan):.6g} s: {status.get('reason', '')}"
    result = Result(
        time=time,
        channels=list(names),
        data=data,
        stats=cast(RunStats, dict(summary["stats"])),
        status=status["status"],
        message=message,
        warnings=list(summary.get("warnings", [])),
        model=dict(model),
        options=dict(options),
        impacts=summary.get("impacts", []),
        clearances=summary.get("clearances", []),
        wear=summary.get("wear", []),
        samples=summary.get("samples"),
        mode_time={contact_name(j): j["mode_time"] for j in summary.get("impacts", [])},
        peaks=summary.get("peaks", []),
    )
    note = impacts_between_samples(result)
    if note is not None:
        result.warnings.append(note)
    collect_warnings(result.warnings)
    return result


_collectors: dict[int, list[str]] = {}
"""The open :func:`collecting_warnings`, by the identity of their lists."""
_collectors_lock = threading.Lock()


@contextmanager
def collecting_warnings() -> Iterator[list[str]]:
    """Collects the warnings of every run made in this process while it is open, in any
    thread (a batch, a study's threads, an identification's trials), in the order they
    come: what a command that runs many models prints once at its end. Lines repeat as
    often as runs give them."""
    lines: list[str] = []
    with _collectors_lock:
        _collectors[id(lines)] = lines
    try:
        yield lines
    finally:
        with _collectors_lock:
            del _collectors[id(lines)]


def collect_warnings(lines: Iterable[str]) -> None:
    """Hands a run's warnings to every open :func:`collecting_warnings` (every Result
    made here does; a study passes on those of its cases run elsewhere)."""
    lines = list(lines)
    with _collectors_lock:
        for collector in _collectors.values():
            collector.extend(lines)


def _warned(result: Result) -> Result:
    """The result, its notes of :func:`impacts_between_samples` also raised as a
    :class:`~jointgap.results.RunWarning` at the caller of ``Model.simulate``."""
    for note in result.warnings:
        if note.startswith(_BETWEEN_SAMPLES):
            warnings.warn(note, RunWarning, stacklevel=4)
    return result


_BETWEEN_SAMPLES = "impacts between output samples: "


def impacts_between_samples(result: Result) -> str | None:
    """A note when impacts fell between two output samples (no sample from onset to
    separation): the sampled channels then miss their forces and accelerations entirely
    (with very stiff contact, every impact can). It counts them per clearance joint, gives
    the shortest impact and the output interval, and says how to see them; None when
    every impact has a sample (an every-step run always has one, at the located onset).
    """
    if len(result.time) < 2:
        return None
    parts = []
    shortest = math.inf
    last = result.time[-1]
    for joint, impacts in result.impacts.items():
        closed = [i for i in impacts if i.onset_time + i.duration <= last]
        if not closed:
            continue
        onset = np.array([i.onset_time for i in closed])
        end = onset + np.array([i.duration for i in closed])
        first = np.searchsorted(result.time, onset, side="left")
        after = np.searchsorted(result.time, end, side="right")
        missed = int(np.count_nonzero(after <= first))
        if missed:
            parts.append(f"{joint}: {missed} of {len(impacts)}")
            shortest = min(shortest, min(i.duration for i in closed))
    if not parts:
        return None
    interval = float(np.median(np.diff(result.time)))
    # A graze (onset and separation at one located time) lasts no time: no rate shows it.
    rate = f" or raise the rate above {1e-3 / shortest:.3g} kHz" if shortest > 0 else ""
    return (
        f"{_BETWEEN_SAMPLES}{'; '.join(parts)} impacts had no output sample from onset to "
        f"separation (shortest {1e3 * shortest:.3g} ms, output interval {1e3 * interval:.3g} "
        "ms): the sampled channels miss their forces and accelerations (the impact list has "
        "them all); to see them, record every step (--every-step, every_step=True)"
        f"{rate}{' (ten times that to resolve their peaks)' if rate else ''}"
    )
