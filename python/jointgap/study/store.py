"""A study's folder: the resolved study, the log of cases as they end, the tables, the
time series.

::

    DIR/study.json          the resolved study (:meth:`Study.to_dict`)
    DIR/cases.jsonl         one line per case as it ends, appended and flushed to disk
                            at once: the record a restart reads to skip what is done
    DIR/cases.csv           the table, one row per case in case order: case, the
    DIR/cases.parquet       parameters, the metrics, status, reason, run_time_s; each
                            header carries its column's SI unit: "rod_slider.clearance [m]"
    DIR/series/case_000012.parquet
                            with time_series: that case's time and channels
    DIR/study.lock          who runs the study (host, process id, start), while a run
                            goes (locked: a second run on the folder is refused)

The log is the truth; the tables are written from it at the end of every run (also an
interrupted one), after the log is synced to disk, so a study that dies loses at most
the cases it was running.
"""

from __future__ import annotations

import json
import math
import os
import re
import socket
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .sampling import MODEL

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped]

__all__ = [
    "CASES_CSV",
    "column_name",
    "with_units",
    "CASES_PARQUET",
    "FAILED",
    "FINISHED",
    "LOCK",
    "LOG",
    "STUDY_JSON",
    "Outcome",
    "Store",
    "load_results",
    "load_series",
]

STUDY_JSON = "study.json"
LOG = "cases.jsonl"
CASES_CSV = "cases.csv"
CASES_PARQUET = "cases.parquet"
LOCK = "study.lock"
SERIES = "series"
FINISHED, FAILED = "finished", "failed"


@dataclass(frozen=True)
class Outcome:
    """What one case gave.

    Attributes:
        case: the case index (0-based).
        values: its parameter values, ``{path: value}`` (SI, or a model file name).
        metrics: ``{name: value}``; NaN when the case failed.
        status: ``finished`` or ``failed``.
        reason: why it failed; ``""`` when finished.
        run_time_s: wall time of the case [s] (its runs and metrics).
        series: ``{"time": .., channel: ..}`` when time series are kept, else None.
        warnings: the warnings of its runs, for the command to print (not logged).
    """

    case: int
    values: Mapping[str, Any]
    metrics: Mapping[str, float]
    status: str
    reason: str
    run_time_s: float
    series: Mapping[str, np.ndarray] | None = None
    warnings: tuple[str, ...] = ()

    def record(self) -> dict[str, Any]:
        """The log line's content: strict JSON, NaN as null."""
        metrics = {k: None if math.isnan(v) else v for k, v in self.metrics.items()}
        return {
            "case": self.case,
            "values": dict(self.values),
            "metrics": metrics,
            "status": self.status,
            "reason": self.reason,
            "run_time_s": self.run_time_s,
        }


class Store:
    """A study folder being written: locked for this run (a second run on the same
    folder is refused, naming the first), ``study.json`` checked or written on opening,
    each case logged as it ends. :meth:`close` releases the folder; the operating system
    releases it too when the process dies."""

    def __init__(self, directory: str | PathLike[str], study: Mapping[str, Any]) -> None:
        self.dir = Path(directory)
        self.study = dict(study)
        self.dir.mkdir(parents=True, exist_ok=True)
        self._lock = _lock(self.dir / LOCK)
        try:
            self._open()
        except BaseException:
            self.close()
            raise

    def _open(self) -> None:
        stored = self.dir / STUDY_JSON
        if stored.exists():
            old = json.loads(stored.read_text(encoding="utf-8"))
            differ = [
                k for k in sorted(set(old) | set(self.study)) if old.get(k) != self.study.get(k)
            ]
            if differ:
                raise ValueError(
                    f"{self.dir} holds another study (it differs in {', '.join(differ)}): "
                    "remove the folder or choose another --out"
                )
        else:
            _write_atomic(stored, json.dumps(self.study, indent=2) + "\n")
        self.done = {r["case"] for r in read_log(self.dir)}
        log = self.dir / LOG
        with open(log, "ab") as f:  # a line cut short by a crash ends here, alone
            if f.tell() and _last_byte(log) != b"\n":
                f.write(b"\n")

    def add(self, outcome: Outcome) -> None:
        """Stores one case: its time series first, then its log line, flushed to disk."""
        if outcome.series is not None:
            import pyarrow as pa
            import pyarrow.parquet as pq

            folder = self.dir / SERIES
            folder.mkdir(exist_ok=True)
            path = folder / f"case_{outcome.case:06d}.parquet"
            partial = path.with_suffix(".partial")
            pq.write_table(pa.table(dict(outcome.series)), partial)
            os.replace(partial, path)
        line = json.dumps(outcome.record(), allow_nan=False) + "\n"
        with open(self.dir / LOG, "a", encoding="utf-8") as f:
            f.write(line)
            f.flush()
            os.fsync(f.fileno())
        self.done.add(outcome.case)

    def close(self) -> None:
        """Releases the folder for another run."""
        if not self._lock.closed:  # the file stays (empty): removing it could let two in
            self._lock.truncate(0)
            self._lock.close()

    def write_tables(self) -> pd.DataFrame:
        """Writes ``cases.csv`` and ``cases.parquet`` from the log (synced to disk first,
        so that a table never holds a case the log could lose), each header with its
        column's unit (:func:`with_units`); returns the table (plain column names)."""
        with open(self.dir / LOG, "rb") as f:
            os.fsync(f.fileno())
        table = load_results(self.dir)
        headed = with_units(table, self.study.get("units", {}))
        _write_atomic(self.dir / CASES_CSV, headed.to_csv(index=False))
        partial = self.dir / f"{CASES_PARQUET}.partial"
        headed.to_parquet(partial, index=False)
        os.replace(partial, self.dir / CASES_PARQUET)
        return table


_HEADER_UNIT = re.compile(r"^(.*\S) \[[^\[\]]*\]$")


def with_units(table: pd.DataFrame, units: Mapping[str, str]) -> pd.DataFrame:
    """The table with each column headed ``name [unit]`` (SI; no unit for a
    dimensionless column, a count or text)."""
    return table.rename(columns=lambda c: f"{c} [{units[c]}]" if units.get(c) else c)


def column_name(header: str) -> str:
    """A column's name from its header: ``"rod_slider.clearance [m]"`` gives
    ``"rod_slider.clearance"``; a header without a unit (tables written before headers
    carried units) is the name itself."""
    m = _HEADER_UNIT.match(header)
    return m.group(1) if m else header


def read_log(directory: str | PathLike[str]) -> list[dict[str, Any]]:
    """The log's records, the first of each case, in the order they were written; a
    line cut short by a crash is skipped."""
    path = Path(directory) / LOG
    if not path.exists():
        return []
    records: dict[int, dict[str, Any]] = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            continue
        records.setdefault(int(record["case"]), record)
    return list(records.values())


def load_results(directory: str | PathLike[str]) -> pd.DataFrame:
    """The table of a study folder, one row per stored case in case order: ``case``,
    one column per parameter (named by its path; SI floats, a model as its file
    name), one per metric, ``status``, ``reason`` (empty when finished), ``run_time_s``.

    Read from the log when the folder has one (it also holds the cases of a study
    still running or interrupted), else from ``cases.parquet``.
    """
    import pandas as pd

    folder = Path(directory)
    if not (folder / LOG).exists():
        table = pd.read_parquet(folder / CASES_PARQUET)
        return table.rename(columns=column_name)
    study = json.loads((folder / STUDY_JSON).read_text(encoding="utf-8"))
    return _table(study, sorted(read_log(folder), key=lambda r: int(r["case"])))


def _table(study: Mapping[str, Any], records: Iterable[Mapping[str, Any]]) -> pd.DataFrame:
    import pandas as pd

    paths = [p["path"] for p in study["parameters"]]
    counts = {m["name"] for m in study["metric_definitions"] if m["stat"] == "impacts"}
    rows = [
        {
            "case": int(r["case"]),
            **{p: r["values"][p] for p in paths},
            **{
                m: math.nan if r["metrics"][m] is None else r["metrics"][m]
                for m in study["metrics"]
            },
            "status": r["status"],
            "reason": r["reason"],
            "run_time_s": float(r["run_time_s"]),
        }
        for r in records
    ]
    columns = ["case", *paths, *study["metrics"], "status", "reason", "run_time_s"]
    table = pd.DataFrame(rows, columns=columns)
    dtypes: dict[str, Any] = {"case": "int64", "status": "str", "reason": "str"}
    for p in study["parameters"]:
        dtypes[p["path"]] = "str" if p["path"] == MODEL else "float64"
    for m in study["metrics"]:
        dtypes[m] = "Int64" if m in counts else "float64"
    return table.astype(dtypes)


def load_series(directory: str | PathLike[str], case: int) -> pd.DataFrame:
    """The time series kept for one case: ``time`` and the channels, one row per sample.
    Raises FileNotFoundError when the study kept none for it."""
    import pandas as pd

    path = Path(directory) / SERIES / f"case_{case:06d}.parquet"
    if not path.exists():
        raise FileNotFoundError(f"{path}: no time series of case {case} (time_series in [study])")
    return pd.read_parquet(path)


def _lock(path: Path) -> Any:
    """``path`` opened and locked (``flock``) for this process, holding who runs the
    study; ValueError naming the holder when another process has it."""
    import fcntl

    f = open(path, "a+", encoding="utf-8")  # noqa: SIM115 - held until Store.close
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        f.seek(0)
        holder = f.read().strip() or "another process"
        f.close()
        raise ValueError(
            f"{path.parent} is in use by another study run ({holder}): wait for it to end "
            "or choose another --out"
        ) from None
    f.seek(0)
    f.truncate()
    started = time.strftime("%Y-%m-%d %H:%M:%S %z")
    f.write(f"host {socket.gethostname()}, process {os.getpid()}, since {started}\n")
    f.flush()
    return f


def _write_atomic(path: Path, text: str) -> None:
    partial = path.with_name(path.name + ".partial")
    partial.write_text(text, encoding="utf-8")
    os.replace(partial, path)


def _last_byte(path: Path) -> bytes:
    with open(path, "rb") as f:
        f.seek(-1, os.SEEK_END)
        return f.read(1)
