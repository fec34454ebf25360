"""Variants of a model: a clearance joint's contact parameters set by name, for
identification (:mod:`jointgap.identify`) and batch runs (:func:`jointgap.simulate_batch`).

A parameter is ``<joint>.<quantity>`` with ``quantity`` one of :data:`QUANTITIES`: a
normal law's ``restitution``, ``c_max``, ``d_max`` or ``damping``; a friction law's
``mu_s``, ``mu_d``, ``mu`` or ``viscous``; the contact ``stiffness``; the radial
``clearance`` (the bearing radius is kept). ``*.<quantity>`` sets it in every clearance
joint. Beyond the contact: a driver's ``<driver>.speed`` (the final speed of a constant
or ramped profile) and ``<driver>.ramp_time``, and ``gravity`` (its magnitude, along the
model's gravity direction, -y when the model has none).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from typing import Any

from .model import Model

__all__ = [
    "FRICTION_KEYS",
    "LAW_KEYS",
    "QUANTITIES",
    "DRIVER_KEYS",
    "clearance_joint",
    "set_clearance_parameter",
    "set_driver_parameter",
    "with_parameters",
]

LAW_KEYS = {"restitution", "c_max", "d_max", "damping"}
FRICTION_KEYS = {"mu_s", "mu_d", "mu", "viscous"}
QUANTITIES = LAW_KEYS | FRICTION_KEYS | {"stiffness", "clearance"}
"""The contact parameters a variant can set."""
DRIVER_KEYS = {"speed", "ramp_time"}
"""The driver-profile parameters a variant can set (``motor.speed``)."""


def parameter_value(path: str, value: Any) -> float:
    """A parameter's value in SI: a number, or a quantity string in the parameter's
    dimension (``"0.3 mm"`` for a clearance, ``"20 kN*s/m"`` for a C_max)."""
    from . import units as u

    quantity = path.rpartition(".")[2]
    if quantity not in QUANTITIES | DRIVER_KEYS | {"gravity"}:
        known = ", ".join(sorted(QUANTITIES | DRIVER_KEYS | {"gravity"}))
        raise ValueError(f"parameter {path}: unknown quantity '{quantity}' (known: {known})")
    dims: dict[str, u.Dimension | tuple[u.Dimension, ...]] = {
        "c_max": u.DAMPING,
        "damping": u.DAMPING,
        "viscous": u.DAMPING,
        "d_max": u.LENGTH,
        "clearance": u.LENGTH,
        "stiffness": (u.STIFFNESS, u.HERTZ_STIFFNESS),
        "speed": (u.ANGULAR_SPEED, u.SPEED),
        "ramp_time": u.TIME,
        "gravity": u.ACCELERATION,
    }
    try:
        return u.to_si(
            value.strip() if isinstance(value, str) else value, dims.get(quantity, u.DIMENSIONLESS)
        )
    except u.UnitError as exc:
        raise ValueError(f"parameter {path}: {exc}") from None


def with_parameters(model: Model, parameters: Mapping[str, Any]) -> Model:
    """A copy of ``model`` with ``{"joint.quantity": value}`` set (SI numbers or
    quantity strings such as ``"0.3 mm"``)."""
    data = copy.deepcopy(model.to_dict())
    for path, value in parameters.items():
        element, _, quantity = path.rpartition(".")
        si = parameter_value(path, value)
        if quantity == "gravity":
            if element or si < 0.0:
                raise ValueError(f"parameter {path} = {si:g}: set 'gravity' to a magnitude >= 0")
            gx, gy = data["gravity"]
            norm = math.hypot(gx, gy)
            data["gravity"] = [si * gx / norm, si * gy / norm] if norm > 0.0 else [0.0, -si]
        elif quantity in DRIVER_KEYS:
            set_driver_parameter(data, element, quantity, si)
        else:
            every = [j["name"] for j in data["joints"] if j.get("type") == "clearance_revolute"]
            for joint in (every if element == "*" else []) or [element]:
                set_clearance_parameter(data, joint, quantity, si)
    return Model.from_dict(data)


def set_driver_parameter(data: dict[str, Any], driver: str, quantity: str, value: float) -> None:
    """Writes ``driver.quantity = value`` into the profile of a driver in a model dictionary."""
    for d in data["drivers"]:
        if d["name"] == driver:
            if quantity not in d["profile"]:
                kind = d["profile"]["type"]
                raise ValueError(
                    f"{driver}.{quantity}: the {kind} profile of '{driver}' has no {quantity}"
                )
            d["profile"][quantity] = value
            return
    names = ", ".join(d["name"] for d in data["drivers"]) or "none"
    raise ValueError(f"no driver '{driver}' in the model (drivers: {names})")


def set_clearance_parameter(
    data: dict[str, Any], joint_name: str, quantity: str, value: float
) -> None:
    """Writes ``joint.quantity = value`` into a model dictionary."""
    joint = clearance_joint(data, joint_name)
    spec = joint["clearance"]
    law, friction = spec["normal_law"], spec.get("friction") or {"type": "none"}
    q = quantity
    if q in LAW_KEYS:
        if q not in law:
            raise ValueError(
                f"{joint_name}.{q}: the {law['type']} law of '{joint_name}' has no {q}"
            )
        law[q] = value
    elif q in FRICTION_KEYS:
        if q not in friction:
            raise ValueError(
                f"{joint_name}.{q}: the {friction['type']} friction of '{joint_name}' has no {q}"
            )
        friction[q] = value
    elif q == "stiffness":
        spec["stiffness"] = value
    elif q == "clearance":
        bearing = spec.get("bearing_radius")
        if bearing is not None and spec.get("journal_radius") is not None:
            spec["journal_radius"] = bearing - value
        else:
            spec["clearance"] = value


def clearance_joint(data: dict[str, Any], joint: str) -> dict[str, Any]:
    for j in data["joints"]:
        if j["name"] == joint:
            if j.get("type") != "clearance_revolute":
                raise ValueError(
                    f"joint '{joint}' is a {j.get('type')} joint, not a clearance joint"
                )
            found: dict[str, Any] = j
            return found
    names = [j["name"] for j in data["joints"] if j.get("type") == "clearance_revolute"]
    raise ValueError(
        f"no joint '{joint}' in the model (clearance joints: {', '.join(names) or 'none'})"
    )
