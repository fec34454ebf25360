"""The report of a spatial run (a model with ``"dimension": 3``): its mechanism in 3D
(plotly's WebGL scenes, the script inlined from plotly's wheel), each clearance joint's
pin-centre orbit inside its clearance in 3D, the marker paths, the plotted channels and
the planar report's tables (model, options, run statistics, contact statistics and
impacts per contact point).

Each body is drawn as sticks through its points (its named points, the points its
joints and markers use, in that order; the centre of mass first when it has fewer than
two) with a small triad of its frame, each joint as a marker at its point on body i,
each clearance joint's marker coloured by its contact mode, each marker with its path.

Poses come from the channels ``<body>.x y z e0 e1 e2 e3``: the position of the centre
of mass and the unit quaternion (scalar first) of the body's principal frame. Points of
the model are given in the body frame of the model file, which is the principal frame
turned by the inertia's ``principal.frame`` (identity when absent); for an inertia
given as a ``tensor`` the principal frame is found as the engine finds it
(:func:`principal_frame`). The eccentricity channels ``<joint>.ex ey ez`` are in the
principal frame of body i (the bearing, socket) and are drawn in its model frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation  # type: ignore[import-untyped]

from .._schema import GROUND
from ..errors import ReportError
from ..results import Result, clearance_joints, effort_channels
from ..statistics import contact_statistics, deviation_from_ideal
from .encode import rounded
from .run import DEFAULT_MAX_POINTS, _plots
from .scene import DEFAULT_MAX_FRAMES, auto_magnify, frame_indices
from .tables import (
    Table,
    contact_table,
    deviation_table,
    impact_table,
    model_table,
    options_table,
    run_statistics_table,
)

__all__ = [
    "CLEARANCE_TYPES",
    "ambiguous_frame",
    "is_spatial",
    "orientation_matrix",
    "principal_frame",
    "spatial_deviation_channels",
    "spatial_plotted_channels",
    "spatial_section",
]

CLEARANCE_TYPES = ("clearance_spherical", "clearance_cylindrical", "lubricated_cylindrical")
"""The spatial clearance joints, whose orbits the report draws (a block in its channel has
its contact forces plotted and its impacts listed, no orbit)."""
_TRIAD_FRACTION = 0.08  # length of a body frame's triad, as a fraction of the drawing's size
_POSE = ("x", "y", "z", "e0", "e1", "e2", "e3")


def is_spatial(model: Mapping[str, Any]) -> bool:
    """Whether a model dictionary is spatial (``"dimension": 3``, as the engine reads it)."""
    return model.get("dimension") == 3


def orientation_matrix(orientation: Mapping[str, Any] | None) -> np.ndarray:
    """The rotation matrix of an orientation of the engine's spatial JSON: ``quaternion``
    (scalar first), ``axis_angle`` or ``euler`` (intrinsic: upper-case convention, as
    scipy's); the identity for None."""
    if orientation is None:
        return np.eye(3)
    if "quaternion" in orientation:
        e0, e1, e2, e3 = (float(v) for v in orientation["quaternion"])
        return np.asarray(Rotation.from_quat([e1, e2, e3, e0]).as_matrix())
    if "axis_angle" in orientation:
        aa = orientation["axis_angle"]
        axis = np.asarray(aa["axis"], dtype=float)
        return np.asarray(
            Rotation.from_rotvec(axis / np.linalg.norm(axis) * float(aa["angle"])).as_matrix()
        )
    if "euler" in orientation:
        eu = orientation["euler"]
        return np.asarray(Rotation.from_euler(str(eu["convention"]), eu["angles"]).as_matrix())
    raise ReportError(f"orientation {dict(orientation)!r} cannot be read")


def principal_frame(body: Mapping[str, Any]) -> np.ndarray:
    """The rotation from a body's principal frame (whose quaternion the channels hold) to
    its model frame (in which its points are given).

    A ``principal`` inertia gives it as ``frame`` (identity when absent). A ``tensor``
    is diagonalised by the engine's rule (crates/jointgap-core/src/mechanics/spatial/
    inertia.rs, ``from_tensor``): the eigenvectors ordered to lie closest to the model
    axes, each turned to point along its own, a left-handed triad mended by reversing
    the axis farthest from its own. Where two principal moments are equal and the tensor
    is not diagonal, the axes in their plane are not unique and the engine's may differ
    from these: that body may then be drawn turned about its symmetry axis, and the page
    says so (:func:`ambiguous_frame`, docs/report.md).
    """
    inertia = body.get("inertia", {})
    if "principal" in inertia:
        return orientation_matrix(inertia["principal"].get("frame"))
    if "tensor" not in inertia:
        return np.eye(3)
    j = np.asarray(inertia["tensor"], dtype=float)
    _, v = np.linalg.eigh(0.5 * (j + j.T))
    orders = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    order = max(orders, key=lambda o: sum(abs(v[k, o[k]]) for k in range(3)))
    axes = np.column_stack([v[:, order[k]] * math.copysign(1.0, v[k, order[k]]) for k in range(3)])
    if np.linalg.det(axes) < 0.0:
        k = int(np.argmin(np.diag(axes)))
        axes[:, k] = -axes[:, k]
    return axes


def ambiguous_frame(body: Mapping[str, Any]) -> bool:
    """Whether a body's inertia is a tensor, not diagonal, with two principal moments
    equal (to 1e-6 relative): its principal axes in their plane are not unique, and the
    engine's may differ from :func:`principal_frame`'s."""
    tensor = body.get("inertia", {}).get("tensor")
    if tensor is None:
        return False
    j = np.asarray(tensor, dtype=float)
    if not np.any(j - np.diag(np.diag(j))):
        return False
    moments = np.linalg.eigvalsh(0.5 * (j + j.T))
    return bool(np.min(np.diff(moments)) <= 1e-6 * np.max(np.abs(moments)))


def _point(body: Mapping[str, Any] | None, ref: Any, ground: Mapping[str, Any]) -> list[float]:
    """A joint's or marker's point: a name (of the body's points, or the ground's) or
    [x, y, z] in the body frame (global for the ground)."""
    if isinstance(ref, str):
        points = ground if body is None else body.get("points", {})
        if ref not in points:
            owner = "ground" if body is None else f"body '{body.get('name')}'"
            raise ReportError(f"point '{ref}' is not a point of {owner}")
        ref = points[ref]
    if ref is None:
        return [0.0, 0.0, 0.0]
    return [float(ref[0]), float(ref[1]), float(ref[2])]


def _body_quaternions(result: Result, body: Mapping[str, Any], index: np.ndarray) -> np.ndarray:
    """The body's model frame per frame as unit quaternions (n x 4, scalar first): the
    principal frame's channels turned back by :func:`principal_frame`."""
    name = str(body["name"])
    missing = [f"{name}.{q}" for q in _POSE if f"{name}.{q}" not in result]
    if missing:
        raise ReportError(
            f"the 3D view needs the channels {', '.join(missing)}: record them "
            "(run without --channel, or add 'body.*')"
        )
    e = np.column_stack([np.asarray(result[f"{name}.e{k}"])[index] for k in range(4)])
    principal = Rotation.from_quat(e[:, [1, 2, 3, 0]])
    frame = Rotation.from_matrix(principal_frame(body))
    q = np.asarray((principal * frame.inv()).as_quat())
    return np.column_stack([q[:, 3], q[:, :3]])


def _extent(points: np.ndarray) -> list[list[float]]:
    """[[xmin, ymin, zmin], [xmax, ymax, zmax]] of finite points (k x 3)."""
    finite = points[np.all(np.isfinite(points), axis=1)]
    if not len(finite):
        return [[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]
    return [finite.min(axis=0).tolist(), finite.max(axis=0).tolist()]


def _rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Points ``v`` (k x 3, body frame) turned by each quaternion of ``q`` (n x 4,
    scalar first): n x 3 x k."""
    turned: np.ndarray = np.asarray(Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_matrix()) @ v.T
    return turned


def _path_indices(xyz: np.ndarray, max_points: int) -> np.ndarray:
    """Indices of at most about ``max_points`` points of the 3D path ``xyz`` (3 x n)
    evenly spaced along its length, and its ends (as
    :func:`jointgap.report.run.path_indices` for a 2D path): an orbit on the wall of
    its clearance stays on the wall."""
    n = xyz.shape[1]
    if n <= max_points:
        return np.arange(n)
    step = np.linalg.norm(np.diff(xyz, axis=1), axis=0)
    arc = np.concatenate(([0.0], np.cumsum(np.where(np.isfinite(step), step, 0.0))))
    if not arc[-1] > 0.0:
        return np.array([0, n - 1])
    keep = np.searchsorted(arc, np.linspace(0.0, arc[-1], max_points)).clip(0, n - 1)
    return np.unique(np.concatenate(([0, n - 1], keep)))


def _marker_paths(
    run: Result, markers: Sequence[Mapping[str, Any]], max_points: int, ideal: bool
) -> list[dict[str, Any]]:
    """Each marker's whole path (global, thinned evenly along it), of the run or of the
    ideal run (drawn dashed)."""
    out = []
    for m in markers:
        channels = [f"{m['name']}.{q}" for q in "xyz"]
        if not all(ch in run for ch in channels):
            continue
        xyz = np.vstack([np.asarray(run[ch]) for ch in channels])
        keep = _path_indices(xyz, max_points)
        out.append(
            {
                "marker": str(m["name"]),
                "ideal": ideal,
                "x": rounded(xyz[0, keep]),
                "y": rounded(xyz[1, keep]),
                "z": rounded(xyz[2, keep]),
            }
        )
    return out


def spatial_deviation_channels(result: Result) -> list[str]:
    """The channels a spatial run is compared on with its ideal run: each marker's
    position (an end effector's deviation from its ideal path) and every driver's
    effort, those recorded."""
    chosen = [f"{m['name']}.{q}" for m in result.model.get("markers", []) for q in "xyz"]
    return [c for c in chosen + effort_channels(result) if c in result]


def spatial_plotted_channels(result: Result) -> list[str]:
    """The channels a spatial report plots: driver efforts, each contact point's normal
    force, each marker's position, and the constraint error (those recorded)."""
    chosen = effort_channels(result)
    chosen += [f"{c}.fn" for c in clearance_joints(result)]
    for marker in result.model.get("markers", []):
        chosen += [f"{marker['name']}.{q}" for q in ("x", "y", "z")]
    chosen.append("system.constraint_error")
    return [c for c in dict.fromkeys(chosen) if c in result]


def _contact_points(result: Result, joint: str) -> list[str]:
    """The contact names of a clearance joint: itself, or ``joint.p<i>`` for each of its
    points (as its channels and impact lists are named)."""
    if f"{joint}.mode" in result:
        return [joint]
    return [c for c in clearance_joints(result) if c.startswith(f"{joint}.p")]


def _joint_mode(result: Result, joint: str) -> np.ndarray:
    """The joint's contact mode per sample: the largest of its points' (a joint of two
    ends in impact at one and free at the other shows as in impact)."""
    modes = [np.asarray(result[f"{c}.mode"]) for c in _contact_points(result, joint)]
    if not modes:
        raise ReportError(f"the 3D view needs the channel {joint}.mode: record it")
    mode: np.ndarray = np.nanmax(np.vstack(modes), axis=0)
    return mode


def _clearance_size(result: Result, joint: Mapping[str, Any]) -> float:
    name = str(joint["name"])
    data = result.clearances.get(name)
    if data is not None:
        return float(data["clearance"])
    c = joint.get("clearance", {})
    if "clearance" in c:
        return float(c["clearance"])
    return float(c["bearing_radius"]) - float(c["journal_radius"])


def spatial_section(
    result: Result,
    *,
    ideal: Result | None = None,
    source: str | None = None,
    magnify: float | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
    max_points: int = DEFAULT_MAX_POINTS,
    labels: Sequence[str] | None = None,
) -> dict[str, Any]:
    """Everything the page needs to draw one spatial run in 3D (the counterpart of
    :func:`jointgap.report.run_section`).

    Args:
        result: the run, with its spatial model (``Result.model``, the engine's JSON).
        ideal: the same mechanism with ideal joints: overlaid in the plots, its marker
            paths drawn dashed, and the deviation table
            (:func:`spatial_deviation_channels`).
        source: the model file, shown in the model table.
        magnify: the clearance joints' markers in the 3D view are drawn at the bearing
            centre plus ``magnify`` times the eccentricity; default
            :func:`auto_magnify` of the smallest clearance and the drawing's size.
        max_frames: most animation frames.
        max_points: most points per plotted series, orbit and marker path.
        labels: legend labels of the run and the ideal run.

    Raises:
        ReportError: the result lacks a channel the 3D view needs, a point or body is
            unknown, or the run has fewer than 2 samples.
    """
    model = result.model
    if not is_spatial(model):
        raise ReportError('not a spatial model: the 3D report needs "dimension": 3')
    if not model.get("bodies"):
        raise ReportError("the result carries no model with bodies: nothing to draw")
    if len(result.time) < 2:
        raise ReportError(f"the run has {len(result.time)} samples: a report needs at least 2")
    time = np.asarray(result.time)
    index = frame_indices(time, max_frames)
    ground = model.get("ground_points", {})
    bodies: dict[str, Mapping[str, Any]] = {str(b["name"]): b for b in model["bodies"]}

    def owner(name: Any) -> Mapping[str, Any] | None:
        if str(name) == GROUND:
            return None
        if str(name) not in bodies:
            raise ReportError(f"body '{name}' is not a body of the model")
        return bodies[str(name)]

    # Each body's points in its model frame: named points, then joint and marker points.
    points: dict[str, list[list[float]]] = {
        n: [_point(b, p, ground) for p in b.get("points", {})] for n, b in bodies.items()
    }

    def add(body: str, p: list[float]) -> None:
        if body != GROUND and p not in points[body]:
            points[body].append(p)

    joints: list[dict[str, Any]] = []
    for joint in model.get("joints", []):
        bi, bj = str(joint.get("body_i")), str(joint.get("body_j"))
        pi = _point(owner(bi), joint.get("point_i"), ground)
        pj = _point(owner(bj), joint.get("point_j"), ground)
        add(bi, pi)
        add(bj, pj)
        joints.append(
            {
                "name": str(joint["name"]),
                "type": str(joint.get("type")),
                "body": None if bi == GROUND else bi,
                "point": pi,
            }
        )
    markers: list[dict[str, Any]] = []
    for marker in model.get("markers", []):
        body = str(marker["body"])
        p = _point(owner(body), marker.get("point"), ground)
        add(body, p)
        markers.append(
            {"name": str(marker["name"]), "body": None if body == GROUND else body, "point": p}
        )

    quats = {n: _body_quaternions(result, b, index) for n, b in bodies.items()}
    centres = {
        n: np.column_stack([np.asarray(result[f"{n}.{q}"])[index] for q in "xyz"]) for n in bodies
    }
    sticks: dict[str, list[list[float]]] = {}
    reach = [np.array([p]) for p in (_point(None, g, ground) for g in ground)]
    for n in bodies:
        sticks[n] = points[n] if len(points[n]) >= 2 else [[0.0, 0.0, 0.0], *points[n]]
        glob = _rotate(quats[n], np.array(sticks[n])).transpose(0, 2, 1) + centres[n][:, None, :]
        reach.append(glob.reshape(-1, 3))
    lo, hi = _extent(np.vstack(reach))
    size = max(float(np.max(np.subtract(hi, lo))), 1e-9)

    clearances: list[dict[str, Any]] = []
    orbits: list[dict[str, Any]] = []
    joint_frames: dict[str, Any] = {}
    for joint in model.get("joints", []):
        if joint.get("type") not in CLEARANCE_TYPES:
            continue
        name = str(joint["name"])
        bearing = owner(joint.get("body_i"))
        missing = [f"{name}.e{q}" for q in "xyz" if f"{name}.e{q}" not in result]
        if missing:
            raise ReportError(f"the 3D view needs the channels {', '.join(missing)}: record them")
        e_principal = np.vstack([np.asarray(result[f"{name}.e{q}"]) for q in "xyz"])
        # In the bearing body's model frame: its principal frame turned back.
        turn = np.eye(3) if bearing is None else principal_frame(bearing)
        e = turn @ e_principal
        mode = _joint_mode(result, name)
        c = _clearance_size(result, joint)
        axis = None
        if joint.get("type") != "clearance_spherical":
            a = np.asarray(joint.get("axis") or (0.0, 0.0, 1.0), dtype=float)
            axis = (a / np.linalg.norm(a)).tolist()
        keep = _path_indices(e, max_points)
        if len(keep) < e.shape[1]:
            # Each change of mode stays, so that the colours change where the run's do.
            changes = np.flatnonzero(np.diff(mode) != 0)
            keep = np.union1d(keep, np.concatenate((changes, changes + 1)))
        clearances.append(
            {
                "joint": name,
                "type": str(joint["type"]),
                "bearing_body": None if bearing is None else str(bearing["name"]),
                "point": _point(bearing, joint.get("point_i"), ground),
                "clearance": c,
                "axis": axis,
                "contacts": _contact_points(result, name),
            }
        )
        orbits.append(
            {
                "joint": name,
                "type": str(joint["type"]),
                "clearance": c,
                "axis": axis,
                "bearing_body": None if bearing is None else str(bearing["name"]),
                "ex": rounded(e[0, keep]),
                "ey": rounded(e[1, keep]),
                "ez": rounded(e[2, keep]),
                "mode": rounded(mode[keep], 2),
                "thinned": e.shape[1] if len(keep) < e.shape[1] else 0,
            }
        )
        joint_frames[name] = {
            "ex": rounded(e[0, index]),
            "ey": rounded(e[1, index]),
            "ez": rounded(e[2, index]),
            "mode": rounded(mode[index], 2),
        }
    smallest = min((c["clearance"] for c in clearances), default=0.0)
    factor = float(magnify) if magnify is not None else auto_magnify(smallest, size)
    if not (math.isfinite(factor) and factor > 0):
        raise ReportError(f"magnify must be a positive number, not {magnify}")

    paths = _marker_paths(result, markers, max_points, ideal=False)
    if ideal is not None:
        paths += _marker_paths(ideal, markers, max_points, ideal=True)

    frames = {
        "time": rounded(time[index], 9),
        "bodies": {
            n: {
                "x": rounded(centres[n][:, 0]),
                "y": rounded(centres[n][:, 1]),
                "z": rounded(centres[n][:, 2]),
                "q": [rounded(quats[n][:, k]) for k in range(4)],
            }
            for n in bodies
        },
        "joints": joint_frames,
    }
    name = str(model.get("name") or "run")
    names = (
        (str(labels[0]), str(labels[1]))
        if labels is not None
        else (("clearance", "ideal") if ideal is not None else (name, ""))
    )
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
    if ideal is not None and len(ideal.time):
        compared = [c for c in spatial_deviation_channels(result) if c in ideal]
        if compared:
            tables.append(deviation_table(deviation_from_ideal(result, ideal, compared)))
    plots = _plots(result, ideal, names, max_points, spatial_plotted_channels(result))
    used = {s["x"] for p in plots for s in p["series"] if isinstance(s["x"], str)}
    impacts = [{"joint": j, "t": i.onset_time} for j, lst in result.impacts.items() for i in lst]
    return {
        "spatial": True,
        "name": str(model.get("name") or ""),
        "status": result.status,
        "message": result.message,
        "labels": list(names),
        "scene": {
            "bodies": [{"name": n, "sticks": sticks[n]} for n in bodies],
            "joints": joints,
            "markers": markers,
            "ground": [_point(None, g, ground) for g in ground],
            "ground_names": list(ground),
            "clearances": clearances,
            "bounds": [lo, hi],
            "triad": _TRIAD_FRACTION * size,
            "magnify": factor,
            "paths": paths,
            "notes": [
                f"body '{n}': its inertia tensor has two equal principal moments, so its "
                "principal axes in their plane are not unique: it may be drawn turned about "
                "its symmetry axis (give its inertia as principal moments with a frame)"
                for n, b in bodies.items()
                if ambiguous_frame(b)
            ],
        },
        "frames": frames,
        "times": {
            "run": rounded(time, 9) if "run" in used else [],
            "ideal": rounded(np.asarray(ideal.time), 9)
            if ideal is not None and "ideal" in used
            else [],
        },
        "plots": plots,
        "orbits": orbits,
        "impacts": impacts,
        "impact_counts": {j: len(v) for j, v in result.impacts.items()},
        "tables": [t.to_dict() for t in tables],
    }
