"""The standard figures of a study (matplotlib, no display needed), from its folder.

* ``<metric>_vs_<x>``: the metric against one grid parameter, one line per value of a
  second, one panel per value of any other grid parameter (e.g. the model);
* ``<metric>_heatmap``: the metric over the same two parameters, one panel likewise;
* with sampled parameters, ``<metric>_histogram``: its distribution (one outline per
  grid point), and ``sensitivity``: the Spearman rank correlation of every metric with
  every sampled parameter (one panel per grid point).

Only finished cases are drawn. Lengths are shown in mm and angular speeds in rpm.
"""

from __future__ import annotations

import itertools
import json
import math
import re
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..plots import save_figures
from .sampling import DISTRIBUTIONS, MODEL
from .store import FINISHED, STUDY_JSON, load_results

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped]

__all__ = ["FIGURES", "save_study_figures", "sensitivity", "study_figures"]

FIGURES = "figures"
"""The folder of a study's figures, inside the study folder."""
_MAX_PANELS = 12
_PANEL = (3.3, 2.6)  # one panel [in]
_DISPLAY = {"m": ("mm", 1e3), "rad/s": ("rpm", 30.0 / math.pi)}
"""SI unit -> (shown unit, factor from SI)."""
_RC: dict[Any, Any] = {  # keys: matplotlib rcParams
    "font.size": 8.0,
    "axes.titlesize": 8.0,
    "legend.fontsize": 7.0,
    "lines.linewidth": 1.0,
    "lines.markersize": 3.0,
    "legend.frameon": False,
    "svg.hashsalt": "jointgap",
}


@contextmanager
def _style() -> Iterator[None]:
    with mpl.rc_context(_RC):
        yield


def save_study_figures(
    directory: str | PathLike[str],
    *,
    x: str | None = None,
    lines: str | None = None,
    formats: Sequence[str] = ("png",),
) -> list[Path]:
    """Writes :func:`study_figures` of a study folder into ``<directory>/figures``, one
    file per figure and format; returns the paths."""
    folder = Path(directory)
    study = json.loads((folder / STUDY_JSON).read_text(encoding="utf-8"))
    figures = study_figures(load_results(folder), study, x=x, lines=lines)
    return save_figures(figures, folder / FIGURES, formats)


def study_figures(
    table: pd.DataFrame, study: Mapping[str, Any], *, x: str | None = None, lines: str | None = None
) -> dict[str, Figure]:
    """The figures of a study by name (module docstring).

    Args:
        table: the study's table (:func:`jointgap.study.load_results`).
        study: its ``study.json``.
        x: the parameter on the x axis (default: the first numeric grid parameter with
            more than one value).
        lines: the parameter with one line per value (default: the next numeric grid
            parameter with more than one value, else the model).

    Raises:
        ValueError: ``x`` or ``lines`` is not a grid parameter of the study, or too many
            panels would result.
    """
    done = table[table["status"] == FINISHED]
    params = {p["path"]: p for p in study["parameters"]}
    units: Mapping[str, str] = study.get("units", {})
    varied = [p for p in params.values() if p["kind"] not in DISTRIBUTIONS]
    varied = [p["path"] for p in varied if len(p["values"]) > 1]
    sampled = [p["path"] for p in params.values() if p["kind"] in DISTRIBUTIONS]
    figures: dict[str, Figure] = {}
    with _style():
        if sampled:
            for metric in study["metrics"]:
                figures[f"{_safe(metric)}_histogram"] = _histogram(done, metric, varied, units)
            figures["sensitivity"] = _sensitivity_figure(done, study, varied)
            return figures
        numeric = [p for p in varied if p != MODEL]
        if x is None and numeric:
            x = numeric[0]
        if x is None:
            return figures
        for name, value in (("x", x), ("lines", lines)):
            if value is not None and value not in varied:
                raise ValueError(
                    f"--{name} {value}: not a grid parameter with several values "
                    f"(these are: {', '.join(varied) or 'none'})"
                )
        if x == MODEL:
            raise ValueError("--x model: the x axis needs a numeric parameter")
        if lines is None:  # the next numeric parameter, else the model
            lines = next((p for p in [*numeric, *varied] if p != x), None)
        rest = [p for p in varied if p not in (x, lines)]
        panels = list(itertools.product(*(params[p]["values"] for p in rest)))
        if len(panels) > _MAX_PANELS:
            raise ValueError(
                f"{len(panels)} panels (one per value of {', '.join(rest)}): choose --x and "
                "--lines among the parameters with the most values"
            )
        for metric in study["metrics"]:
            args = (done, metric, x, lines, rest, panels, units)
            figures[f"{_safe(metric)}_vs_{_safe(x)}"] = _line_figure(*args)
            if lines is not None and lines != MODEL:
                figures[f"{_safe(metric)}_heatmap"] = _heatmap(*args)
    return figures


def sensitivity(table: pd.DataFrame, study: Mapping[str, Any]) -> pd.DataFrame:
    """Spearman rank correlation of every metric (columns) with every sampled parameter
    (rows), over the finished cases of ``table``; NaN where a metric does not vary."""
    import pandas as pd

    sampled = [p["path"] for p in study["parameters"] if p["kind"] in DISTRIBUTIONS]
    done = table[table["status"] == FINISHED]
    ranks = done[sampled + list(study["metrics"])].astype(float).rank()
    rho = ranks.corr(method="pearson")  # Pearson of ranks: Spearman, without SciPy
    return pd.DataFrame(rho.loc[sampled, list(study["metrics"])])


# ------------------------------------------------------------------ one figure each


def _line_figure(
    done: pd.DataFrame,
    metric: str,
    x: str,
    lines: str | None,
    rest: list[str],
    panels: list[tuple[Any, ...]],
    units: Mapping[str, str],
) -> Figure:
    fig, axes = _panels(len(panels), sharey=True)
    xunit, xscale = _shown(units.get(x, ""))
    yunit, yscale = _shown(units.get(metric, ""))
    for ax, fixed in zip(axes, panels, strict=False):
        rows = _select(done, rest, fixed)
        groups = [None] if lines is None else sorted(rows[lines].unique(), key=_order)
        for value in groups:
            part = rows if value is None else rows[rows[lines] == value]
            part = part.sort_values(x)
            label = None if value is None else _value_text(lines or "", value, units, bare=True)
            ax.plot(part[x] * xscale, part[metric] * yscale, marker="o", label=label)
        ax.set_xlabel(_label(x, xunit))
        ax.set_title(_panel_title(rest, fixed, units))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(_label(metric, yunit))
    if lines is not None:
        title = _label(lines, _shown(units.get(lines, ""))[0])
        fig.legend(*axes[0].get_legend_handles_labels(), title=title, loc="outside right upper")
    return fig


def _heatmap(
    done: pd.DataFrame,
    metric: str,
    x: str,
    lines: str | None,
    rest: list[str],
    panels: list[tuple[Any, ...]],
    units: Mapping[str, str],
) -> Figure:
    assert lines is not None
    fig, axes = _panels(len(panels))
    yunit, yscale = _shown(units.get(lines, ""))
    xunit, xscale = _shown(units.get(x, ""))
    munit, mscale = _shown(units.get(metric, ""))
    low, high = (done[metric].astype(float) * mscale).agg(["min", "max"])
    for ax, fixed in zip(axes, panels, strict=False):
        rows = _select(done, rest, fixed)
        grid = rows.pivot_table(index=lines, columns=x, values=metric, aggfunc="mean")
        image = ax.imshow(
            grid.to_numpy(dtype=float) * mscale,
            origin="lower",
            aspect="auto",
            cmap="viridis",
            vmin=low,
            vmax=high,
        )
        ax.set_xticks(range(len(grid.columns)), [f"{v * xscale:.3g}" for v in grid.columns])
        ax.set_yticks(range(len(grid.index)), [f"{v * yscale:.3g}" for v in grid.index])
        ax.set_xlabel(_label(x, xunit))
        ax.set_ylabel(_label(lines, yunit))
        ax.set_title(_panel_title(rest, fixed, units))
        fig.colorbar(image, ax=ax, label=_label(metric, munit))
    return fig


def _histogram(
    done: pd.DataFrame, metric: str, varied: list[str], units: Mapping[str, str]
) -> Figure:
    fig, (ax,) = _panels(1)
    unit, scale = _shown(units.get(metric, ""))
    values = done[metric].astype(float) * scale
    finite = values[np.isfinite(values)]
    bins = np.histogram_bin_edges(finite, bins="auto").tolist() if len(finite) else 10
    groups = list(done.groupby(varied, sort=True)) if varied else [((), done)]
    style: dict[str, Any] = {"histtype": "step"} if varied else {"alpha": 0.7}
    for key, part in groups:
        fixed = key if isinstance(key, tuple) else (key,)
        label = _panel_title(varied, fixed, units) or None
        ax.hist(part[metric].astype(float) * scale, bins=bins, label=label, **style)
    ax.set_xlabel(_label(metric, unit))
    ax.set_ylabel("cases")
    if varied:
        ax.legend()
    return fig


def _sensitivity_figure(done: pd.DataFrame, study: Mapping[str, Any], varied: list[str]) -> Figure:
    """Rank correlations as a table of colours: a row per metric, a column per sampled
    parameter; one panel per grid point."""
    groups = list(done.groupby(varied, sort=True)) if varied else [((), done)]
    n_metrics = len(study["metrics"])
    n_sampled = sum(p["kind"] in DISTRIBUTIONS for p in study["parameters"])
    size = (2.2 + 0.8 * n_sampled, 0.9 + 0.3 * n_metrics)
    fig, axes = _panels(len(groups), size)
    units = study.get("units", {})
    for ax, (key, part) in zip(axes, groups, strict=False):
        rho = sensitivity(part, study).T
        values = rho.to_numpy(dtype=float)
        image = ax.imshow(values, cmap="RdBu_r", vmin=-1.0, vmax=1.0, aspect="auto")
        for (i, j), r in np.ndenumerate(values):
            if math.isfinite(r):
                ax.text(j, i, f"{r:.2f}", ha="center", va="center", fontsize=7)
        ax.set_xticks(range(len(rho.columns)), list(rho.columns), rotation=20, ha="right")
        ax.set_yticks(range(len(rho.index)), list(rho.index))
        fixed = key if isinstance(key, tuple) else (key,)
        ax.set_title(_panel_title(varied, fixed, units).replace(", ", "\n"))
    fig.colorbar(image, ax=axes, label="Spearman rank correlation")
    return fig


# ------------------------------------------------------------------ helpers


def _panels(
    n: int, size: tuple[float, float] = _PANEL, sharey: bool = False
) -> tuple[Figure, list[Axes]]:
    """A figure of ``n`` panels of ``size`` [in], at most three a row."""
    columns = min(n, 3)
    rows = -(-n // columns)
    fig = Figure(figsize=(size[0] * columns, size[1] * rows), layout="constrained")
    axes = fig.subplots(rows, columns, squeeze=False, sharey=sharey).ravel().tolist()
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig, axes[:n]


def _select(table: pd.DataFrame, paths: Sequence[str], values: Sequence[Any]) -> pd.DataFrame:
    mask = np.ones(len(table), dtype=bool)
    for path, value in zip(paths, values, strict=True):
        mask &= (table[path] == value).to_numpy()
    return table[mask]


def _shown(unit: str) -> tuple[str, float]:
    """The unit a value is shown in and the factor from SI."""
    return _DISPLAY.get(unit, (unit, 1.0))


def _label(path: str, unit: str) -> str:
    name = f"{path[2:]} (every clearance joint)" if path.startswith("*.") else path
    return f"{name} [{unit}]" if unit else name


def _value_text(path: str, value: Any, units: Mapping[str, str], bare: bool = False) -> str:
    """A parameter's value as shown, with its unit unless ``bare``."""
    if path == MODEL:
        return str(value)
    unit, scale = _shown(units.get(path, ""))
    return f"{value * scale:.4g}" + (f" {unit}" if unit and not bare else "")


def _panel_title(paths: Sequence[str], values: Sequence[Any], units: Mapping[str, str]) -> str:
    return ", ".join(
        _value_text(p, v, units) if p == MODEL else f"{p} = {_value_text(p, v, units)}"
        for p, v in zip(paths, values, strict=True)
    )


def _order(value: Any) -> tuple[int, float, str]:
    return (0, float(value), "") if isinstance(value, (int, float)) else (1, 0.0, str(value))


def _safe(name: str) -> str:
    return re.sub(r"[^\w-]", "_", name.removeprefix("*."))
