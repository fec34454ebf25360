"""Many runs at once: variants of a mechanism simulated in parallel inside the engine.

:func:`simulate_batch` hands every model to the Rust core, which runs them on a pool of
threads with the GIL released, so a sweep or a Monte Carlo sample uses every core
without processes or pickling. Each result is bit for bit the serial one (the runs share
nothing), and a model that cannot run leaves its error in its slot instead of stopping
the others::

    base = jointgap.load("examples/slider_crank_clearance.toml")
    variants = [with_parameters(base, {"rod_slider.clearance": c}) for c in ("0.2 mm", "0.5 mm")]
    results = jointgap.simulate_batch(variants, 0.5, rate=10_000)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from .model import Model
from .results import Result
from .run import run_options, simulate_many
from .schema import ModelError

__all__ = ["simulate_batch"]


def simulate_batch(
    models: Sequence[Model],
    t_end: float | str,
    *,
    threads: int | None = None,
    **options: Any,
) -> list[Result | Exception]:
    """Runs ``models`` with the same options on ``threads`` threads (default: all cores).

    Args:
        models: the mechanisms (e.g. from :func:`jointgap.variants.with_parameters`).
        t_end: end time of every run [s].
        threads: engine threads; 1 runs them one after the other.
        options: as :meth:`Model.simulate` (``rate``, ``rtol``, ``method``, ...).

    Returns:
        In the order of ``models``: each run's :class:`Result` (a failed run is a Result
        with status ``failed``), or the :class:`ModelError` of a model the engine
        refused. Invalid options raise ValueError before anything runs.
    """
    settings = run_options(t_end, **options)
    slots: list[Result | Exception | None] = []
    ready: list[tuple[int, Model]] = []
    for model in models:
        try:
            model._check_drivers()
        except ModelError as exc:
            slots.append(exc)
            continue
        ready.append((len(slots), model))
        slots.append(None)
    outcomes = simulate_many([m.to_dict() for _, m in ready], settings, threads)
    for (index, model), outcome in zip(ready, outcomes, strict=True):
        slots[index] = model.engine_error(outcome) if isinstance(outcome, ValueError) else outcome
    return [s for s in slots if s is not None]
