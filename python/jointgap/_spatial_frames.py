"""Spatial bodies described in a frame of their own: moved to their centre-of-mass
frame, the engine's, when the model goes to the engine (:meth:`jointgap.Model.to_dict`),
as :func:`jointgap.model._at_centres_of_mass` does for planar bodies.

A body given ``com``, its centre of mass ``c`` in its own frame (URDF's inertial origin,
a CAD part's origin at a joint axis), keeps its axes; with ``R`` the frame's rotation
(its ``orientation``), a point ``s`` of the frame becomes ``s - c``, the origin's
position ``r`` becomes the centre of mass's ``r + R c`` and its velocity ``v`` becomes
``v + w x (R c)`` (``w`` the angular velocity, global axes). The inertia is about the
centre of mass in both descriptions and is not changed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["at_centres_of_mass", "rotation_matrix"]


def _turn(axis: str, angle: float) -> np.ndarray:
    """The rotation matrix of a turn by ``angle`` about the x, y or z axis."""
    c, s = math.cos(angle), math.sin(angle)
    k = "XYZ".index(axis)
    i, j = (k + 1) % 3, (k + 2) % 3
    m = np.eye(3)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def rotation_matrix(orientation: Mapping[str, Any] | None) -> np.ndarray | None:
    """The rotation matrix of an orientation in the engine's form (``quaternion``,
    ``axis_angle``, ``euler``; intrinsic Euler angles, ``R = R1(a) R2(b) R3(c)``);
    the identity for None, and None for one the engine will refuse (zero quaternion or
    axis, unknown convention), whose error the engine reports."""
    if orientation is None:
        return np.eye(3)
    if "quaternion" in orientation:
        q = np.array(orientation["quaternion"], dtype=float)
        norm = float(np.linalg.norm(q))
        if not (math.isfinite(norm) and norm > 0):
            return None
        e0, e1, e2, e3 = q / norm
        return np.array(
            [
                [1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
                [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)],
            ]
        )
    if "axis_angle" in orientation:
        axis = np.array(orientation["axis_angle"]["axis"], dtype=float)
        norm = float(np.linalg.norm(axis))
        if not (math.isfinite(norm) and norm > 0):
            return None
        x, y, z = axis / norm
        k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
        angle = float(orientation["axis_angle"]["angle"])
        rodrigues: np.ndarray = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
        return rodrigues
    convention = str(orientation["euler"]["convention"])
    if len(convention) != 3 or any(a not in "XYZ" for a in convention):
        return None
    angles = orientation["euler"]["angles"]
    turns = [_turn(a, float(t)) for a, t in zip(convention, angles, strict=True)]
    result: np.ndarray = turns[0] @ turns[1] @ turns[2]
    return result


def at_centres_of_mass(model: dict[str, Any]) -> dict[str, Any]:
    """Moves every spatial body given ``com`` to its centre-of-mass frame, in place (the
    module's docstring); the joints', forces' and markers' vector points on it move with
    its points."""
    offsets: dict[str, np.ndarray] = {}
    for body in model["bodies"]:
        c = np.array(body.pop("com", None) or (0.0, 0.0, 0.0), dtype=float)
        if not c.any():
            continue
        offsets[body["name"]] = c
        body["points"] = {k: _list(np.array(s) - c) for k, s in body["points"].items()}
        turn = rotation_matrix(body.get("orientation"))
        rc = (np.eye(3) if turn is None else turn) @ c  # R c, global axes
        body["position"] = _list(np.array(body.get("position", (0.0, 0.0, 0.0))) + rc)
        w = np.array(body.get("angular_velocity", (0.0, 0.0, 0.0)), dtype=float)
        if "velocity" in body or w.any():
            v = np.array(body.get("velocity", (0.0, 0.0, 0.0)), dtype=float)
            body["velocity"] = _list(v + np.cross(w, rc))

    def move(element: dict[str, Any], body_key: str, point_key: str) -> None:
        offset = offsets.get(element.get(body_key, ""))
        point = element.get(point_key)
        if offset is not None and isinstance(point, Sequence) and not isinstance(point, str):
            element[point_key] = _list(np.array(point, dtype=float) - offset)

    for joint in model["joints"]:
        move(joint, "body_i", "point_i")
        move(joint, "body_j", "point_j")
    for force in model["forces"]:
        move(force, "body_i", "point_i")
        move(force, "body_j", "point_j")
        move(force, "body", "point")
    for marker in model["markers"]:
        move(marker, "body", "point")
    return model


def _list(vector: np.ndarray) -> list[float]:
    return [float(x) for x in vector]
