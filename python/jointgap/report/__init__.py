"""Interactive HTML reports: one self-contained file that opens offline in a browser.

A report of a run holds an animation of the mechanism drawn from the model's shapes
(play, pause, speed, a time slider; each clearance drawn magnified so that the journal's
motion shows), the journal-centre orbit in its clearance circle with the current
position marked, interactive plots of the main channels (zoom, pan, hover) with a cursor
at the animation's time, and the summary: model, options, contact statistics, the
impact list and the run statistics. The same page compares a clearance run with an
ideal one (overlaid plots, a ghost of the ideal mechanism, the deviation table) or with
a measurement (the aligned signals, their difference and spectra, the error measures),
and shows a study (settings, metrics against parameters, the table of cases, figures).
A spatial model's run (``"dimension": 3``) is drawn in 3D with plotly's WebGL scenes,
plotly.js inlined (:mod:`jointgap.report.spatial`)::

    import jointgap
    from jointgap.report import write_run_report

    model = jointgap.load("examples/slider_crank_clearance.toml")
    result = model.simulate(0.5, rate=10_000)
    write_run_report(result, "report.html")

From the command line: ``jointgap report RESULTS_DIR --out report.html`` (a folder of
``jointgap run``, ``jointgap compare`` or a study), ``jointgap report MODEL.toml --t-end
0.5``, or ``jointgap run ... --report``.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .page import render, write
from .run import DEFAULT_MAX_POINTS, plotted_channels, run_section
from .scene import DEFAULT_MAX_FRAMES, ReportError, auto_magnify, frame_indices
from .sources import (
    COMPARISON_JSON,
    MEASURED_CSV,
    SIMULATION_DIR,
    folder_kind,
    folder_report_data,
)
from .sources import report_data as run_report_data
from .spatial import is_spatial, spatial_section

if TYPE_CHECKING:
    from ..results import Result

__all__ = [
    "COMPARISON_JSON",
    "DEFAULT_MAX_FRAMES",
    "DEFAULT_MAX_POINTS",
    "MEASURED_CSV",
    "ReportError",
    "SIMULATION_DIR",
    "auto_magnify",
    "folder_kind",
    "folder_report_data",
    "frame_indices",
    "is_spatial",
    "plotted_channels",
    "render",
    "run_report_data",
    "run_section",
    "spatial_section",
    "write",
    "write_folder_report",
    "write_run_report",
]


def write_run_report(result: Result, path: str | PathLike[str], **options: Any) -> Path:
    """Writes the report of a run to ``path`` (options as :func:`run_report_data`)."""
    return write(run_report_data(result, **options), path)


def write_folder_report(
    folder: str | PathLike[str], path: str | PathLike[str] | None = None, **options: Any
) -> Path:
    """Writes the report of a folder written by ``jointgap run`` (with ``ideal/``:
    against the ideal run), ``jointgap compare`` or a study, to ``path`` (default
    ``FOLDER/report.html``); options as :func:`run_report_data` (not for a study)."""
    out = Path(path) if path is not None else Path(folder) / "report.html"
    return write(folder_report_data(folder, **options), out)
