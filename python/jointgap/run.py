"""One run of the engine: options in SI, the compiled core called, a Result out."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping, Sequence
from os import PathLike
from typing import Any

from . import units as u
from .results import Result

__all__ = ["DEFAULT_OPTIONS", "METHODS", "run_options", "simulate", "simulate_many"]

METHODS = ("auto", "dopri5", "sdirk4", "radau5")
"""Integration methods: automatic choice, explicit Dormand-Prince 5(4), implicit SDIRK4,
implicit Radau IIA of order 5."""

DEFAULT_OPTIONS: dict[str, Any] = {
    "rate": None,
    "every_step": False,
    "rtol": 1e-8,
    "atol": 1e-11,
    "method": "auto",
    "max_step": None,
    "max_steps": 10_000_000,
    "channels": None,
    "decimate": 1,
    "energy": False,
    "profile": False,
}
"""Defaults of the run options (the engine's own defaults, written out in every result)."""


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
    energy: bool | None = None,
    profile: bool | None = None,
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
        options["max_steps"] = int(max_steps)
    if profile is not None:
        options["profile"] = bool(profile)
    if energy is not None:
        options["energy"] = bool(energy)
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


Progress = Callable[[float, int, int], object]
"""``progress(t, steps, impacts)``: simulated time [s], steps taken, impacts so far."""

STREAM_CHUNK = 8192
"""Samples per chunk (and Parquet row group) of a streamed run."""


def simulate(
    model: Mapping[str, Any],
    options: Mapping[str, Any],
    progress: Progress | None = None,
    stream: str | PathLike[str] | None = None,
) -> Result:
    """Runs the engine on a model dictionary (SI) with complete options.

    ``progress`` is called about every 0.2 s of wall time. With ``stream``, the samples
    go to that Parquet file in chunks as the run goes, and the Result reads them from
    there. Raises the engine's ValueError when the model or the options are invalid; a
    run that stops early returns a Result with status ``failed``.
    """
    from . import _jointgap

    if stream is None:
        arrays = _jointgap.simulate(json.dumps(model), json.dumps(options), progress)
        return _result(arrays, model, options)
    from .stream import ParquetSink, StoredChannels, read_time

    sink = ParquetSink(stream)
    names: list[str] = []
    try:
        _, names, _, summary = _jointgap.simulate(
            json.dumps(model), json.dumps(options), progress, sink, STREAM_CHUNK
        )
    finally:
        sink.close(names)
    times = read_time(stream)
    data = StoredChannels(stream, list(names), len(times))
    return _result((times, names, data, summary), model, options)


def simulate_many(
    models: Sequence[Mapping[str, Any]], options: Mapping[str, Any], threads: int | None = None
) -> list[Result | ValueError]:
    """Runs model dictionaries (SI) with the same complete options on ``threads`` threads
    in the engine (all cores by default, the GIL released): in order, each one's Result
    (bit for bit the one :func:`simulate` gives) or the ValueError that model raised."""
    from . import _jointgap

    if threads is not None and threads < 1:
        raise ValueError(f"threads = {threads}: must be at least 1")
    texts = [json.dumps(m) for m in models]
    out: list[Result | ValueError] = []
    batch = _jointgap.simulate_batch(texts, json.dumps(options), threads)
    for model, (arrays, error) in zip(models, batch, strict=True):
        out.append(ValueError(error) if arrays is None else _result(arrays, model, options))
    return out


def _result(arrays: Any, model: Mapping[str, Any], options: Mapping[str, Any]) -> Result:
    time, names, data, summary_json = arrays
    summary = json.loads(summary_json)
    status = summary["status"]
    message = ""
    if status["status"] != "finished":
        message = f"failed at t = {status.get('time', math.nan):.6g} s: {status.get('reason', '')}"
    return Result(
        time=time,
        channels=list(names),
        data=data,
        stats=dict(summary["stats"]),
        status=status["status"],
        message=message,
        warnings=list(summary.get("warnings", [])),
        model=dict(model),
        options=dict(options),
        impacts=summary.get("impacts", []),
        clearances=summary.get("clearances", []),
    )
