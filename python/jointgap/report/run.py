"""The data of a run's report: the scene and frames of the animation, the plotted
channels (with an ideal run overlaid), the orbits of the journal centres, the impacts
and the summary tables."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..results import Result, clearance_joints, main_channels
from ..statistics import contact_statistics, deviation_from_ideal
from .encode import minmax_indices, rounded
from .scene import DEFAULT_MAX_FRAMES, frame_indices, frames, scene
from .tables import (
    Table,
    channel_label,
    contact_table,
    deviation_table,
    impact_table,
    model_table,
    options_table,
    run_statistics_table,
)

__all__ = [
    "DEFAULT_MAX_POINTS",
    "IMPACT_POINTS",
    "KIND_CHANNELS",
    "impact_samples",
    "path_indices",
    "plotted_channels",
    "run_section",
]

DEFAULT_MAX_POINTS = 20000
"""Most points of one plotted series or orbit; longer ones are thinned by shape: a series
keeps the smallest and largest sample of each column even in time and the samples of
each impact, an orbit keeps points evenly along its path."""
IMPACT_POINTS = 8
"""Most samples kept inside each impact (besides those either side of it) when a series
is thinned, so that a zoomed impact shows its own width, not a column's."""


KIND_CHANNELS = {
    "lubricated_revolute": (
        "eccentricity_ratio",
        "film_thickness",
        "film_fx",
        "film_fy",
        "film_mode",
    ),
    "clearance_translational": ("tilt", "offset"),
    "revolute_with_play": ("play_angle", "torque"),
    "prismatic_with_play": ("play_travel", "force"),
    "gear_pair": ("mesh", "torque_1", "torque_2"),
}
"""Per joint type, the joint's own channels plotted after the contacts' normal forces:
the film of a lubricated joint, the block's tilt and offset in its guide, a play's
coordinate and stop, a gear mesh and its tooth torques."""


def plotted_channels(result: Result) -> list[str]:
    """The main channels (:func:`jointgap.results.main_channels`: slider motion, driver
    efforts, constraint error) with each contact's normal force (each corner's of a
    translational joint) and each joint's own channels of :data:`KIND_CHANNELS` before
    the constraint error."""
    main = main_channels(result)
    forces = [f"{j}.fn" for j in clearance_joints(result) if f"{j}.fn" in result]
    own = [
        f"{j['name']}.{q}"
        for j in result.model.get("joints", [])
        for q in KIND_CHANNELS.get(str(j.get("type")), ())
    ]
    tail = [c for c in main if c == "system.constraint_error"]
    chosen = [c for c in main if c not in tail] + forces + [c for c in own if c in result]
    return list(dict.fromkeys(chosen + tail))


def impact_samples(result: Result, per_impact: int = IMPACT_POINTS) -> np.ndarray:
    """Indices of the samples that show each impact: the last one before its onset, up
    to ``per_impact`` evenly chosen inside it (onset to separation), and the first one
    after it."""
    time = np.asarray(result.time)
    keep: list[np.ndarray] = []
    for impacts in result.impacts.values():
        for i in impacts:
            end = i.onset_time + (i.duration if np.isfinite(i.duration) else 0.0)
            a = max(0, int(np.searchsorted(time, i.onset_time, side="left")) - 1)
            b = min(len(time), int(np.searchsorted(time, end, side="right")) + 1)
            keep.append(np.unique(np.linspace(a, b - 1, min(b - a, per_impact + 2)).astype(int)))
    return np.unique(np.concatenate(keep)) if keep else np.zeros(0, dtype=int)


def _series(
    result: Result,
    channel: str,
    label: str,
    max_points: int,
    times: str,
    spikes: np.ndarray,
    dash: bool = False,
) -> dict[str, Any]:
    """One plotted line; its x is ``times`` (the name of a shared time array of the
    page: "run" or "ideal") unless it was thinned (then ``thinned`` says from how many
    samples)."""
    values = np.asarray(result[channel])
    time = np.asarray(result.time)
    keep = minmax_indices(values, max_points, time)
    if len(keep) == len(values):
        return {"label": label, "x": times, "y": rounded(values), "dash": dash}
    keep = np.union1d(keep, spikes)
    return {
        "label": label,
        "x": rounded(time[keep], 9),
        "y": rounded(values[keep]),
        "dash": dash,
        "thinned": len(values),
    }


def _plots(
    result: Result,
    ideal: Result | None,
    labels: tuple[str, str],
    max_points: int,
    channels: Sequence[str] | None = None,
) -> list[dict[str, Any]]:
    """The plots of ``channels`` (default :func:`plotted_channels`)."""
    out = []
    spikes = impact_samples(result)
    for channel in plotted_channels(result) if channels is None else channels:
        series = [_series(result, channel, labels[0], max_points, "run", spikes)]
        if ideal is not None and channel in ideal and len(ideal.time):
            series.append(
                _series(ideal, channel, labels[1], max_points, "ideal", np.zeros(0, int), dash=True)
            )
        thinned = max((s.get("thinned", 0) for s in series), default=0)
        title = channel
        if thinned:
            title += (
                f" (thinned from {thinned} samples: the smallest and largest of each column,"
                " and every impact)"
            )
        out.append(
            {
                "id": channel,
                "title": title,
                "ylabel": channel_label(channel, result.model),
                "xlabel": "time [s]",
                "series": series,
                "markers": channel.split(".")[-1] in _MARKED,
                "time": True,
                "kind": "line",
            }
        )
    return out


_MARKED = ("ax", "ay", "fn", "torque", "force", "torque_1", "torque_2")
"""The quantities whose plots mark the impacts' onsets."""


def path_indices(x: np.ndarray, y: np.ndarray, max_points: int) -> np.ndarray:
    """Indices of at most about ``max_points`` points of the path ``(x, y)`` evenly spaced
    along its length (and its ends): a journal that runs round its bearing's wall stays
    on the wall, where points even in time would join far points by chords through the
    clearance circle (20 000 of 600 000 reached 337 µm from the centre of a 500 µm
    circle). A chord then spans at most ``length / max_points`` of the path."""
    n = len(x)
    if n <= max_points:
        return np.arange(n)
    step = np.hypot(np.diff(x), np.diff(y))
    arc = np.concatenate(([0.0], np.cumsum(np.where(np.isfinite(step), step, 0.0))))
    if not arc[-1] > 0.0:
        return np.array([0, n - 1])
    marks = np.linspace(0.0, arc[-1], max_points)
    keep = np.searchsorted(arc, marks, side="left").clip(0, n - 1)
    return np.unique(np.concatenate(([0, n - 1], keep)))


def _orbits(result: Result, scene_data: dict[str, Any], max_points: int) -> list[dict[str, Any]]:
    out = []
    for c in scene_data["clearances"]:
        joint = c["joint"]
        ex, ey = np.asarray(result[f"{joint}.ex"]), np.asarray(result[f"{joint}.ey"])
        mode = np.asarray(result[f"{joint}.mode"])
        keep = path_indices(ex, ey, max_points)
        if len(keep) < len(ex):
            # Each change of mode stays, so that the colours change where the run's do.
            changes = np.flatnonzero(np.diff(mode) != 0)
            keep = np.union1d(keep, np.concatenate((changes, changes + 1)))
        out.append(
            {
                "joint": joint,
                "clearance": c["clearance"],
                "bearing_body": c["bearing_body"],
                "t": rounded(np.asarray(result.time)[keep], 9),
                "ex": rounded(ex[keep]),
                "ey": rounded(ey[keep]),
                "mode": rounded(mode[keep], 2),
                "thinned": len(ex) if len(keep) < len(ex) else 0,
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
        tables.append(contact_table(stats, result.model))
    if result.impacts:
        tables.append(impact_table(result))
    if ideal is not None:
        tables.append(deviation_table(deviation_from_ideal(result, ideal)))
    impacts = [{"joint": j, "t": i.onset_time} for j, lst in result.impacts.items() for i in lst]
    plots = _plots(result, ideal, names, max_points)
    # A time vector goes into the page only when a series draws on it unthinned.
    used = {s["x"] for p in plots for s in p["series"] if isinstance(s["x"], str)}
    return {
        "name": str(result.model.get("name") or ""),
        "status": result.status,
        "message": result.message,
        "labels": list(names),
        "scene": drawing,
        "frames": frames(result, index, ideal),
        "times": {
            "run": rounded(np.asarray(result.time), 9) if "run" in used else [],
            "ideal": rounded(np.asarray(ideal.time), 9)
            if ideal is not None and "ideal" in used
            else [],
        },
        "plots": plots,
        "orbits": _orbits(result, drawing, max_points),
        "impacts": impacts,
        "impact_counts": {j: len(v) for j, v in result.impacts.items()},
        "tables": [t.to_dict() for t in tables],
    }
