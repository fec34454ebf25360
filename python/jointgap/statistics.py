"""Contact statistics of clearance joints, and how far a clearance run strays from an
ideal one.

Per clearance joint (:func:`contact_statistics`): the number of impacts, the fractions of
time spent in free flight, impact and continuous contact, the peak contact force, the
largest penetration, and the mean and largest onset speed. Against a run of the same
mechanism with ideal joints (:func:`deviation_from_ideal`): the RMS and the peak of the
difference of chosen channels (by default the slider acceleration and the motor efforts)::

    r = jointgap.load("examples/slider_crank_clearance.toml").simulate(0.5, rate=10_000)
    ideal = jointgap.load("examples/slider_crank_ideal.toml").simulate(0.5, rate=10_000)
    print(format_statistics(contact_statistics(r), deviation_from_ideal(r, ideal)))

Both come as frozen objects with ``to_dict()`` (strict JSON: NaN becomes None) and as
tables (:func:`statistics_table`, :func:`deviation_table`), SI units throughout.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .results import (
    Result,
    channel_unit,
    clearance_joints,
    effort_channels,
    impact_units,
    slider_channels,
)

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped]

__all__ = [
    "ContactStatistics",
    "clearance_joints",
    "Deviation",
    "contact_statistics",
    "deviation_from_ideal",
    "default_deviation_channels",
    "statistics_table",
    "deviation_table",
    "format_statistics",
    "time_mean",
]

CLEARANCE_TYPE = "clearance_revolute"
FREE_FLIGHT, IMPACT, CONTACT = 0, 1, 2
"""Values of the ``<joint>.mode`` channel (docs/clearance-joints.md, the mode channel)."""


@dataclass(frozen=True)
class ContactStatistics:
    """Contact statistics of one clearance joint over the computed part of a run.

    Counts, forces, penetrations and speeds come from the engine's impact list (exact at
    located onsets, peaks over accepted steps and samples) together with the ``fn`` and
    ``penetration`` channels; the time fractions come from the time the engine summed
    in each mode over the accepted steps (:attr:`jointgap.Result.mode_time`): exact at
    onsets and separations whatever the output rate (a rate of 100 Hz missed every
    impact of the founding case, whose impacts last about 0.1 ms). A result without
    those times (built by hand) falls back on its sampled ``mode`` channel.

    Attributes:
        joint: the clearance joint.
        impacts: number of impacts (contact onsets), from the impact list.
        free_flight: fraction of the sampled time in free flight (mode 0), in [0, 1].
        impact: fraction in impact (mode 1: onset through the first restitution).
        contact: fraction in continuous contact (mode 2). The three sum to 1. Without
            the engine's times each is NaN when the ``mode`` channel was not recorded or
            fewer than two samples exist, and the samples are held: the mode of sample
            ``t_k`` holds over ``[t_k, t_k+1)``.
        peak_force: largest normal contact force [N], over the impacts' peaks and the
            ``fn`` samples; 0 without contact.
        max_penetration: largest penetration [m], over the impacts and the positive
            ``penetration`` samples; 0 without contact.
        onset_speed_mean: mean approach speed at onset [m/s]; NaN without impacts.
        onset_speed_max: largest approach speed at onset [m/s]; NaN without impacts.
        span: time the statistics cover, first to last sample [s].
        complete: False when the run failed, so the statistics stop where it did.
    """

    joint: str
    impacts: int
    free_flight: float
    impact: float
    contact: float
    peak_force: float
    max_penetration: float
    onset_speed_mean: float
    onset_speed_max: float
    span: float
    complete: bool = True

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict for ``summary.json``: NaN as None, so it stays strict JSON."""
        return _json_numbers(asdict(self))


@dataclass(frozen=True)
class Deviation:
    """Difference of one channel between a clearance run and its ideal counterpart,
    ``d(t) = clearance(t) - ideal(t)`` on the clearance run's samples within both runs'
    time spans (the ideal run linearly interpolated there when the grids differ).

    Attributes:
        channel: the channel, e.g. ``slider.ax``.
        rms: root mean square of ``d`` over time [channel unit]: ``d^2`` integrated by
            the trapezoidal rule over the samples and divided by their span, so that
            samples clustered at impacts (every step) weigh by the time they stand for
            (a plain mean over every step read 63.9 % of the ideal range where a uniform
            10 kHz grid gave 27.8 %).
        peak: largest ``|d|`` [channel unit].
        peak_time: time of the largest ``|d|`` [s].
        ideal_range: ``max - min`` of the ideal channel over the same samples.
        rms_relative: ``rms / ideal_range``; NaN when the range is 0.
        peak_relative: ``peak / ideal_range``; NaN when the range is 0.
        samples: number of samples compared.
    """

    channel: str
    rms: float
    peak: float
    peak_time: float
    ideal_range: float
    rms_relative: float
    peak_relative: float
    samples: int

    @property
    def unit(self) -> str:
        """The channel's SI unit."""
        return channel_unit(self.channel)

    def to_dict(self) -> dict[str, Any]:
        """The fields and the unit as a dict for ``summary.json``: NaN as None."""
        return _json_numbers({**asdict(self), "unit": self.unit})


# ---------------------------------------------------------------- contact statistics


def contact_statistics(result: Result) -> list[ContactStatistics]:
    """Statistics of every clearance joint, in model order; empty without clearance
    joints. A failed run gives the statistics of what it computed (``complete=False``)."""
    return [_joint_statistics(result, joint) for joint in clearance_joints(result)]


def _joint_statistics(result: Result, joint: str) -> ContactStatistics:
    impacts = result.impacts.get(joint, [])
    free, impact, contact = _mode_fractions(result, joint)
    speeds = np.array([i.onset_speed for i in impacts], dtype=float)
    forces = [i.peak_force for i in impacts] + _channel_max(result, f"{joint}.fn")
    depths = [i.max_penetration for i in impacts] + _channel_max(result, f"{joint}.penetration")
    return ContactStatistics(
        joint=joint,
        impacts=len(impacts),
        free_flight=free,
        impact=impact,
        contact=contact,
        peak_force=_largest(forces),
        max_penetration=_largest(depths),
        onset_speed_mean=float(np.mean(speeds)) if len(speeds) else math.nan,
        onset_speed_max=float(np.max(speeds)) if len(speeds) else math.nan,
        span=float(result.time[-1] - result.time[0]) if len(result.time) else 0.0,
        complete=result.ok,
    )


def _mode_fractions(result: Result, joint: str) -> tuple[float, float, float]:
    """Fractions of time in modes 0, 1, 2: the engine's times over the steps, or for a
    result without them the sampled mode channel held from sample to sample (NaN
    without the channel or a time interval; samples of another value, NaN, are left out
    of both numerator and denominator, so the three still sum to 1)."""
    times = result.mode_time.get(joint)
    if times is not None:
        total = sum(times)
        if total <= 0.0:
            return math.nan, math.nan, math.nan
        free, impact, contact = (t / total for t in times)
        return free, impact, contact
    channel = f"{joint}.mode"
    if channel not in result or len(result.time) < 2:
        return math.nan, math.nan, math.nan
    mode = result[channel][:-1]
    weight = np.diff(result.time)
    known = np.isin(mode, (FREE_FLIGHT, IMPACT, CONTACT))
    total = float(weight[known].sum())
    if total <= 0.0:
        return math.nan, math.nan, math.nan
    free, impact, contact = (float(weight[mode == m].sum()) / total for m in range(3))
    return free, impact, contact


def _channel_max(result: Result, channel: str) -> list[float]:
    """The largest finite sample of a channel as a one-item list; empty when the
    channel was not recorded (``simulate(channels=...)``) or holds no finite value."""
    if channel not in result:
        return []
    v = result[channel]
    return [float(np.max(v[np.isfinite(v)]))] if np.isfinite(v).any() else []


def _largest(values: Sequence[float]) -> float:
    """Largest finite value, at least 0 (no contact: no force, no penetration)."""
    finite = [v for v in values if math.isfinite(v)]
    return max([0.0, *finite])


# ---------------------------------------------------------------- deviation from ideal


def default_deviation_channels(result: Result) -> list[str]:
    """The channels that show a clearance's effect: the acceleration along the guide of
    every prismatic-guided body (``slider.ax`` in the slider-crank) and every driver's
    torque or force, those recorded in ``result``."""
    accelerations = [c for c in slider_channels(result) if c.split(".")[-1] in ("ax", "ay")]
    return accelerations + effort_channels(result)


def deviation_from_ideal(
    result: Result, ideal: Result, channels: Iterable[str] | None = None
) -> list[Deviation]:
    """How far ``result`` (with clearances) departs from ``ideal`` (the same mechanism
    with ideal joints), per channel.

    Args:
        result: the clearance run.
        ideal: the ideal run; its samples are interpolated onto ``result``'s times when
            the grids differ.
        channels: channels to compare; default :func:`default_deviation_channels` of
            ``result`` that ``ideal`` also has.

    Raises:
        KeyError: a named channel is missing in either run.
        ValueError: the runs share no time span with samples of ``result`` in it.
    """
    if channels is None:
        names = [c for c in default_deviation_channels(result) if c in ideal]
    else:
        names = list(channels)
        for run, label in ((result, "clearance"), (ideal, "ideal")):
            for c in names:
                try:
                    run[c]
                except KeyError as exc:
                    raise KeyError(f"{label} run: {exc.args[0]}") from None
    t = result.time
    start = max(t[0], ideal.time[0]) if len(t) and len(ideal.time) else math.inf
    end = min(t[-1], ideal.time[-1]) if len(t) and len(ideal.time) else -math.inf
    inside = (t >= start) & (t <= end)
    if not inside.any():
        raise ValueError(
            f"the clearance run ({_span(result)}) and the ideal run ({_span(ideal)}) "
            "share no time span"
        )
    same_grid = len(t) == len(ideal.time) and np.array_equal(t, ideal.time)
    return [_deviation(result, ideal, c, inside, same_grid) for c in names]


def _deviation(
    result: Result, ideal: Result, channel: str, inside: np.ndarray, same_grid: bool
) -> Deviation:
    t = result.time[inside]
    ours = result[channel][inside]
    if same_grid:
        theirs = ideal[channel][inside]
    else:
        theirs = np.interp(t, ideal.time, ideal[channel])
    d = ours - theirs
    k = int(np.argmax(np.abs(d)))
    rms = float(np.sqrt(time_mean(t, d**2)))
    peak = float(abs(d[k]))
    span = float(np.max(theirs) - np.min(theirs))
    return Deviation(
        channel=channel,
        rms=rms,
        peak=peak,
        peak_time=float(t[k]),
        ideal_range=span,
        rms_relative=rms / span if span > 0.0 else math.nan,
        peak_relative=peak / span if span > 0.0 else math.nan,
        samples=len(t),
    )


def time_mean(t: np.ndarray, values: np.ndarray) -> float:
    """The mean over time of samples ``values`` at times ``t``: their trapezoidal
    integral divided by the span, each sample weighing half of each interval beside it;
    the plain mean when the samples span no time."""
    if len(t) < 2 or t[-1] <= t[0]:
        return float(np.mean(values))
    dt = np.diff(t)
    return float(np.sum(dt * (values[:-1] + values[1:])) / (2.0 * (t[-1] - t[0])))


def _span(result: Result) -> str:
    return f"t = {result.time[0]:g}..{result.time[-1]:g} s" if len(result.time) else "no samples"


# ---------------------------------------------------------------- tables and text


def statistics_table(stats: Iterable[ContactStatistics]) -> pd.DataFrame:
    """One row per clearance joint, the fields of :class:`ContactStatistics` as columns
    (SI; fractions in [0, 1]); NaN stays NaN, as pandas writes it (empty) in CSV."""
    import pandas as pd

    columns = list(ContactStatistics.__dataclass_fields__)
    return pd.DataFrame([asdict(s) for s in stats], columns=columns)


def deviation_table(deviations: Iterable[Deviation]) -> pd.DataFrame:
    """One row per compared channel, the fields of :class:`Deviation` and ``unit``."""
    import pandas as pd

    columns = [*Deviation.__dataclass_fields__, "unit"]
    return pd.DataFrame([{**asdict(d), "unit": d.unit} for d in deviations], columns=columns)


def format_statistics(
    stats: Iterable[ContactStatistics],
    deviations: Iterable[Deviation] = (),
    model: Mapping[str, Any] | None = None,
) -> str:
    """The lines a run summary prints, one per joint and one per compared channel::

        rod_slider: 21 impacts; free flight 6.7 %, impact 2.4 %, contact 90.9 %; peak force
        3052 N; max penetration 11.35 µm; onset speed mean 0.037 m/s, max 0.175 m/s
        slider.ax vs ideal: RMS 38.12 m/s^2 (24.1 % of ideal range), peak 1091 m/s^2
        (690.7 %) at t = 0.4721 s

    (each on one line); empty text when there is nothing to say. With the model (SI
    dictionary), a joint's values are in its kind's units
    (:func:`jointgap.results.impact_units`: a revolute joint's play in N*m, µrad and
    rad/s).
    """
    lines = [_contact_line(s, model) for s in stats]
    return "\n".join([*lines, *map(_deviation_line, deviations)])


def _contact_line(s: ContactStatistics, model: Mapping[str, Any] | None = None) -> str:
    units = impact_units(model or {}, s.joint)
    force, depth, speed = units["peak_force"], units["max_penetration"], units["onset_speed"]
    parts = [f"{s.joint}: {s.impacts} impact{'' if s.impacts == 1 else 's'}"]
    if math.isnan(s.free_flight):
        parts.append("time fractions unknown (no mode channel)")
    else:
        parts.append(
            f"free flight {_percent(s.free_flight)}, impact {_percent(s.impact)}, "
            f"contact {_percent(s.contact)}"
        )
    parts += [
        f"peak force {s.peak_force:.4g} {force}",
        f"max penetration {s.max_penetration * 1e6:.4g} µ{depth}",
    ]
    if s.impacts:
        parts.append(
            f"onset speed mean {s.onset_speed_mean:.3g} {speed}, "
            f"max {s.onset_speed_max:.3g} {speed}"
        )
    line = "; ".join(parts)
    return line if s.complete else f"{line} (run failed: first {s.span:g} s only)"


def _deviation_line(d: Deviation) -> str:
    unit = f" {d.unit}" if d.unit else ""
    return (
        f"{d.channel} vs ideal: RMS {d.rms:.4g}{unit} ({_percent(d.rms_relative)} of ideal "
        f"range), peak {d.peak:.4g}{unit} ({_percent(d.peak_relative)}) at t = {d.peak_time:.4g} s"
    )


def _percent(fraction: float) -> str:
    return "- %" if math.isnan(fraction) else f"{100.0 * fraction:.1f} %"


def _json_numbers(d: dict[str, Any]) -> dict[str, Any]:
    """Non-finite floats as None: strict JSON, and 'not defined' reads as null."""
    return {k: None if isinstance(v, float) and not math.isfinite(v) else v for k, v in d.items()}
