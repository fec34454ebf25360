"""What a study keeps of each case: named metrics computed from the case's result.

Three families, chosen by ``stat``:

* a channel's ``max``, ``min``, ``peak`` (largest absolute value), ``mean`` or ``rms``
  over the samples, optionally within a time ``window`` (``channel = "slider.ax"``);
* contact statistics of a clearance joint (:func:`jointgap.contact_statistics`):
  ``peak_contact_force``, ``max_penetration``, ``impacts``, and the time fractions
  ``free_flight_fraction``, ``impact_fraction``, ``contact_fraction``; over every
  clearance joint unless ``joint`` names one (the largest force and penetration, the
  total impact count; the fractions need one joint);
* the deviation from the ideal mechanism (:func:`jointgap.deviation_from_ideal`):
  ``deviation_rms`` and ``deviation_peak`` of a ``channel``, against the same case with
  every clearance joint made an ideal revolute joint at the same points.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..results import Result, channel_unit
from ..statistics import contact_statistics, deviation_from_ideal

__all__ = [
    "CHANNEL_STATS",
    "CONTACT_STATS",
    "DEVIATION_STATS",
    "Metric",
    "ideal_counterpart",
    "parse_metric",
]

CHANNEL_STATS = ("max", "min", "peak", "mean", "rms")
CONTACT_STATS = {
    "peak_contact_force": "peak_force",
    "max_penetration": "max_penetration",
    "impacts": "impacts",
    "free_flight_fraction": "free_flight",
    "impact_fraction": "impact",
    "contact_fraction": "contact",
}
"""Contact metrics and the :class:`~jointgap.statistics.ContactStatistics` field of each."""
DEVIATION_STATS = {"deviation_rms": "rms", "deviation_peak": "peak"}
"""Deviation metrics and the :class:`~jointgap.statistics.Deviation` field of each."""
_FRACTIONS = ("free_flight_fraction", "impact_fraction", "contact_fraction")
_KEYS = {"stat", "channel", "joint", "window"}


@dataclass(frozen=True)
class Metric:
    """One metric: a column of the study's table.

    Attributes:
        name: the column name.
        stat: what it computes (module docstring).
        channel: the channel of a channel or deviation metric.
        joint: the clearance joint of a contact metric; None: every one.
        window: ``(start, end)`` [s] of a channel metric; end None: the run's end.
    """

    name: str
    stat: str
    channel: str | None = None
    joint: str | None = None
    window: tuple[float, float | None] | None = None

    @property
    def needs_ideal(self) -> bool:
        """True when the metric compares with the ideal mechanism."""
        return self.stat in DEVIATION_STATS

    @property
    def integer(self) -> bool:
        """True for a count (``impacts``)."""
        return self.stat == "impacts"

    @property
    def unit(self) -> str:
        """SI unit of the metric's values."""
        if self.channel is not None:
            return channel_unit(self.channel)
        return {"peak_contact_force": "N", "max_penetration": "m"}.get(self.stat, "")

    def to_dict(self) -> dict[str, Any]:
        """The metric as the study file gives it (SI), for ``study.json``."""
        out: dict[str, Any] = {"name": self.name, "stat": self.stat}
        for key in ("channel", "joint"):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        if self.window is not None:
            out["window"] = list(self.window)
        return out

    def check(self, channels: list[str], clearance: list[str], ideal: list[str]) -> None:
        """Raises ValueError unless a model with these channels, clearance joints and
        ideal-counterpart channels has what the metric needs."""
        if self.stat in CONTACT_STATS:
            if self.joint is not None and self.joint not in clearance:
                raise ValueError(
                    f"no clearance joint '{self.joint}' (clearance joints: "
                    f"{', '.join(clearance) or 'none'})"
                )
            if self.joint is None and self.stat in _FRACTIONS and len(clearance) != 1:
                raise ValueError(
                    f"{self.stat} of which joint? add joint = one of {', '.join(clearance)}"
                )
            return
        assert self.channel is not None
        for names, which in ((channels, "the model"), (ideal, "the ideal mechanism")):
            if self.channel not in names:
                close = [c for c in names if c.split(".")[0] == self.channel.split(".")[0]]
                hint = f" ({', '.join(close)})" if close else ""
                raise ValueError(f"{which} has no channel '{self.channel}'{hint}")
            if not self.needs_ideal:
                break

    def value(self, result: Result, ideal: Result | None = None) -> float:
        """The metric of one finished run (``ideal``: its ideal counterpart)."""
        if self.stat in CONTACT_STATS:
            field = CONTACT_STATS[self.stat]
            stats = [s for s in contact_statistics(result) if self.joint in (None, s.joint)]
            values = [float(getattr(s, field)) for s in stats]
            if self.stat == "impacts":
                return float(sum(values))
            return max(values) if values else math.nan
        assert self.channel is not None
        if self.needs_ideal:
            assert ideal is not None
            (deviation,) = deviation_from_ideal(result, ideal, [self.channel])
            return float(getattr(deviation, DEVIATION_STATS[self.stat]))
        v = result[self.channel]
        if self.window is not None:
            start, end = self.window
            t = result.time
            v = v[(t >= start) & (t <= (math.inf if end is None else end))]
        if len(v) == 0:
            return math.nan
        if self.stat == "min":
            return float(np.min(v))
        if self.stat == "mean":
            return float(np.mean(v))
        if self.stat == "rms":
            return float(np.sqrt(np.mean(v**2)))
        return float(np.max(np.abs(v) if self.stat == "peak" else v))


def parse_metric(name: str, raw: Any, to_seconds: Any) -> Metric:
    """A metric from its study-file entry: a table ``{stat, channel, joint, window}`` or
    just the stat's name. ``to_seconds`` converts a window bound (``"0.2 s"``) to SI.
    Raises ValueError saying what is wrong."""
    spec: Mapping[str, Any] = {"stat": raw} if isinstance(raw, str) else raw
    if not isinstance(spec, Mapping):
        raise ValueError('write a table such as { stat = "peak", channel = "slider.ax" }')
    unknown = sorted(set(spec) - _KEYS)
    if unknown:
        raise ValueError(f"unknown key '{unknown[0]}' (known: {', '.join(sorted(_KEYS))})")
    stat = spec.get("stat")
    known = [*CHANNEL_STATS, *CONTACT_STATS, *DEVIATION_STATS]
    if stat not in known:
        raise ValueError(f"stat {stat!r}: must be one of {', '.join(known)}")
    channel, joint, window = spec.get("channel"), spec.get("joint"), spec.get("window")
    if stat in CONTACT_STATS:
        if channel is not None or window is not None:
            raise ValueError(f"{stat} takes a joint, not a channel or window")
        if joint is not None and not isinstance(joint, str):
            raise ValueError(f"joint {joint!r}: must be a joint name")
        return Metric(name, stat, joint=joint)
    if not isinstance(channel, str):
        raise ValueError(f'{stat} needs channel = "<element>.<quantity>", e.g. "slider.ax"')
    if joint is not None:
        raise ValueError(f"{stat} takes a channel, not a joint")
    if window is None:
        return Metric(name, stat, channel=channel)
    if stat in DEVIATION_STATS:
        raise ValueError(f"{stat} covers the whole run: no window")
    if not (isinstance(window, list) and len(window) == 2):
        raise ValueError(f'window {window!r}: write ["START", "END"], e.g. ["0.2 s", "end"]')
    start = float(to_seconds(window[0]))
    end = None if window[1] == "end" else float(to_seconds(window[1]))
    if start < 0.0 or (end is not None and end <= start):
        raise ValueError(f"window {window!r}: must satisfy 0 <= start < end")
    return Metric(name, stat, channel=channel, window=(start, end))


def ideal_counterpart(model: Mapping[str, Any]) -> dict[str, Any]:
    """A model dictionary with every clearance joint replaced by an ideal revolute joint
    between the same bodies and points (the mechanism the clearance disturbs)."""
    data = copy.deepcopy(dict(model))
    keep = ("name", "body_i", "point_i", "body_j", "point_j")
    data["joints"] = [
        {**{k: j[k] for k in keep}, "type": "revolute"}
        if j.get("type") == "clearance_revolute"
        else j
        for j in data["joints"]
    ]
    return data
