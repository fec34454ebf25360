"""The wear tests' closed-form case: a pin turned at constant speed by a motor on a
carrier that slides freely up and down, pressed by a constant load into a fixed bearing
(the engine's closed-form wear case, crates/jointgap-core/tests/wear.rs), as a planar
model with a clearance_revolute joint or a spatial one with a clearance_cylindrical
joint along z."""

from __future__ import annotations

import math
from typing import Any

import jointgap

LOAD, OMEGA = 200.0, 50.0
R_B, R_J, LENGTH = 7.5e-3, 7.0e-3, 0.01
PERIOD = 2 * math.pi / OMEGA


def pressed_journal(dimension: int = 2) -> jointgap.Model:
    """The pressed journal in ``dimension`` 2 or 3 (the bearing's axis along z)."""
    spatial = dimension == 3

    def at(x: float, y: float) -> list[float]:
        return [x, y, 0.0] if spatial else [x, y]

    def body(name: str, mass: float, inertia: float) -> dict[str, Any]:
        moments = {"principal": {"moments": [inertia] * 3}} if spatial else inertia
        return {"name": name, "mass": mass, "inertia": moments, "position": at(0.0, -0.5e-3)}

    def joint(name: str, type_: str, body_i: str, body_j: str, **more: Any) -> dict[str, Any]:
        pins = {"point_i": at(0.0, 0.0), "point_j": at(0.0, 0.0)}
        return {"name": name, "type": type_, "body_i": body_i, "body_j": body_j, **pins, **more}

    clearance: dict[str, Any] = {
        "bearing_radius": R_B,
        "clearance": 0.5e-3,
        "bearing_material": {"youngs_modulus": 97e9, "poisson_ratio": 0.3},
        "journal_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
        "normal_law": {"type": "kelvin_voigt", "exponent": 1.5, "damping": 1e4},
    }
    z = {"axis": [0.0, 0.0, 1.0]} if spatial else {}
    if spatial:
        bearing = joint(
            "bearing",
            "clearance_cylindrical",
            "ground",
            "pin",
            **z,
            length=LENGTH,
            clearance=clearance,
        )
    else:
        bearing = joint(
            "bearing",
            "clearance_revolute",
            "ground",
            "pin",
            clearance={**clearance, "length": LENGTH},
        )
    return jointgap.Model.from_dict(
        {
            **({"dimension": 3} if spatial else {}),
            "gravity": at(0.0, 0.0),
            "bodies": [body("carrier", 1.0, 1e-3), body("pin", 0.5, 1e-5)],
            "joints": [
                joint("slide", "prismatic", "ground", "carrier", axis=at(0.0, 1.0)),
                joint("spin", "revolute", "carrier", "pin", **z),
                bearing,
            ],
            "drivers": [
                {
                    "name": "motor",
                    "joint": "spin",
                    "profile": {"type": "constant_speed", "speed": OMEGA},
                }
            ],
            "forces": [
                {
                    "type": "applied_force",
                    "name": "load",
                    "body": "carrier",
                    "force": at(0.0, -LOAD),
                }
            ],
        }
    )
