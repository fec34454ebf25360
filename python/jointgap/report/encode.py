"""Numbers as the report's embedded JSON holds them: rounded to a few significant
digits (what a screen can show), NaN and infinities as null, and min/max decimation
that keeps every peak of a long series."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["DIGITS", "rounded", "minmax_indices", "strict"]

DIGITS = 7
"""Significant digits kept in the report's data: 1 µm in 1 m, 0.1 µs in 1 s."""


def rounded(values: Any, digits: int = DIGITS) -> list[float | None]:
    """The values as a list of floats with ``digits`` significant digits; NaN and
    infinities as None (JSON null)."""
    arr = np.asarray(values, dtype=float).reshape(-1)
    fmt = f".{digits}g"
    return [float(format(v, fmt)) if math.isfinite(v) else None for v in arr.tolist()]


def minmax_indices(
    values: np.ndarray, max_points: int, time: np.ndarray | None = None
) -> np.ndarray:
    """Indices of at most about ``max_points`` samples that keep the series' shape: all
    of them when there are few enough, else the first, the last, and the smallest and
    largest sample of each of ``max_points / 2`` columns, in order; so every peak (an
    impact's acceleration spike) survives. With ``time`` the columns are even in time,
    as the plot's pixel columns are (samples of every step cluster at impacts, and even
    counts of them would spend the points there); else even in sample count."""
    n = len(values)
    if n <= max_points:
        return np.arange(n)
    columns = max(1, max_points // 2)
    if time is None or not time[-1] > time[0]:
        edges = np.linspace(0, n, columns + 1).astype(int)
    else:
        bounds = np.linspace(time[0], time[-1], columns + 1)
        edges = np.searchsorted(time, bounds, side="left")
        edges[-1] = n
    starts = np.unique(edges[:-1][edges[:-1] < np.r_[edges[1:]]])
    v = np.where(np.isfinite(values), values, 0.0)
    # Per column, the place of its minimum and maximum, without a Python loop.
    low = _arg_extreme(v, starts, np.minimum)
    high = _arg_extreme(v, starts, np.maximum)
    return np.unique(np.concatenate(([0, n - 1], low, high)))


def _arg_extreme(v: np.ndarray, starts: np.ndarray, extreme: Any) -> np.ndarray:
    """For each run ``v[starts[k]:starts[k+1]]``, the index of its first extreme value."""
    best = extreme.reduceat(v, starts)
    run = np.repeat(np.arange(len(starts)), np.diff(np.r_[starts, len(v)]))
    hit = np.flatnonzero(v == best[run])
    first = np.unique(run[hit], return_index=True)[1]
    return hit[first]


def strict(value: Any) -> Any:
    """A JSON-ready copy: non-finite floats as None, NumPy scalars as Python numbers,
    tuples as lists."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): strict(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [strict(v) for v in value]
    if isinstance(value, np.ndarray):
        return strict(value.tolist())
    return value
