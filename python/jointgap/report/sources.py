"""What a report is made from: a run (and an ideal run or a measurement beside it), or
a folder, recognised by what it holds:

* ``study.json``: a study (``jointgap study``);
* ``comparison.json``: a comparison with a measurement (``jointgap compare``), with the
  simulation in ``simulation/`` and the measured signal in ``measured.csv``;
* ``summary.json``: a run (``jointgap run``); with ``ideal/summary.json``, against the
  ideal run.
"""

from __future__ import annotations

import json
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ReportError
from ..results import SUMMARY_JSON, Result, clearance_joints
from .compare import comparison_section
from .run import DEFAULT_MAX_POINTS, run_section
from .scene import DEFAULT_MAX_FRAMES
from .spatial import is_spatial, spatial_section
from .study import STUDY_JSON, study_section

if TYPE_CHECKING:
    from ..comparison import Comparison

__all__ = [
    "COMPARISON_JSON",
    "MEASURED_CSV",
    "SIMULATION_DIR",
    "IDEAL_DIR",
    "folder_kind",
    "folder_report_data",
    "load_comparison",
    "report_data",
]

COMPARISON_JSON = "comparison.json"
SIMULATION_DIR = "simulation"
MEASURED_CSV = "measured.csv"
IDEAL_DIR = "ideal"


def _generator() -> str:
    from .._version import __version__

    return f"jointgap {__version__}"


def folder_kind(folder: str | PathLike[str]) -> str:
    """``"study"``, ``"comparison"`` or ``"run"``, from the files in ``folder``.

    Raises:
        ReportError: it is not a folder, or holds none of study.json, comparison.json,
            summary.json.
    """
    path = Path(folder)
    if not path.is_dir():
        raise ReportError(f"{path}: no such folder")
    for name, kind in (
        (STUDY_JSON, "study"),
        (COMPARISON_JSON, "comparison"),
        (SUMMARY_JSON, "run"),
    ):
        if (path / name).is_file():
            return kind
    raise ReportError(
        f"{path}: not a results folder (no {SUMMARY_JSON} of 'jointgap run', "
        f"{COMPARISON_JSON} of 'jointgap compare' or {STUDY_JSON} of a study)"
    )


def _subtitle(result: Result, extra: str = "") -> str:
    span = f"t = {result.time[0]:g}..{result.time[-1]:g} s" if len(result.time) else "no samples"
    impacts = ", ".join(
        f"{len(result.impacts.get(j, []))} impacts ({j})" for j in clearance_joints(result)
    )
    parts = [span, f"{len(result.time)} samples", result.status, impacts, extra]
    return " · ".join(p for p in parts if p)


def report_data(
    result: Result,
    *,
    ideal: Result | None = None,
    comparison: Comparison | None = None,
    source: str | None = None,
    magnify: float | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
    max_points: int = DEFAULT_MAX_POINTS,
) -> dict[str, Any]:
    """The data of a run's report (what the page embeds as JSON); a spatial model's
    (``"dimension": 3``) draws its mechanism and orbits in 3D
    (:func:`jointgap.report.spatial.spatial_section`).

    Args:
        result: the run, with its model.
        ideal: the same mechanism with ideal joints, to compare with.
        comparison: a comparison of ``result`` with a measurement
            (:func:`jointgap.compare`).
        source: the model file's path, shown in the model table.
        magnify: drawn clearance over true clearance (default :func:`auto_magnify`).
        max_frames: most animation frames (evenly spaced in time).
        max_points: most points per plotted series (min/max decimation keeps peaks).

    Raises:
        ReportError: the result lacks a channel the animation needs or has no model.
    """
    name = str(result.model.get("name") or "run")
    if comparison is not None:
        title, kind = f"{name}: simulation against measurement", "comparison"
    elif ideal is not None:
        title, kind = f"{name}: clearance against ideal", "comparison"
    else:
        title, kind = f"{name}: simulation report", "run"
    return {
        "kind": kind,
        "title": title,
        "subtitle": _subtitle(result, _generator()),
        "generator": _generator(),
        "run": (spatial_section if is_spatial(result.model) else run_section)(
            result,
            ideal=ideal,
            source=source,
            magnify=magnify,
            max_frames=max_frames,
            max_points=max_points,
        ),
        "comparison": comparison_section(comparison, max_points)
        if comparison is not None
        else None,
        "study": None,
    }


def load_comparison(folder: str | PathLike[str]) -> tuple[Result, Comparison]:
    """The simulation and its comparison with the measurement, from a folder written by
    ``jointgap compare``: the comparison is computed again from ``simulation/`` and
    ``measured.csv`` with the settings of ``comparison.json`` (the lag as found)."""
    from ..comparison import compare
    from ..measured import read_measured

    path = Path(folder)
    settings = json.loads((path / COMPARISON_JSON).read_text(encoding="utf-8"))
    missing = [n for n in (SIMULATION_DIR, MEASURED_CSV) if not (path / n).exists()]
    if missing:
        raise ReportError(
            f"{path}: {COMPARISON_JSON} without {' and '.join(missing)}: run 'jointgap compare' "
            "again (it now writes the simulation and the measured signal beside it)"
        )
    result = Result.load(path / SIMULATION_DIR)
    measured = read_measured(path / MEASURED_CSV, str(settings["measured"]))
    comparison = compare(
        result,
        measured,
        str(settings["channel"]),
        lag=float(settings["lag"]),
        max_lag=float(settings.get("max_lag", 0.05)),
        lowpass=settings.get("lowpass"),
        offset=settings.get("offset", "mean"),
        spectrum_max=settings.get("spectrum_max"),
        crank=settings.get("crank"),
    )
    return result, comparison


def folder_report_data(
    folder: str | PathLike[str],
    *,
    ideal: Result | None = None,
    magnify: float | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
    max_points: int = DEFAULT_MAX_POINTS,
) -> dict[str, Any]:
    """The page's data for a folder (kind from :func:`folder_kind`). For a run folder,
    ``ideal`` defaults to the run in its ``ideal/`` subfolder."""
    path = Path(folder)
    kind = folder_kind(path)
    if kind == "study":
        study = study_section(path)
        return {
            "kind": "study",
            "title": f"{study['name']}: study",
            "subtitle": f"{study['n_cases']} cases, {study['n_failed']} failed · {_generator()}",
            "generator": _generator(),
            "run": None,
            "comparison": None,
            "study": study,
        }
    options: dict[str, Any] = {
        "magnify": magnify,
        "max_frames": max_frames,
        "max_points": max_points,
    }
    if kind == "comparison":
        result, comparison = load_comparison(path)
        return report_data(result, comparison=comparison, **options)
    result = Result.load(path)
    if ideal is None and (path / IDEAL_DIR / SUMMARY_JSON).is_file():
        ideal = Result.load(path / IDEAL_DIR)
    return report_data(result, ideal=ideal, **options)
