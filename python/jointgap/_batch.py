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

from ._engine import BatchProgress, run_options, simulate_many
from .errors import BatchInterrupted, ModelError
from .model import Model
from .results import Result

__all__ = ["BatchInterrupted", "simulate_batch"]


def simulate_batch(
    models: Sequence[Model],
    t_end: float | str,
    *,
    threads: int | None = None,
    progress: BatchProgress | None = None,
    **options: Any,
) -> list[Result | Exception]:
    """Runs ``models`` with the same options on ``threads`` threads (default: all cores).

    Args:
        models: the mechanisms (e.g. from :func:`jointgap.variants.with_parameters`).
        t_end: end time of every run [s].
        threads: engine threads; 1 runs them one after the other.
        progress: ``progress(running, ended)``, called about every 0.2 s of wall time
            while the batch goes (runs going, runs ended), e.g. for a display; a
            KeyboardInterrupt it raises stops the batch as Ctrl-C does, any other
            exception stops it and propagates.
        options: as :meth:`Model.simulate` (``rate``, ``rtol``, ``method``, ...).

    Returns:
        In the order of ``models``: each run's :class:`Result` (a failed run is a Result
        with status ``failed``), or the :class:`ModelError` of a model the engine
        refused. Invalid options raise ValueError before anything runs.

    Raises:
        BatchInterrupted: Ctrl-C stopped the batch (within one check of the engine, every
            16 steps of each run): the runs going end with status ``interrupted`` and
            what they computed, those not started do not start, and the exception's
            ``results`` holds them all; it is a KeyboardInterrupt.
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
    outcomes, interrupted = simulate_many(
        [m.to_dict() for _, m in ready], settings, threads, progress
    )
    for (index, model), outcome in zip(ready, outcomes, strict=True):
        slots[index] = model.engine_error(outcome) if isinstance(outcome, ValueError) else outcome
    if interrupted:
        raise BatchInterrupted(slots)
    return [s for s in slots if s is not None]
