"""A short spatial run for the 3D report's tests (tests/test_report_spatial.py, and in
the browser tests/test_report_browser.py): an arm hung from the ground by a ball in a
socket with clearance (``clearance_spherical``), a tip on its end by a journal in a
bearing with clearance (``clearance_cylindrical``, the bearing in the arm), a marker at
the tip's end. The arm's principal axes are turned from its model frame and the tip's
inertia is a full tensor, so that the report's poses must turn the engine's principal
frames back to the frames the points are given in."""

from __future__ import annotations

import math
from typing import Any

HALF_TURN = math.pi / 2
T_END = 0.3
RATE = 5000


def ball_and_hinge_pendulum() -> dict[str, Any]:
    """The model as the engine's spatial JSON (SI units, radians)."""
    down = {"axis_angle": {"axis": [0.0, 1.0, 0.0], "angle": HALF_TURN}}  # body z along x
    return {
        "dimension": 3,
        "name": "ball_and_hinge_pendulum",
        "gravity": [0.0, 0.0, -9.81],
        "ground_points": {"O": [0.0, 0.0, 0.0]},
        "bodies": [
            {
                "name": "arm",
                "mass": 1.0,
                "inertia": {
                    "principal": {
                        "moments": [8e-3, 8e-3, 1e-4],
                        "frame": {"euler": {"convention": "ZYX", "angles": [0.2, 0.0, 0.3]}},
                    }
                },
                "position": [0.15, 0.0, 0.0],
                "orientation": down,
                "angular_velocity": [0.0, 0.0, 2.0],
                "points": {"S": [0.0, 0.0, -0.15], "T": [0.0, 0.0, 0.15]},
            },
            {
                "name": "tip",
                "mass": 0.3,
                "inertia": {"tensor": [[1e-3, 0.0, 0.0], [0.0, 1e-3, 2e-4], [0.0, 2e-4, 5e-4]]},
                "position": [0.35, 0.0, 0.0],
                "orientation": down,
                "points": {"A": [0.0, 0.0, -0.05], "E": [0.0, 0.0, 0.05]},
            },
        ],
        "joints": [
            {
                "name": "ball",
                "type": "clearance_spherical",
                "body_i": "ground",
                "point_i": "O",
                "body_j": "arm",
                "point_j": "S",
                "clearance": {
                    "bearing_radius": 0.01,
                    "clearance": 2e-4,
                    "stiffness": 1e9,
                    "normal_law": {"type": "lankarani_nikravesh", "restitution": 0.8},
                },
            },
            {
                "name": "elbow",
                "type": "clearance_cylindrical",
                "body_i": "arm",
                "point_i": "T",
                "body_j": "tip",
                "point_j": "A",
                "axis": [0.0, 1.0, 0.0],
                "length": 0.02,
                "axial_clearance": 2e-4,
                "clearance": {
                    "bearing_radius": 0.006,
                    "clearance": 1e-4,
                    "stiffness": 5e8,
                    "normal_law": {"type": "lankarani_nikravesh", "restitution": 0.8},
                },
            },
        ],
        "markers": [{"name": "end", "body": "tip", "point": "E"}],
    }


def spatial_run() -> Any:
    """The run: T_END seconds at RATE (a jointgap Result)."""
    from jointgap._engine import run_options, simulate

    return simulate(ball_and_hinge_pendulum(), run_options(T_END, rate=RATE))


def ideal_pendulum() -> dict[str, Any]:
    """The same pendulum with ideal joints: a spherical joint for the ball, a revolute
    joint about the bearing's axis for the journal."""
    model = ball_and_hinge_pendulum()
    model["name"] = "ball_and_hinge_pendulum_ideal"
    ball, elbow = model["joints"]
    for joint, kind in ((ball, "spherical"), (elbow, "revolute")):
        joint["type"] = kind
        for key in ("clearance", "length", "axial_clearance"):
            joint.pop(key, None)
    return model


def ideal_run() -> Any:
    """The ideal pendulum's run, on the same samples as :func:`spatial_run`."""
    from jointgap._engine import run_options, simulate

    return simulate(ideal_pendulum(), run_options(T_END, rate=RATE))
