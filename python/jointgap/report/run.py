"""The data of a run's report: the scene and frames of the animation, the plotted
channels (with an ideal run overlaid), the orbits of the journal centres, the impacts
and the summary tables."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..results import Result, channel_unit, clearance_joints, main_channels
from ..statistics import contact_statistics, deviation_from_ideal
from .encode import minmax_indices, rounded
from .scene import DEFAULT_MAX_FRAMES, frame_indices, frames, scene
from .tables import (
    Table,
    contact_table,
    deviation_table,
    impact_table,
    model_table,
    options_table,
    run_statistics_table,
)

__all__ = ["DEFAULT_MAX_POINTS", "plotted_channels", "run_section"]

DEFAULT_MAX_POINTS = 20000
"""Most points of one plotted series or orbit; longer ones are decimated (min/max per
bucket for series, so every peak stays)."""


def plotted_channels(result: Result) -> list[str]:
    """The main channels (:func:`jointgap.results.main_channels`: slider motion, driver
    efforts, constraint error) with each clearance joint's normal force before the
    constraint error."""
    main = main_channels(result)
    forces = [f"{j}.fn" for j in clearance_joints(result) if f"{j}.fn" in result]
    tail = [c for c in main if c == "system.constraint_error"]
    return [c for c in main if c not in tail] + forces + tail


def _series(
    result: Result, channel: str, label: str, max_points: int, times: str, dash: bool = False
) -> dict[str, Any]:
    """One plotted line; its x is ``times`` (the name of a shared time array of the
    page: "run" or "ideal") unless it was decimated."""
    values = np.asarray(result[channel])
    keep = minmax_indices(values, max_points)
    x: Any = times if len(keep) == len(values) else rounded(np.asarray(result.time)[keep], 9)
    return {"label": label, "x": x, "y": rounded(values[keep]), "dash": dash}


def _plots(
    result: Result, ideal: Result | None, labels: tuple[str, str], max_points: int
) -> list[dict[str, Any]]:
    out = []
    for channel in plotted_channels(result):
        series = [_series(result, channel, labels[0], max_points, "run")]
        if ideal is not None and channel in ideal and len(ideal.time):
            series.append(_series(ideal, channel, labels[1], max_points, "ideal", dash=True))
        out.append(
            {
                "id": channel,
                "title": channel,
                "ylabel": f"{channel} [{channel_unit(channel)}]"
                if channel_unit(channel)
                else channel,
                "xlabel": "time [s]",
                "series": series,
                "markers": channel.split(".")[-1] in ("ax", "ay", "fn", "torque", "force"),
                "time": True,
                "kind": "line",
            }
        )
    return out


def _orbits(result: Result, scene_data: dict[str, Any], max_points: int) -> list[dict[str, Any]]:
    out = []
    for c in scene_data["clearances"]:
        joint = c["joint"]
        keep = frame_indices(np.asarray(result.time), max_points)
        out.append(
            {
                "joint": joint,
                "clearance": c["clearance"],
                "bearing_body": c["bearing_body"],
                "t": rounded(np.asarray(result.time)[keep], 9),
                "ex": rounded(np.asarray(result[f"{joint}.ex"])[keep]),
                "ey": rounded(np.asarray(result[f"{joint}.ey"])[keep]),
                "mode": rounded(np.asarray(result[f"{joint}.mode"])[keep], 2),
            }
        )
    return out


def run_section(
    result: Result,
    *,
    ideal: Result | None = None,
    source: str | None = None,
    magnify: float | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
    max_points: int = DEFAULT_MAX_POINTS,
    labels: Sequence[str] | None = None,
) -> dict[str, Any]:
    """Everything the page needs to draw one run (and an ideal run beside it).

    Args:
        result: the run (with its model: ``Result.model``).
        ideal: the same mechanism with ideal joints: overlaid in the plots, drawn as a
            ghost in the animation, and the deviation table.
        source: the model file, shown in the model table.
        magnify: drawn clearance over true clearance; default :func:`auto_magnify`.
        max_frames: most animation frames.
        max_points: most points per plotted series and orbit.
        labels: legend labels of the run and the ideal run (default "clearance",
            "ideal", or the model's name alone without an ideal run).
    """
    if len(result.time) < 2:
        raise ValueError(f"the run has {len(result.time)} samples: a report needs at least 2")
    index = frame_indices(np.asarray(result.time), max_frames)
    drawing = scene(result, index, magnify)
    default = (
        ("clearance", "ideal")
        if ideal is not None
        else (str(result.model.get("name") or "run"), "")
    )
    names = (str(labels[0]), str(labels[1])) if labels is not None else default
    stats = contact_statistics(result)
    tables: list[Table] = [
        model_table(result, source),
        options_table(result),
        run_statistics_table(result),
    ]
    if stats:
        tables.append(contact_table(stats))
    if result.impacts:
        tables.append(impact_table(result))
    if ideal is not None:
        tables.append(deviation_table(deviation_from_ideal(result, ideal)))
    impacts = [{"joint": j, "t": i.onset_time} for j, lst in result.impacts.items() for i in lst]
    return {
        "name": str(result.model.get("name") or ""),
        "status": result.status,
        "message": result.message,
        "labels": list(names),
        "scene": drawing,
        "frames": frames(result, index, ideal),
        "times": {
            "run": rounded(np.asarray(result.time), 9),
            "ideal": rounded(np.asarray(ideal.time), 9) if ideal is not None else [],
        },
        "plots": _plots(result, ideal, names, max_points),
        "orbits": _orbits(result, drawing, max_points),
        "impacts": impacts,
        "impact_counts": {j: len(v) for j, v in result.impacts.items()},
        "tables": [t.to_dict() for t in tables],
    }
