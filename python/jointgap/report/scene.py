"""The mechanism as the report's animation draws it: shapes in body frames, ground
points and guides, clearance joints drawn magnified, and the bodies' poses per frame.

Everything comes from the result: the model dictionary it carries (``shape`` tables,
points, joints) and its channels (``<body>.x``, ``.y``, ``.angle``; ``<joint>.ex``,
``.ey``, ``.mode``). A body without a ``shape`` is drawn as a thin bar through its
points. Each clearance joint's journal is drawn at the bearing centre plus ``magnify``
times the eccentricity, with the drawn clearance ``magnify * c``, so that a 0.5 mm
clearance shows in a 0.5 m mechanism.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._schema import GROUND
from ..errors import ReportError
from ..plots import radial_clearance, resolved_clearance
from ..results import Result
from .encode import rounded

__all__ = [
    "DEFAULT_MAX_FRAMES",
    "ReportError",
    "auto_magnify",
    "frame_indices",
    "scene",
    "frames",
]

DEFAULT_MAX_FRAMES = 6000
"""Most animation frames: a run with more samples is subsampled evenly in time."""
_MAGNIFY_TARGET = 0.02  # the drawn clearance as a fraction of the drawing's size
_BAR_FRACTION = 0.02  # width of a shapeless body's bar, as a fraction of the size


@dataclass(frozen=True)
class _Body:
    name: str
    points: dict[str, tuple[float, float]]
    shapes: list[dict[str, Any]]


def _vec(value: Any) -> tuple[float, float]:
    return float(value[0]), float(value[1])


def _point(
    body: Mapping[str, Any] | None, ref: Any, ground: Mapping[str, Any]
) -> tuple[float, float]:
    """A joint or shape point: a name (of the body's points, or of the ground points) or
    [x, y] in the body frame (global for the ground)."""
    if isinstance(ref, str):
        points = ground if body is None else body.get("points", {})
        if ref not in points:
            owner = "ground" if body is None else f"body '{body.get('name')}'"
            raise ReportError(f"point '{ref}' is not a point of {owner}")
        return _vec(points[ref])
    if ref is None:
        return 0.0, 0.0
    return _vec(ref)


def _bodies(model: Mapping[str, Any]) -> dict[str, Mapping[str, Any]]:
    return {str(b["name"]): b for b in model.get("bodies", [])}


def _body_shapes(
    body: Mapping[str, Any], ground: Mapping[str, Any], size: float
) -> list[dict[str, Any]]:
    """The body's drawing in its frame: its ``shape``, else a bar through its points."""
    shape = body.get("shape")
    if shape:
        kind = shape.get("type")
        if kind == "bar":
            return [
                {
                    "type": "bar",
                    "from": list(_point(body, shape.get("from"), ground)),
                    "to": list(_point(body, shape.get("to"), ground)),
                    "width": float(shape.get("width", 0.01)),
                }
            ]
        if kind == "block":
            return [
                {"type": "block", "width": float(shape["width"]), "height": float(shape["height"])}
            ]
        if kind == "disk":
            return [{"type": "disk", "radius": float(shape["radius"])}]
        raise ReportError(f"body '{body.get('name')}': shape type {kind!r} cannot be drawn")
    points = [list(_vec(p)) for p in body.get("points", {}).values()]
    width = _BAR_FRACTION * size
    if len(points) >= 2:
        return [{"type": "path", "points": points, "width": width}]
    return [{"type": "disk", "radius": width}]


def _shape_vertices(shape: Mapping[str, Any]) -> np.ndarray:
    """Points that bound a shape in its body frame (k x 2), for the drawing's extent."""
    kind = shape["type"]
    if kind == "bar":
        (x0, y0), (x1, y1), w = shape["from"], shape["to"], shape["width"] / 2.0
        return np.array([[x0 - w, y0 - w], [x0 + w, y0 + w], [x1 - w, y1 - w], [x1 + w, y1 + w]])
    if kind == "block":
        w, h = shape["width"] / 2.0, shape["height"] / 2.0
        return np.array([[-w, -h], [w, -h], [w, h], [-w, h]])
    if kind == "disk":
        r = shape["radius"]
        return np.array([[-r, -r], [r, r], [-r, r], [r, -r]])
    return np.array(shape["points"], dtype=float)


def _poses(result: Result, body: str, index: np.ndarray) -> tuple[np.ndarray, ...]:
    missing = [f"{body}.{q}" for q in ("x", "y", "angle") if f"{body}.{q}" not in result]
    if missing:
        raise ReportError(
            f"the animation needs the channels {', '.join(missing)}: record them "
            "(run without --channel, or add 'body.*')"
        )
    return tuple(np.asarray(result[f"{body}.{q}"])[index] for q in ("x", "y", "angle"))


def frame_indices(time: np.ndarray, max_frames: int = DEFAULT_MAX_FRAMES) -> np.ndarray:
    """Sample indices of the animation frames: every sample when there are at most
    ``max_frames``, else the samples nearest ``max_frames`` even instants (first and
    last kept)."""
    if max_frames < 2:
        raise ReportError(f"max_frames must be at least 2, not {max_frames}")
    n = len(time)
    if n <= max_frames:
        return np.arange(n)
    targets = np.linspace(time[0], time[-1], max_frames)
    k = np.clip(np.searchsorted(time, targets), 1, n - 1)
    nearer_left = (targets - time[k - 1]) <= (time[k] - targets)
    return np.unique(np.where(nearer_left, k - 1, k))


def _bounds(
    result: Result,
    bodies: Sequence[_Body],
    index: np.ndarray,
    links: Mapping[str, list[list[float]]],
    ground: Sequence[list[float]],
) -> list[float]:
    """The drawing's extent over all frames: shapes, joint points, ground points."""
    lo = np.array([math.inf, math.inf])
    hi = -lo
    if ground:
        lo = np.minimum(lo, np.min(np.array(ground), axis=0))
        hi = np.maximum(hi, np.max(np.array(ground), axis=0))
    for body in bodies:
        verts = np.vstack(
            [_shape_vertices(s) for s in body.shapes] + [np.array(links[body.name] or [[0.0, 0.0]])]
        )
        x, y, a = _poses(result, body.name, index)
        c, s = np.cos(a)[:, None], np.sin(a)[:, None]
        gx = x[:, None] + c * verts[:, 0] - s * verts[:, 1]
        gy = y[:, None] + s * verts[:, 0] + c * verts[:, 1]
        lo = np.minimum(lo, [np.nanmin(gx), np.nanmin(gy)])
        hi = np.maximum(hi, [np.nanmax(gx), np.nanmax(gy)])
    return [float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])]


def _size(model: Mapping[str, Any]) -> float:
    """A length scale of the mechanism from its points and initial positions [m]."""
    coords = [_vec(p) for p in model.get("ground_points", {}).values()]
    for body in model.get("bodies", []):
        x, y = _vec(body.get("position", (0.0, 0.0)))
        coords.append((x, y))
        coords += [
            (x + px, y + py) for px, py in (_vec(p) for p in body.get("points", {}).values())
        ]
    if len(coords) < 2:
        return 1.0
    arr = np.array(coords)
    span = float(np.max(arr.max(axis=0) - arr.min(axis=0)))
    return span if span > 0 else 1.0


def auto_magnify(clearance: float, size: float) -> float:
    """The default magnification: a round factor (1, 2 or 5 times a power of ten, at
    least 1) that draws the clearance at about 2 % of the drawing's size."""
    if clearance <= 0 or size <= 0:
        return 1.0
    raw = _MAGNIFY_TARGET * size / clearance
    if raw <= 1.0:
        return 1.0
    power = 10.0 ** math.floor(math.log10(raw))
    return max(m * power for m in (1.0, 2.0, 5.0) if m * power <= raw)


JOURNAL_TYPES = ("clearance_revolute", "lubricated_revolute")
"""The joint types drawn as a journal in its bearing, whose eccentricity the animation
and the orbits show."""


def journal_joints(result: Result) -> list[str]:
    """The joints of ``result`` drawn as a journal in its bearing, in model order."""
    return [
        str(j["name"]) for j in result.model.get("joints", []) if j.get("type") in JOURNAL_TYPES
    ]


def scene(result: Result, index: np.ndarray, magnify: float | None = None) -> dict[str, Any]:
    """The static drawing: bodies with shapes, pins and joint points (``links``, drawn
    as thin lines from the centre of mass) in their frames, ground points and guides,
    clearance joints with drawn radii, the extent over all frames, and the
    magnification used."""
    model = result.model
    if not model.get("bodies"):
        raise ReportError("the result carries no model with bodies: nothing to draw")
    ground = model.get("ground_points", {})
    bodies_raw = _bodies(model)
    size = _size(model)
    bodies = [
        _Body(
            name,
            {k: _vec(v) for k, v in b.get("points", {}).items()},
            _body_shapes(b, ground, size),
        )
        for name, b in bodies_raw.items()
    ]
    pins: dict[str, list[list[float]]] = {b.name: [] for b in bodies}
    links: dict[str, list[list[float]]] = {b.name: [] for b in bodies}  # joint points
    ground_pins: list[list[float]] = []
    guides: list[dict[str, Any]] = []
    clearances: list[dict[str, Any]] = []
    for joint in model.get("joints", []):
        kind = joint.get("type")
        bi, bj = str(joint.get("body_i")), str(joint.get("body_j"))
        body_i = None if bi == GROUND else bodies_raw.get(bi)
        body_j = None if bj == GROUND else bodies_raw.get(bj)
        pi = _point(body_i, joint.get("point_i"), ground)
        pj = _point(body_j, joint.get("point_j"), ground)
        for body, point in ((bi, pi), (bj, pj)):
            if body != GROUND and body in links and list(point) not in links[body]:
                links[body].append(list(point))
        if kind in ("revolute", "revolute_with_play"):
            if bj != GROUND:
                pins[bj].append(list(pj))
            else:
                pins[bi].append(list(pi))
            if GROUND in (bi, bj):
                ground_pins.append(list(pi if bi == GROUND else pj))
        elif kind in ("prismatic", "prismatic_with_play", "clearance_translational"):
            axis = _vec(joint.get("axis") or (1.0, 0.0))
            guides.append(
                {"body": None if bi == GROUND else bi, "point": list(pi), "axis": list(axis)}
            )
        elif kind in JOURNAL_TYPES:
            clearances.append(
                {
                    "joint": str(joint["name"]),
                    "bearing_body": None if bi == GROUND else bi,
                    "point": list(pi),
                    "journal_body": None if bj == GROUND else bj,
                }
            )
    bounds = _bounds(result, bodies, index, links, ground_pins)
    extent = max(bounds[2] - bounds[0], bounds[3] - bounds[1], 1e-9)
    smallest = min((radial_clearance(result, c["joint"]) for c in clearances), default=0.0)
    factor = float(magnify) if magnify is not None else auto_magnify(smallest, extent)
    if not (math.isfinite(factor) and factor > 0):
        raise ReportError(f"magnify must be a positive number, not {magnify}")
    for c in clearances:
        c.update(_drawn_clearance(result, c["joint"], factor))
    return {
        "bodies": [
            {"name": b.name, "shapes": b.shapes, "pins": pins[b.name], "links": links[b.name]}
            for b in bodies
        ],
        "ground": {"pins": ground_pins, "guides": guides},
        "clearances": clearances,
        "magnify": factor,
        "bounds": bounds,
        "pin_radius": _pin_radius(bodies, extent),
    }


def _pin_radius(bodies: Sequence[_Body], extent: float) -> float:
    widths = [s["width"] for b in bodies for s in b.shapes if s["type"] in ("bar", "path")]
    return 0.3 * min(widths) if widths else 0.012 * extent


def _drawn_clearance(result: Result, joint: str, factor: float) -> dict[str, float]:
    """True and drawn radii: the drawn clearance is ``factor * c``; the bearing keeps its
    radius unless the magnified clearance needs a larger one."""
    data = resolved_clearance(result, joint)
    c, bearing = float(data["clearance"]), float(data["bearing_radius"])
    drawn_c = factor * c
    drawn_bearing = max(bearing, 1.5 * drawn_c)
    return {
        "clearance": c,
        "bearing_radius": bearing,
        "journal_radius": float(data["journal_radius"]),
        "drawn_bearing_radius": drawn_bearing,
        "drawn_journal_radius": drawn_bearing - drawn_c,
    }


def frames(result: Result, index: np.ndarray, ideal: Result | None = None) -> dict[str, Any]:
    """Per frame: time, each body's x, y, angle, each journal's ex, ey, mode, and
    (with ``ideal``) the ideal run's body poses at the same times (interpolated)."""
    time = np.asarray(result.time)[index]
    bodies: dict[str, Any] = {}
    for body in _bodies(result.model):
        x, y, a = _poses(result, body, index)
        bodies[body] = {"x": rounded(x), "y": rounded(y), "angle": rounded(a)}
    joints: dict[str, Any] = {}
    for joint in journal_joints(result):
        entry: dict[str, Any] = {}
        for q in ("ex", "ey", "mode"):
            channel = f"{joint}.{q}"
            if channel not in result:
                raise ReportError(f"the animation needs the channel {channel}: record it")
            entry[q] = rounded(np.asarray(result[channel])[index])
        joints[joint] = entry
    out: dict[str, Any] = {"time": rounded(time, 9), "bodies": bodies, "joints": joints}
    if ideal is not None and len(ideal.time) >= 2:
        ghost: dict[str, Any] = {}
        inside = time <= ideal.time[-1]
        for body in _bodies(result.model):
            if all(f"{body}.{q}" in ideal for q in ("x", "y", "angle")):
                ghost[body] = {
                    q: rounded(
                        np.where(inside, np.interp(time, ideal.time, ideal[f"{body}.{q}"]), np.nan)
                    )
                    for q in ("x", "y", "angle")
                }
        out["ideal"] = ghost
    return out
