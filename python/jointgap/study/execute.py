"""Running a study's cases: on the local cores (threads; the engine releases the GIL),
or on an existing Dask cluster. Either way each case is one call of :func:`run_case`,
and its outcome is handed to the caller the moment it arrives, to be stored.
"""

from __future__ import annotations

import math
import signal
import sys
import threading
import time
import uuid
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..model import Model
from ..variants import with_parameters
from .metrics import Metric, ideal_counterpart
from .sampling import MODEL
from .store import FAILED, FINISHED, Outcome

__all__ = ["Case", "run_case", "run_dask", "run_local"]


@dataclass(frozen=True)
class Case:
    """Everything one case needs, self-contained so that it can travel to a worker.

    Attributes:
        case: the case index.
        values: ``{path: value}`` (SI, or a model file name).
        model: the model dictionary it starts from (SI), before ``values`` are set.
        run: keyword arguments of :meth:`jointgap.Model.simulate`.
        metrics: what to keep.
        time_series: keep every channel (True), these channels, or none (False).
    """

    case: int
    values: Mapping[str, Any]
    model: Mapping[str, Any]
    run: Mapping[str, Any]
    metrics: tuple[Metric, ...]
    time_series: bool | tuple[str, ...] = False


def run_case(case: Case) -> Outcome:
    """Runs one case: sets its parameters, simulates, computes its metrics (running the
    ideal counterpart when a metric needs it). A failure (an invalid variant, a run
    that stops early) is the case's outcome, with its reason, never an exception."""
    start = time.perf_counter()
    series = None
    notes: list[str] = []  # the runs' warnings, which travel back with the outcome
    try:
        varied = {p: v for p, v in case.values.items() if p != MODEL}
        model = with_parameters(Model.from_dict(case.model), varied)
        result = model.simulate(**case.run)
        notes += result.warnings
        if case.time_series:
            chosen = result.channels if isinstance(case.time_series, bool) else case.time_series
            series = {"time": result.time, **{c: result[c] for c in chosen}}
        if not result.ok:
            return _failed(case, start, result.message, series, notes)
        ideal = None
        if any(m.needs_ideal for m in case.metrics):
            ideal = Model.from_dict(ideal_counterpart(model.to_dict())).simulate(**case.run)
            notes += ideal.warnings
            if not ideal.ok:
                return _failed(case, start, f"the ideal run {ideal.message}", series, notes)
        metrics = {m.name: m.value(result, ideal) for m in case.metrics}
    except ValueError as exc:  # ModelError too: a variant the model or engine refuses
        return _failed(case, start, str(exc), series, notes)
    except Exception as exc:  # one case's surprise must not end the study
        return _failed(case, start, f"{type(exc).__name__}: {exc}", series, notes)
    elapsed = time.perf_counter() - start
    values = dict(case.values)
    return Outcome(case.case, values, metrics, FINISHED, "", elapsed, series, tuple(notes))


def _failed(
    case: Case,
    start: float,
    reason: str,
    series: Mapping[str, np.ndarray] | None,
    notes: Sequence[str],
) -> Outcome:
    metrics = {m.name: math.nan for m in case.metrics}
    elapsed = time.perf_counter() - start
    values = dict(case.values)
    return Outcome(case.case, values, metrics, FAILED, reason, elapsed, series, tuple(notes))


def run_local(cases: Sequence[Case], workers: int, store: Callable[[Outcome], None]) -> None:
    """Runs ``cases`` on ``workers`` threads, handing each outcome to ``store`` (in this
    thread) as it ends. On an interrupt, the cases not started are dropped and those
    running are waited for and stored before the interrupt goes on; Ctrl-C again
    meanwhile does not drop them (it says so on stderr)."""
    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="jointgap-study")
    pending: set[Future[Outcome]] = {pool.submit(run_case, c) for c in cases}
    try:
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:  # each leaves pending as it is stored: none twice
                pending.discard(future)
                store(future.result())
    finally:
        pool.shutdown(wait=False, cancel_futures=True)
        running = {f for f in pending if not f.cancelled()}
        with _interrupts_wait(len(running)):
            for future in running:
                store(future.result())
        pool.shutdown(wait=True)


@contextmanager
def _interrupts_wait(running: int) -> Iterator[None]:
    """While the running cases of an interrupted study end and are stored: Ctrl-C only
    says that they are still running (the main thread only can change the handler)."""
    if not running or threading.current_thread() is not threading.main_thread():
        yield
        return

    def note(signum: int, frame: object) -> None:
        print(
            f"\njointgap: interrupted: waiting for the {running} running case"
            f"{'s' if running > 1 else ''} to end and be stored",
            file=sys.stderr,
            flush=True,
        )

    previous = signal.signal(signal.SIGINT, note)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def run_dask(
    cases: Sequence[Case], scheduler: str, store: Callable[[Outcome], None]
) -> dict[int, str]:
    """Runs ``cases`` on the Dask cluster at ``scheduler`` (``tcp://host:port``),
    handing each outcome to ``store`` as it arrives. A worker that dies takes no case
    with it: the scheduler runs its cases again elsewhere. Returns the cases the
    cluster could not run (e.g. every worker died), with why; they stay missing, for
    a rerun to pick up."""
    from distributed import Client, as_completed

    lost: dict[int, str] = {}
    with Client(scheduler, timeout="30s") as client:  # type: ignore[no-untyped-call]
        _check_workers(client)
        token = uuid.uuid4().hex[:8]
        keys = [f"jointgap-case-{c.case}-{token}" for c in cases]
        futures = client.map(run_case, cases, key=keys)
        index = {f.key: c.case for f, c in zip(futures, cases, strict=True)}
        for future in as_completed(futures):  # type: ignore[no-untyped-call]
            if future.status == "finished":
                store(future.result())
            else:
                lost[index[future.key]] = repr(future.exception())
            future.release()
    return lost


def _check_workers(client: Any) -> None:
    """Every worker runs the same jointgap as this client (it imports the engine)."""
    from .._version import __version__

    versions = client.run(_jointgap_version, on_error="return")
    if not versions:
        raise ValueError(f"the Dask cluster at {client.scheduler.address} has no workers")
    for worker, version in versions.items():
        if version != __version__:
            found = f"jointgap {version}" if isinstance(version, str) else repr(version)
            raise ValueError(
                f"Dask worker {worker} has {found}, this client jointgap {__version__}: "
                "install the same jointgap (with its engine) on every worker"
            )


def _jointgap_version() -> str:
    from .. import _jointgap  # noqa: F401 - the engine must import too
    from .._version import __version__

    return __version__
