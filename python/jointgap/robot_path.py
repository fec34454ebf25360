"""How far joint clearance takes a robot's tool point off its path: the same URDF robot
and move run twice, with the overlay's clearance joints and with every joint ideal (the
overlay without its ``[joint]`` table: the drivers then turn the URDF's ideal joints), and
the distance between the two positions of a marker at each output time (docs/urdf.md)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ._engine import run_options, simulate
from .errors import ModelError, RunStopped
from .results import Result
from .urdf import engine_model, load_urdf, read_overlay

__all__ = ["PathDeviation", "path_deviation", "plot_path_deviation"]


@dataclass(frozen=True)
class PathDeviation:
    """A marker's path with clearance against its ideal path, SI, at the output times."""

    marker: str
    time: npt.NDArray[np.float64]
    ideal: npt.NDArray[np.float64]
    """Positions of the ideal run, shape (3, samples) [m]."""
    actual: npt.NDArray[np.float64]
    """Positions of the run with clearance, shape (3, samples) [m]."""
    runs: tuple[Result, Result]
    """The ideal run and the run with clearance."""

    @property
    def deviation(self) -> npt.NDArray[np.float64]:
        """Distance between the two positions at each time [m]."""
        return np.asarray(np.linalg.norm(self.actual - self.ideal, axis=0))

    @property
    def largest(self) -> tuple[float, float]:
        """The largest deviation [m] and its time [s]."""
        k = int(np.argmax(self.deviation))
        return float(self.deviation[k]), float(self.time[k])


def _run(model: Mapping[str, Any], options: Mapping[str, Any], label: str) -> Result:
    result = simulate(engine_model(model), options)
    if not result.ok:
        raise RunStopped(f"the {label} run {result.message}", result)
    return result


def path_deviation(
    urdf: str | PathLike[str],
    overlay: str | PathLike[str] | Mapping[str, Any],
    marker: str,
    t_end: float | str,
    rate: float | str = "1 kHz",
    **options: Any,
) -> PathDeviation:
    """Runs the robot with the overlay and with its joints ideal, and returns the path
    of ``marker`` (a marker of the overlay) in both. Raises RunStopped when a run stops
    early (its result attached) and ModelError for bad input."""
    spec = read_overlay(overlay)
    ideal_spec = {k: v for k, v in spec.items() if k != "joint"}
    if marker not in spec.get("marker", {}):
        raise ModelError(f"no marker '{marker}' in the overlay", kind="marker", name=marker)
    opts = run_options(t_end, rate=rate, **options)
    ideal = _run(load_urdf(urdf, ideal_spec), opts, "ideal")
    actual = _run(load_urdf(urdf, overlay), opts, "clearance")
    path = [np.array([run[f"{marker}.{c}"] for c in "xyz"]) for run in (ideal, actual)]
    return PathDeviation(marker, np.asarray(actual.time), path[0], path[1], (ideal, actual))


def plot_path_deviation(result: PathDeviation, folder: str | PathLike[str]) -> Path:
    """Writes ``<marker>_deviation.png`` in ``folder`` (made if needed): the deviation [mm]
    against time, its largest value marked, over the tool point's ideal path."""
    from matplotlib.figure import Figure

    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(7, 5), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    for k, c in enumerate("xyz"):
        top.plot(result.time, result.ideal[k], label=f"{c} ideal", linestyle="--", color="black")
        top.plot(result.time, result.actual[k], label=f"{c} with clearance", linewidth=1)
    top.set_ylabel(f"{result.marker} position [m]")
    top.legend(fontsize=7, ncol=2)
    bottom.plot(result.time, 1e3 * result.deviation, color="tab:red", linewidth=1)
    peak, at = result.largest
    bottom.plot([at], [1e3 * peak], "kx")
    bottom.annotate(f"max {1e3 * peak:.3f} mm at {at:.3f} s", (at, 1e3 * peak), fontsize=8)
    bottom.set_xlabel("time [s]")
    bottom.set_ylabel("deviation from ideal path [mm]")
    path = out / f"{result.marker}_deviation.png"
    fig.savefig(path, dpi=150)
    return path
