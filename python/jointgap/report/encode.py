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


def minmax_indices(values: np.ndarray, max_points: int) -> np.ndarray:
    """Indices of at most about ``max_points`` samples that keep the series' shape: all
    of them when there are few enough, else the first, the last, and the smallest and
    largest sample of each of ``max_points / 2`` even buckets, in order; so every peak
    (an impact's acceleration spike) survives."""
    n = len(values)
    if n <= max_points:
        return np.arange(n)
    buckets = max(1, max_points // 2)
    edges = np.linspace(0, n, buckets + 1).astype(int)
    keep = [0, n - 1]
    v = np.where(np.isfinite(values), values, 0.0)
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        if b > a:
            keep += [a + int(np.argmin(v[a:b])), a + int(np.argmax(v[a:b]))]
    return np.unique(np.array(keep))


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
