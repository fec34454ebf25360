"""Parametric and Monte Carlo studies: many variants of a mechanism, one table.

A study file (``docs/studies.md``) names a base model, parameters addressed by path
(``rod_slider.clearance``, ``motor.speed``, ``gravity``, ``model``) as lists, ranges or
distributions, and the metrics to keep per case. :func:`run_study` runs every case on
the local cores, or on a Dask cluster with ``scheduler="tcp://host:port"``, storing each
case as it ends, so that a study that stops resumes where it stopped::

    from jointgap.study import load_results, run_study

    run_study("examples/study_clearance_speed.toml", "out/study")
    table = load_results("out/study")      # one row per case: parameters, metrics, status
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from .._engine import collect_warnings
from .execute import Case, run_case, run_dask, run_local
from .metrics import Metric
from .progress import Progress
from .sampling import Parameter
from .spec import Study, StudyError, load_study, loads_study
from .store import FAILED, Outcome, Store, load_results, load_series

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped]

__all__ = [
    "Case",
    "Metric",
    "Outcome",
    "Parameter",
    "Study",
    "StudyError",
    "StudyRun",
    "load_results",
    "load_series",
    "load_study",
    "loads_study",
    "run_case",
    "run_study",
]


@dataclass(frozen=True)
class StudyRun:
    """What one call of :func:`run_study` did.

    Attributes:
        directory: the study folder.
        n_cases: cases of the study.
        skipped: cases found stored by an earlier run, not run again.
        ran: cases run this time.
        where: where they ran: ``"2 local threads"`` or the Dask scheduler's address.
        table: the table of every stored case (:func:`load_results`).
        missing: cases the Dask cluster could not run, with why (they stay missing, for
            a rerun to pick up); empty when every case is stored.
        wall_time: seconds this run took.
    """

    directory: Path
    n_cases: int
    skipped: int
    ran: int
    where: str
    table: pd.DataFrame = field(repr=False)
    missing: dict[int, str]
    wall_time: float

    @property
    def failed(self) -> int:
        """Stored cases that failed."""
        return int((self.table["status"] == FAILED).sum())

    @property
    def complete(self) -> bool:
        """True when every case of the study is stored."""
        return len(self.table) == self.n_cases


def run_study(
    study: Study | str | PathLike[str],
    out: str | PathLike[str],
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: TextIO | None = sys.stderr,
) -> StudyRun:
    """Runs the cases of a study that ``out`` does not hold yet.

    Args:
        study: a study file or a loaded :class:`Study`.
        out: the study folder (created); ``study.json``, ``cases.jsonl``, ``cases.csv``,
            ``cases.parquet`` and, with time series, ``series/``.
        scheduler: address of a Dask scheduler (``tcp://host:port``) to run the cases
            on; None runs them here.
        workers: threads for local runs (default: the cores this process may use).
        progress: where the progress bar goes; None for none.

    Raises:
        StudyError: an invalid study file (before anything runs).
        ValueError: ``out`` holds another study, or another run of a study is using it;
            the cluster has no or mismatched workers.
        KeyboardInterrupt: Ctrl-C; the cases not started are dropped, those running
            end and are stored (Ctrl-C again does not drop them), the tables written.
    """
    started = time.perf_counter()
    resolved = study if isinstance(study, Study) else load_study(study)
    if workers is not None and workers < 1:
        raise ValueError(f"workers = {workers}: must be at least 1")
    store = Store(out, resolved.to_dict())
    try:
        return _run(resolved, store, scheduler, workers, progress, started)
    finally:
        store.close()


def _run(
    resolved: Study,
    store: Store,
    scheduler: str | None,
    workers: int | None,
    progress: TextIO | None,
    started: float,
) -> StudyRun:
    """:func:`run_study` on an opened study folder."""
    values = resolved.cases()
    cases = [
        Case(k, v, resolved.model_of(v), resolved.run, resolved.metrics, resolved.time_series)
        for k, v in enumerate(values)
        if k not in store.done
    ]
    bar = Progress(len(values), len(values) - len(cases), progress)

    def keep(outcome: Outcome) -> None:
        store.add(outcome)
        collect_warnings(outcome.warnings)  # of cases run in other processes too
        bar.add(outcome.status == FAILED)

    missing: dict[int, str] = {}
    threads = workers or _cores()
    try:
        if scheduler is not None:
            missing = run_dask(cases, scheduler, keep)
        else:
            run_local(cases, threads, keep)
    finally:
        bar.close()
        table = store.write_tables()
    return StudyRun(
        directory=store.dir,
        n_cases=len(values),
        skipped=len(values) - len(cases),
        ran=bar.ran,
        where=scheduler or f"{threads} local thread{'' if threads == 1 else 's'}",
        table=table,
        missing=missing,
        wall_time=time.perf_counter() - started,
    )


def _cores() -> int:
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity is not None else os.cpu_count() or 1
