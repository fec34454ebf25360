"""Motion profiles of drivers: how a driven joint moves against time.

A profile describes the joint coordinate relative to its initial value: an angle for a
revolute joint (speeds in rad/s, ``"300 rpm"``, ``"90 deg/s"``), a displacement for a
prismatic joint (m/s, ``"0.2 m/s"``). Positive is counter-clockwise (revolute) or along
the joint axis (prismatic). Values are checked when the profile is made and again,
against the driven joint, when it is given to :meth:`jointgap.Model.add_driver`.

>>> from jointgap import profiles
>>> profiles.linear_ramp("300 rpm", "0.2 s").to_dict()["type"]
'linear_ramp'
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ._schema import convert_element

__all__ = [
    "Profile",
    "constant_speed",
    "linear_ramp",
    "smooth_ramp",
    "table_angle",
    "table_speed",
]

Quantity = float | str


@dataclass(frozen=True)
class Profile:
    """A driver's motion profile: its ``type`` and the user's values (numbers or units)."""

    type: str
    params: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", MappingProxyType(dict(self.params)))
        convert_element("profile", self.to_dict(), label=f"{self.type} profile")

    def to_dict(self) -> dict[str, Any]:
        """The profile as a table, as written in a model file (values not converted)."""
        return {"type": self.type, **self.params}

    def to_si(self) -> dict[str, Any]:
        """The profile in SI units and radians, as the engine reads it."""
        return convert_element("profile", self.to_dict(), label=f"{self.type} profile")[0]


def constant_speed(speed: Quantity) -> Profile:
    """Constant speed from t = 0 (rad/s or m/s; e.g. ``"60 rpm"``)."""
    return Profile("constant_speed", {"speed": speed})


def linear_ramp(speed: Quantity, ramp_time: Quantity) -> Profile:
    """Speed rising linearly from rest to ``speed`` over ``ramp_time``, then constant."""
    return Profile("linear_ramp", {"speed": speed, "ramp_time": ramp_time})


def smooth_ramp(speed: Quantity, ramp_time: Quantity) -> Profile:
    """Speed rising from rest to ``speed`` along a cubic STEP over ``ramp_time`` (no jerk
    at the ends of the ramp), then constant."""
    return Profile("smooth_ramp", {"speed": speed, "ramp_time": ramp_time})


def table_angle(time: Sequence[Quantity], value: Sequence[Quantity]) -> Profile:
    """Displacement of the joint (angle or length) at the given times, interpolated by a
    natural cubic spline. Times strictly increasing, at least two."""
    return Profile("table_angle", {"time": list(time), "value": list(value)})


def table_speed(time: Sequence[Quantity], value: Sequence[Quantity]) -> Profile:
    """Speed of the joint at the given times, linear between points; the displacement is
    its integral. Times strictly increasing, at least two."""
    return Profile("table_speed", {"time": list(time), "value": list(value)})
