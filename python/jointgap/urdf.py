"""Robots from URDF: a URDF file (and an optional overlay) as a spatial model.

The URDF is read with ``yourdfpy`` (maintained, MIT); this module only turns what it
read into jointgap's terms (docs/urdf.md):

- the tree's root link is the ground (the robot's base bolted down at the origin);
- every other link with mass is a body whose frame sits at its link's inertial origin,
  placed by composing the joint origins at the zero configuration (all joint coordinates
  0), its inertia the URDF tensor about the inertial origin in the inertial frame;
- a link without mass (no ``<inertial>``, or mass 0), or any link welded to the ground,
  is merged into its parent when its joint is ``fixed`` (its frame becomes a frame of
  the parent body: markers may name it); a massless link on a moving joint is an error;
- revolute and continuous joints are ``revolute``, prismatic ``prismatic``, fixed
  ``fixed``; limits are kept as data (:attr:`UrdfJoint.limits`), the run does not
  enforce them; ``floating``, ``planar`` and unknown types are errors.

URDF's ``rpy`` is the fixed-axis roll-pitch-yaw rotation ``Rz(yaw) Ry(pitch) Rx(roll)``
(intrinsic ``ZYX`` with angles ``[yaw, pitch, roll]``); the parser composes it into each
origin's matrix and this module writes orientations as unit quaternions (scalar first).

The overlay (a TOML file or a dict, units as in model files) gives gravity, clearance to
joints by name, drivers per joint and markers on links: see :func:`load_urdf`.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from . import units as u
from ._schema import CLEARANCE_KEYS, convert_element
from .errors import ModelError

__all__ = [
    "UrdfJoint",
    "UrdfLink",
    "UrdfRobot",
    "engine_model",
    "load_robot",
    "load_urdf",
    "read_overlay",
    "read_urdf",
]

Matrix = npt.NDArray[np.float64]

JOINT_TYPES = {
    "revolute": "revolute",
    "continuous": "revolute",
    "prismatic": "prismatic",
    "fixed": "fixed",
}
"""URDF joint types read, and the spatial joint each becomes."""

CLEARANCE_TYPES = ("clearance_cylindrical", "clearance_spherical")
"""Joint types an overlay may give a URDF joint."""

OVERLAY_KEYS = ("urdf", "gravity", "joint", "driver", "marker")
"""Top-level keys of an overlay (``urdf``: the robot's file, for :func:`load_robot`)."""

DRIVE_KEYS = ("stiffness", "damping", "arm", "mass")
"""Keys of a clearance joint's ``drive`` table (all required)."""


@dataclass(frozen=True)
class UrdfLink:
    """A URDF link as read: its inertial frame in the link frame and its mass properties
    (SI); ``mass`` 0 and the identity frame when the link has no ``<inertial>``."""

    name: str
    mass: float
    inertial_origin: Matrix
    """4x4 transform of the inertial frame in the link frame."""
    inertia: Matrix
    """3x3 inertia tensor about the inertial origin, in the inertial frame [kg m^2]."""


@dataclass(frozen=True)
class UrdfJoint:
    """A URDF joint as read: parent and child links, origin of the child link frame in the
    parent link frame at the zero configuration, unit axis in the joint (child) frame."""

    name: str
    type: str
    parent: str
    child: str
    origin: Matrix
    axis: Matrix
    limits: dict[str, float] = field(default_factory=dict)
    """``lower``, ``upper`` [rad or m], ``effort`` [N m or N], ``velocity`` [rad/s or
    m/s], those given: data only, not enforced by a run."""


@dataclass(frozen=True)
class UrdfRobot:
    """A URDF robot as read, with the links' frames at the zero configuration."""

    name: str
    root: str
    links: dict[str, UrdfLink]
    joints: dict[str, UrdfJoint]
    link_frames: dict[str, Matrix]
    """4x4 pose of each link frame in the ground at the zero configuration."""


def _error(
    problem: str, path: str | None, kind: str | None = None, name: str | None = None
) -> ModelError:
    return ModelError(problem, kind=kind, name=name, file=path)


def read_urdf(path: str | PathLike[str]) -> UrdfRobot:
    """Reads a URDF file; raises ModelError naming the file and the offending link or
    joint (unsupported type, zero axis, several roots, a loop)."""
    import yourdfpy

    where = str(path)
    if not Path(path).is_file():
        raise _error("no such URDF file", where)
    try:
        parsed = yourdfpy.URDF.load(
            where, build_scene_graph=False, load_meshes=False, load_collision_meshes=False
        )
    except Exception as exc:  # the parser's own errors: XML, missing attributes
        raise _error(f"cannot read the URDF: {exc}", where) from None
    robot = parsed.robot
    links: dict[str, UrdfLink] = {}
    for link in robot.links:
        inertial = link.inertial
        if inertial is None or inertial.mass is None:
            links[link.name] = UrdfLink(link.name, 0.0, np.eye(4), np.zeros((3, 3)))
            continue
        origin = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, float)
        tensor = (
            np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia, float)
        )
        links[link.name] = UrdfLink(link.name, float(inertial.mass), origin, tensor)
    joints: dict[str, UrdfJoint] = {}
    for joint in robot.joints:
        if joint.type not in JOINT_TYPES:
            raise _error(
                f"type '{joint.type}' is not supported (supported: {', '.join(JOINT_TYPES)})",
                where,
                "joint",
                joint.name,
            )
        for end in (joint.parent, joint.child):
            if end not in links:
                raise _error(f"link '{end}' is not defined", where, "joint", joint.name)
        axis = np.array([1.0, 0.0, 0.0]) if joint.axis is None else np.asarray(joint.axis, float)
        norm = float(np.linalg.norm(axis))
        if joint.type != "fixed" and not norm > 0:
            raise _error(f"axis {list(axis)} has zero length", where, "joint", joint.name)
        limits: dict[str, float] = {}
        if joint.limit is not None:
            for key in ("lower", "upper", "effort", "velocity"):
                value = getattr(joint.limit, key)
                if value is not None:
                    limits[key] = float(value)
        origin = np.eye(4) if joint.origin is None else np.asarray(joint.origin, float)
        joints[joint.name] = UrdfJoint(
            joint.name, joint.type, joint.parent, joint.child, origin, axis / (norm or 1.0), limits
        )
    return UrdfRobot(robot.name, *_tree(links, joints, where))


def _tree(
    links: Mapping[str, UrdfLink], joints: Mapping[str, UrdfJoint], where: str
) -> tuple[str, dict[str, UrdfLink], dict[str, UrdfJoint], dict[str, Matrix]]:
    """The root link, links and joints in tree order (parents first) and each link frame's
    pose at the zero configuration."""
    parent_joint: dict[str, UrdfJoint] = {}
    for joint in joints.values():
        if joint.child in parent_joint:
            raise _error(
                f"link '{joint.child}' is the child of joints '{parent_joint[joint.child].name}' "
                f"and '{joint.name}' (a URDF is a tree)",
                where,
                "joint",
                joint.name,
            )
        parent_joint[joint.child] = joint
    roots = [name for name in links if name not in parent_joint]
    if len(roots) != 1:
        raise _error(f"the links must form one tree; roots found: {roots}", where)
    frames: dict[str, Matrix] = {roots[0]: np.eye(4)}
    ordered: dict[str, UrdfJoint] = {}
    pending = list(joints.values())
    while pending:
        ready = [j for j in pending if j.parent in frames]
        if not ready:
            raise _error(f"joints {[j.name for j in pending]} form a loop", where)
        for joint in ready:
            frames[joint.child] = frames[joint.parent] @ joint.origin
            ordered[joint.name] = joint
        pending = [j for j in pending if j.child not in frames]
    link_order = {name: links[name] for name in frames}
    return roots[0], link_order, ordered, frames


def _quaternion(rotation: Matrix) -> list[float]:
    """Unit quaternion (scalar first, e0 >= 0) of a rotation matrix: Shepperd's method,
    from the largest of the four squared components for accuracy at every angle."""
    r = rotation
    squares = [1 + np.trace(r), 1 + r[0, 0] - r[1, 1] - r[2, 2]]
    squares += [1 - r[0, 0] + r[1, 1] - r[2, 2], 1 - r[0, 0] - r[1, 1] + r[2, 2]]
    k = int(np.argmax(squares))
    big = 0.5 * np.sqrt(squares[k])
    pairs = {
        0: (r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]),
        1: (r[2, 1] - r[1, 2], r[0, 1] + r[1, 0], r[0, 2] + r[2, 0]),
        2: (r[0, 2] - r[2, 0], r[0, 1] + r[1, 0], r[1, 2] + r[2, 1]),
        3: (r[1, 0] - r[0, 1], r[0, 2] + r[2, 0], r[1, 2] + r[2, 1]),
    }[k]
    others = [p / (4 * big) for p in pairs]
    q = np.array(others[:k] + [big] + others[k:]) if k else np.array([big, *others])
    q = q if q[0] >= 0 else -q
    return [float(v) for v in q / np.linalg.norm(q)]


def _point(frame: Matrix, world: Matrix) -> list[float]:
    """A ground point's coordinates in a frame (4x4 pose)."""
    local = np.linalg.solve(frame, np.append(world, 1.0))[:3]
    return [float(v) for v in local]


def _in_frame(frame: Matrix, direction: Matrix) -> list[float]:
    return [float(v) for v in frame[:3, :3].T @ direction]


@dataclass
class _Layout:
    """The model-file dictionary being built, with which body (or ``ground``) each link
    belongs to and each body's frame (4x4 pose in the ground at the zero configuration)."""

    model: dict[str, Any]
    owner: dict[str, str]
    frames: dict[str, Matrix]

    def body(self, name: str) -> dict[str, Any]:
        return next(b for b in self.model["body"] if b["name"] == name)

    def add_point(self, body: str, name: str, world: Matrix) -> None:
        """Names a point (ground coordinates) on a body or the ground."""
        local = _point(self.frames[body], world)
        if body == GROUND:
            self.model["ground"]["points"][name] = local
        else:
            self.body(body)["points"][name] = local


GROUND = "ground"


def _layout(robot: UrdfRobot, where: str | None) -> _Layout:
    """The robot as a spatial model-file dictionary (the TOML structure, SI numbers):
    ``model``, ``ground``, ``body``, ``joint``. Raises ModelError for a massless link on
    a moving joint."""
    ground = GROUND
    owner = {robot.root: ground}
    body_frames: dict[str, Matrix] = {ground: np.eye(4)}
    bodies: dict[str, dict[str, Any]] = {}
    ground_points: dict[str, list[float]] = {}
    joints: list[dict[str, Any]] = []
    for joint in robot.joints.values():
        child = robot.links[joint.child]
        parent_owner = owner[joint.parent]
        if joint.type == "fixed" and (parent_owner == ground or child.mass == 0.0):
            owner[child.name] = parent_owner
            continue
        if not child.mass > 0:
            raise _error(
                f"has no mass (no <inertial> or mass 0) and its joint '{joint.name}' is "
                f"{joint.type}: give it an <inertial>, or join it to its parent by a fixed joint",
                where,
                "link",
                child.name,
            )
        frame = robot.link_frames[child.name] @ child.inertial_origin
        owner[child.name] = child.name
        body_frames[child.name] = frame
        bodies[child.name] = {
            "name": child.name,
            "mass": child.mass,
            "inertia": child.inertia.tolist(),
            "position": [float(v) for v in frame[:3, 3]],
            "orientation": {"quaternion": _quaternion(frame[:3, :3])},
            "points": {},
        }
        joint_frame = robot.link_frames[child.name]
        at = joint_frame[:3, 3]
        parent_frame = body_frames[parent_owner]
        point_i = _point(parent_frame, at)
        if parent_owner == ground:
            ground_points[joint.name] = point_i
        else:
            bodies[parent_owner]["points"][joint.name] = point_i
        bodies[child.name]["points"][joint.name] = _point(frame, at)
        entry: dict[str, Any] = {
            "name": joint.name,
            "type": JOINT_TYPES[joint.type],
            "body_i": parent_owner,
            "point_i": joint.name,
            "body_j": child.name,
            "point_j": joint.name,
        }
        if joint.type != "fixed":
            direction = joint_frame[:3, :3] @ joint.axis
            entry["axis"] = _in_frame(parent_frame, direction)
            entry["axis_j"] = _in_frame(frame, direction)
        joints.append(entry)
    model = {
        "model": {"name": robot.name, "dimension": 3},
        "ground": {"points": ground_points},
        "body": list(bodies.values()),
        "joint": joints,
    }
    return _Layout(model, owner, body_frames)


_SPHERICAL_NAMES = {
    "socket_radius": "bearing_radius",
    "ball_radius": "journal_radius",
    "socket_material": "bearing_material",
    "ball_material": "journal_material",
}
"""A ball-in-socket joint's keys in model files, and the engine's names for them."""


def _overlay_table(overlay: Mapping[str, Any], key: str, where: str | None) -> Mapping[str, Any]:
    table = overlay.get(key, {})
    if not isinstance(table, Mapping) or not all(isinstance(v, Mapping) for v in table.values()):
        raise _error(f"overlay: [{key}.NAME] must be tables, got {table!r}", where)
    return table


def _length(value: Any, kind: str, name: str, key: str, where: str | None) -> float:
    try:
        return u.to_si(value, u.LENGTH)
    except ValueError as exc:
        raise ModelError(f"{key} {exc}", kind=kind, name=name, key=key, file=where) from None


def _vector(
    value: Any, dim: u.Dimension, kind: str, name: str, key: str, where: str | None
) -> list[float]:
    if not isinstance(value, list | tuple) or len(value) != 3:
        raise ModelError(
            f"{key} = {value!r}: must be 3 values", kind=kind, name=name, key=key, file=where
        )
    try:
        return [u.to_si(v, dim) for v in value]
    except ValueError as exc:
        raise ModelError(f"{key} {exc}", kind=kind, name=name, key=key, file=where) from None


def _moving_joint(robot: UrdfRobot, name: str, table: str, where: str | None) -> UrdfJoint:
    joint = robot.joints.get(name)
    if joint is None:
        raise _error(
            f"overlay [{table}.{name}]: no joint '{name}' in the URDF (joints: "
            f"{', '.join(robot.joints)})",
            where,
            "joint",
            name,
        )
    if joint.type == "fixed":
        raise _error(
            f"overlay [{table}.{name}]: the joint is fixed in the URDF", where, "joint", name
        )
    return joint


def _converted(kind: str, raw: Mapping[str, Any], where: str | None) -> dict[str, Any]:
    """An element's overlay values in SI by the model files' own conversion, its errors
    located in the overlay file."""
    try:
        return convert_element(kind, raw)[0]
    except ModelError as exc:
        raise exc if where is None else exc.located(where, None) from None


def _clearance(
    layout: _Layout, entry: dict[str, Any], spec: Mapping[str, Any], where: str | None
) -> Mapping[str, Any] | None:
    """Turns a joint entry into a clearance joint from its overlay table; returns the
    ``drive`` table, if any."""
    name = entry["name"]
    kind = spec.get("type")
    if kind not in CLEARANCE_TYPES:
        raise ModelError(
            f"overlay type = {kind!r}: must be one of {', '.join(CLEARANCE_TYPES)}",
            kind="joint",
            name=name,
            key="type",
            file=where,
        )
    keys = {_SPHERICAL_NAMES.get(k, k): v for k, v in spec.items()}
    contact = {k: v for k, v in keys.items() if k in CLEARANCE_KEYS}
    unknown = set(keys) - set(CLEARANCE_KEYS) - {"type", "length", "axial_clearance", "drive"}
    if unknown:
        raise ModelError(
            f"overlay: unknown key(s) {', '.join(sorted(unknown))}",
            kind="joint",
            name=name,
            file=where,
        )
    # The planar reader's conversion of the contact keys (units, laws, materials, the
    # defaults the engine fills in), the one place that knows them.
    planar = {"name": name, "type": "clearance_revolute", "body_i": "i", "point_i": [0, 0]}
    converted = _converted("joint", {**planar, "body_j": "j", "point_j": [0, 0], **contact}, where)
    entry["type"] = kind
    entry.update(converted["clearance"])
    for key in ("length", "axial_clearance"):
        if key in keys:
            entry[key] = _length(keys[key], "joint", name, key, where)
    if kind == "clearance_spherical":
        entry.pop("axis", None)
        entry.pop("axis_j", None)
    drive = keys.get("drive")
    if drive is not None and not isinstance(drive, Mapping):
        raise ModelError(
            f"drive = {drive!r}: must be a table", kind="joint", name=name, key="drive", file=where
        )
    return drive


_DRIVE_UNITS = {
    "stiffness": u.ROTATIONAL_STIFFNESS,
    "damping": u.ROTATIONAL_DAMPING,
    "arm": u.LENGTH,
    "mass": u.MASS,
}


def _drive(
    layout: _Layout, entry: dict[str, Any], drive: Mapping[str, Any], where: str | None
) -> str:
    """Adds the drive train of a clearance joint that is driven: a rotor (a disc of
    radius ``arm`` and the given mass) on an ideal revolute joint ``<joint>_drive`` of the
    parent body, coupled to the child body by a tangential spring-damper ``<joint>_mesh``
    at radius ``arm`` (a gear mesh of torsional stiffness ``stiffness`` and damping
    ``damping``: linear k = stiffness / arm^2, c = damping / arm^2, free length arm).
    The spring also pulls the journal along its line with k: a long arm keeps that pull
    small against the contact forces (a shift across the spring's line strains it only
    to second order). Returns the driven joint's name."""
    name = entry["name"]
    values: dict[str, float] = {}
    for key in DRIVE_KEYS:
        if key not in drive:
            raise ModelError(
                f"drive.{key} is required (drive keys: {', '.join(DRIVE_KEYS)})",
                kind="joint",
                name=name,
                key=f"drive.{key}",
                file=where,
            )
        try:
            values[key] = u.to_si(drive[key], _DRIVE_UNITS[key])
        except ValueError as exc:
            raise ModelError(
                f"drive.{key} {exc}", kind="joint", name=name, key=f"drive.{key}", file=where
            ) from None
        bound = ">= 0" if key == "damping" else "> 0"
        if not (values[key] >= 0 if key == "damping" else values[key] > 0):
            raise ModelError(
                f"drive.{key} = {values[key]:g}: must be {bound}",
                kind="joint",
                name=name,
                key=f"drive.{key}",
                file=where,
            )
    unknown = set(drive) - set(DRIVE_KEYS)
    if unknown:
        raise ModelError(
            f"drive: unknown key(s) {', '.join(sorted(unknown))}",
            kind="joint",
            name=name,
            file=where,
        )
    if entry["type"] != "clearance_cylindrical":
        raise ModelError(
            "a drive needs a clearance_cylindrical joint", kind="joint", name=name, file=where
        )
    parent, child = entry["body_i"], entry["body_j"]
    pframe = layout.frames[parent]
    at = (
        pframe[:3, :3]
        @ np.array(
            layout.model["ground"]["points"][name]
            if parent == GROUND
            else layout.body(parent)["points"][name]
        )
        + pframe[:3, 3]
    )
    axis = pframe[:3, :3] @ np.array(entry["axis"])
    axis /= np.linalg.norm(axis)
    radial = np.cross(axis, np.eye(3)[int(np.argmin(np.abs(axis)))])
    radial /= np.linalg.norm(radial)
    tangential = np.cross(axis, radial)
    r, m = values["arm"], values["mass"]
    rotor = f"{name}_rotor"
    inertia = m * r**2 / 4 * (np.eye(3) - np.outer(axis, axis)) + m * r**2 / 2 * np.outer(
        axis, axis
    )
    layout.model["body"].append(
        {
            "name": rotor,
            "mass": m,
            "inertia": inertia.tolist(),
            "position": [float(v) for v in at],
            "orientation": {"quaternion": [1.0, 0.0, 0.0, 0.0]},
            "points": {"axis": [0.0, 0.0, 0.0], "mesh": [float(v) for v in r * radial]},
        }
    )
    frame = np.eye(4)
    frame[:3, 3] = at
    layout.frames[rotor] = frame
    driven = f"{name}_drive"
    layout.add_point(child, f"{name}_mesh", at + r * radial + r * tangential)
    layout.model["joint"].append(
        {
            "name": driven,
            "type": "revolute",
            "body_i": parent,
            "point_i": name,
            "body_j": rotor,
            "point_j": "axis",
            "axis": entry["axis"],
            "axis_j": [float(v) for v in axis],
        }
    )
    layout.model.setdefault("force", []).append(
        {
            "type": "spring_damper",
            "name": f"{name}_mesh",
            "body_i": rotor,
            "point_i": "mesh",
            "body_j": child,
            "point_j": f"{name}_mesh",
            "stiffness": values["stiffness"] / r**2,
            "damping": values["damping"] / r**2,
            "free_length": r,
        }
    )
    return driven


def _apply(
    layout: _Layout, robot: UrdfRobot, overlay: Mapping[str, Any], where: str | None
) -> None:
    unknown = set(overlay) - set(OVERLAY_KEYS)
    if unknown:
        raise _error(
            f"overlay: unknown table(s) {', '.join(sorted(unknown))} "
            f"(allowed: {', '.join(OVERLAY_KEYS)})",
            where,
        )
    model = layout.model
    if "gravity" in overlay:
        model["model"]["gravity"] = _vector(
            overlay["gravity"], u.ACCELERATION, "model", "", "gravity", where
        )
    entries = {j["name"]: j for j in model["joint"]}
    drives: dict[str, Mapping[str, Any]] = {}
    for name, spec in _overlay_table(overlay, "joint", where).items():
        _moving_joint(robot, name, "joint", where)
        drive = _clearance(layout, entries[name], spec, where)
        if drive is not None:
            drives[name] = drive
    drivers = _overlay_table(overlay, "driver", where)
    for name in drives:
        if name not in drivers:
            raise _error("has a drive table but no [driver] entry", where, "joint", name)
    for name, spec in drivers.items():
        _moving_joint(robot, name, "driver", where)
        unknown = set(spec) - {"profile", "initial"}
        if unknown:
            raise _error(
                f"overlay: unknown key(s) {', '.join(sorted(unknown))}", where, "driver", name
            )
        joint = name
        if entries[name]["type"] in CLEARANCE_TYPES:
            if name not in drives:
                raise _error(
                    "has clearance and a driver: give the joint a drive table (the drive "
                    "train that turns it, docs/urdf.md)",
                    where,
                    "joint",
                    name,
                )
            joint = _drive(layout, entries[name], drives[name], where)
        driver = _converted("driver", {"name": f"{name}_motor", "joint": joint, **spec}, where)
        model.setdefault("driver", []).append(driver)
    for name, spec in _overlay_table(overlay, "marker", where).items():
        link = spec.get("link")
        if link not in robot.links:
            raise _error(f"link = {link!r} is not a link of the URDF", where, "marker", name)
        unknown = set(spec) - {"link", "point"}
        if unknown:
            raise _error(
                f"overlay: unknown key(s) {', '.join(sorted(unknown))}", where, "marker", name
            )
        local = _vector(spec.get("point", [0, 0, 0]), u.LENGTH, "marker", name, "point", where)
        world = (robot.link_frames[link] @ np.append(local, 1.0))[:3]
        body = layout.owner[link]
        model.setdefault("marker", []).append(
            {"name": name, "body": body, "point": _point(layout.frames[body], world)}
        )


def load_urdf(
    path: str | PathLike[str], overlay: str | PathLike[str] | Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """Reads a URDF robot, applies the overlay, and returns the spatial model-file
    dictionary (TOML structure, SI numbers, ``dimension = 3``): ``model``, ``ground``,
    ``body``, ``joint`` and, from the overlay, ``driver``, ``force``, ``marker``.

    The overlay (a TOML file's path or a dict; units as in model files) has the tables
    ``gravity`` (3 values), ``[joint.NAME]`` (a URDF joint given clearance: ``type``
    ``clearance_cylindrical`` or ``clearance_spherical`` and the clearance keys of model
    files, optionally ``drive``), ``[driver.NAME]`` (``profile`` for the URDF joint
    NAME) and ``[marker.NAME]`` (``link`` and ``point`` in the link frame). Raises
    ModelError naming the file and the offending item.
    """
    robot = read_urdf(path)
    layout = _layout(robot, str(path))
    if overlay is not None:
        where = None if isinstance(overlay, Mapping) else str(overlay)
        try:
            _apply(layout, robot, read_overlay(overlay), where)
        except ModelError as exc:
            raise _with_line(exc) from None
    return layout.model


def load_robot(overlay: str | PathLike[str]) -> dict[str, Any]:
    """The model of an overlay file that names its robot, ``urdf = "arm.urdf"`` (a path
    relative to the overlay's folder): :func:`load_urdf` of that URDF with the overlay.
    Such a file is a model file of its own (``jointgap.load``, ``jointgap run``)."""
    spec = read_overlay(overlay)
    robot = spec.get("urdf")
    if not isinstance(robot, str):
        raise _error(f"urdf = {robot!r}: the overlay must name its URDF file", str(overlay))
    return load_urdf(Path(overlay).parent / robot, overlay)


def _with_line(error: ModelError) -> ModelError:
    """The error with the line of its element's table in the overlay file (the first
    line that opens ``[joint.NAME``, ``[driver.NAME`` or ``[marker.NAME``), when found."""
    if error.file is None or error.line is not None or not error.name:
        return error
    tables = {"joint": ("joint", "driver"), "driver": ("driver",), "marker": ("marker",)}
    heads = tuple(f"[{t}.{error.name}" for t in tables.get(error.kind or "", ()))
    try:
        lines = Path(error.file).read_text().splitlines()
    except OSError:
        return error
    for number, text in enumerate(lines, 1):
        if text.strip().startswith(heads):
            return error.located(error.file, number)
    return error


def read_overlay(overlay: str | PathLike[str] | Mapping[str, Any]) -> Mapping[str, Any]:
    """An overlay as a dict: a TOML file read, or the dict itself. Raises ModelError
    naming the file when it is missing or not TOML."""
    if isinstance(overlay, Mapping):
        return overlay
    where = str(overlay)
    try:
        return tomllib.loads(Path(overlay).read_text())
    except FileNotFoundError:
        raise _error("no such overlay file", where) from None
    except tomllib.TOMLDecodeError as exc:
        raise _error(f"overlay: {exc}", where) from None


def engine_model(model: Mapping[str, Any]) -> dict[str, Any]:
    """The engine's spatial JSON (as a dict) of a model-file dictionary from
    :func:`load_urdf`: the same data, under the engine's keys (``bodies``, ``joints``,
    inertia as a tensor, the contact keys of a clearance joint nested in
    ``clearance``)."""
    head = model["model"]
    engine: dict[str, Any] = {"dimension": 3, "name": head.get("name", "")}
    if "gravity" in head:
        engine["gravity"] = head["gravity"]
    engine["ground_points"] = dict(model.get("ground", {}).get("points", {}))
    engine["bodies"] = [{**b, "inertia": {"tensor": b["inertia"]}} for b in model.get("body", [])]
    joints = []
    for joint in model.get("joint", []):
        out = {k: v for k, v in joint.items() if k not in CLEARANCE_KEYS}
        contact = {k: v for k, v in joint.items() if k in CLEARANCE_KEYS}
        if contact:
            out["clearance"] = contact
        joints.append(out)
    engine["joints"] = joints
    engine["drivers"] = list(model.get("driver", []))
    engine["forces"] = list(model.get("force", []))
    engine["markers"] = list(model.get("marker", []))
    return engine
