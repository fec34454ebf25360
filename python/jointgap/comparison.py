"""Simulation against measurement: conditioning, alignment and error measures.

A measured signal is any object with ``.time`` [s], ``.values`` (SI), ``.name`` and
``.unit`` (:class:`MeasuredSignal`). :func:`compare` puts one simulated channel and one
measured signal on a common time base and measures how far apart they are::

    c = compare(result, measured, "slider.ax", lowpass=1000.0)
    print(c.report())

The steps, each a public function of its own (formulas in docs/comparison.md):

* conditioning: :func:`lowpass` (zero-phase Butterworth), :func:`remove_offset`,
  :func:`resample`;
* alignment: :func:`estimate_lag` (normalized cross-correlation, parabolic refinement),
  or :func:`align_on_angle` (both signals against the crank angle);
* measures: :func:`error_measures` (max absolute, max percent of the measured peak, RMS,
  NRMSE, correlation), :func:`compare_spectra` (amplitude spectra and a spectral error),
  :func:`cycle_table` (peak-to-peak per crank turn).

Its figure (signals overlaid, their difference, their spectra) is drawn with the other
figures: :func:`jointgap.plots.comparison_figure`.

Lag convention: ``measured(t) = simulated(t - lag)``; a positive lag means the
measurement is late. The comparison's time base is the simulation's time: the measured
samples at ``t_m`` are compared with the simulation at ``t_m - lag``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any, Protocol

import numpy as np
from scipy.signal import butter, correlate, sosfiltfilt  # type: ignore[import-untyped]

from . import units
from .errors import ComparisonWarning
from .results import Result, channel_unit

__all__ = [
    "ComparisonWarning",
    "MeasuredSignal",
    "ErrorMeasures",
    "Spectra",
    "CycleRow",
    "AngleAlignment",
    "Comparison",
    "lowpass",
    "remove_offset",
    "resample",
    "estimate_lag",
    "align_on_angle",
    "crank_channel",
    "error_measures",
    "amplitude_spectrum",
    "compare_spectra",
    "cycle_table",
    "cycle_lines",
    "compare",
]

LOWPASS_ORDER = 4
"""Order of the Butterworth filter of :func:`lowpass` (applied forward and backward)."""
MIN_SAMPLES = 8
"""Fewest common samples a comparison or a lag estimate accepts."""
CYCLE_LINES = 12
"""Most crank turns :meth:`Comparison.report` lists one by one; beyond, it summarises
them and lists the :data:`WORST_CYCLES` that differ most (60 s are 300 turns)."""
WORST_CYCLES = 5
_UNIFORM_TOLERANCE = 0.05  # largest deviation from a uniform grid, in sample steps
_TURN = 2.0 * math.pi


class MeasuredSignal(Protocol):
    """What :func:`compare` needs of a measured signal (read-only attributes)."""

    @property
    def time(self) -> np.ndarray:
        """Sample times [s], increasing."""
        ...

    @property
    def values(self) -> np.ndarray:
        """Samples, SI units."""
        ...

    @property
    def name(self) -> str:
        """What was measured, e.g. ``"accelerometer"``."""
        ...

    @property
    def unit(self) -> str:
        """SI unit of the values, e.g. ``"m/s^2"``."""
        ...


# ------------------------------------------------------------------ checks


def _array(values: Any, what: str) -> np.ndarray:
    out = np.asarray(values, dtype=float)
    if out.ndim != 1:
        raise ValueError(f"{what}: expected a 1-D array, got shape {out.shape}")
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{what}: contains NaN or infinite values")
    return out


def _series(time: Any, values: Any, what: str) -> tuple[np.ndarray, np.ndarray]:
    """Time and values as float arrays of equal length, time strictly increasing."""
    t = _array(time, f"{what} time")
    v = _array(values, f"{what} values")
    if len(t) != len(v):
        raise ValueError(f"{what}: {len(t)} times for {len(v)} values")
    if len(t) < 2:
        raise ValueError(f"{what}: needs at least 2 samples, got {len(t)}")
    if np.any(np.diff(t) <= 0.0):
        raise ValueError(f"{what}: time must increase strictly")
    return t, v


def _uniform_step(time: np.ndarray, what: str) -> float:
    """The sample step [s] of a uniformly sampled time array; ValueError otherwise."""
    dt = float(time[-1] - time[0]) / (len(time) - 1)
    grid = time[0] + dt * np.arange(len(time))
    if float(np.max(np.abs(time - grid))) > _UNIFORM_TOLERANCE * dt:
        raise ValueError(f"{what} is not sampled uniformly; resample() it onto a uniform grid")
    return dt


# ------------------------------------------------------------------ conditioning


def lowpass(time: Any, values: Any, cutoff: float, *, order: int = LOWPASS_ORDER) -> np.ndarray:
    """Zero-phase low-pass filter: a Butterworth filter of ``order`` (second-order
    sections) run forward and backward (``scipy.signal.sosfiltfilt``), so no delay and
    an attenuation of 1/2 (-6 dB) at ``cutoff``.

    Args:
        time: uniform sample times [s].
        values: the samples.
        cutoff: cut-off frequency [Hz], below the Nyquist frequency 1 / (2 dt).
        order: filter order of one pass (default 4).

    Raises:
        ValueError: time not uniform, cutoff not in (0, Nyquist), or too few samples.
    """
    t, v = _series(time, values, "lowpass")
    nyquist = 0.5 / _uniform_step(t, "lowpass: the signal")
    if not 0.0 < cutoff < nyquist:
        raise ValueError(
            f"lowpass: cutoff {cutoff:g} Hz must lie between 0 and the Nyquist frequency "
            f"{nyquist:g} Hz"
        )
    sos = butter(order, cutoff / nyquist, output="sos")
    pad = 3 * (2 * len(sos) + 1)
    if len(v) <= pad:
        raise ValueError(f"lowpass: needs more than {pad} samples, got {len(v)}")
    out: np.ndarray = sosfiltfilt(sos, v)
    return out


_lowpass = lowpass  # for compare(), whose argument of that name hides the function


def remove_offset(values: Any, offset: str | float = "mean") -> np.ndarray:
    """``values - mean(values)`` for ``offset="mean"``, else ``values - offset``."""
    v = _array(values, "remove_offset")
    if isinstance(offset, str):
        if offset != "mean":
            raise ValueError(f"remove_offset: offset {offset!r}: give 'mean' or a number")
        return v - float(np.mean(v))
    return v - float(offset)


def resample(time: Any, values: Any, new_time: Any) -> np.ndarray:
    """The signal linearly interpolated at ``new_time`` [s].

    Raises:
        ValueError: a new time lies outside ``[time[0], time[-1]]`` (by more than 1e-9
            of the span: rounding).
    """
    t, v = _series(time, values, "resample")
    nt = _array(new_time, "resample new_time")
    eps = 1e-9 * float(t[-1] - t[0])
    if len(nt) and (nt.min() < t[0] - eps or nt.max() > t[-1] + eps):
        raise ValueError(
            f"resample: new times {nt.min():g}..{nt.max():g} s leave the signal's range "
            f"{t[0]:g}..{t[-1]:g} s"
        )
    out: np.ndarray = np.interp(nt, t, v)
    return out


# ------------------------------------------------------------------ alignment


def _correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Pearson's correlation coefficient; NaN when either signal is constant."""
    da, db = a - a.mean(), b - b.mean()
    norm = math.sqrt(float(np.dot(da, da)) * float(np.dot(db, db)))
    return float(np.dot(da, db)) / norm if norm > 0.0 else math.nan


def estimate_lag(
    sim_time: Any,
    sim_values: Any,
    meas_time: Any,
    meas_values: Any,
    *,
    max_lag: float = 0.05,
) -> float:
    """The lag [s] of the measurement behind the simulation, ``measured(t) =
    simulated(t - lag)``, by normalized cross-correlation.

    The simulation is interpolated (linearly) onto the measurement's uniform time grid
    extended by ``max_lag`` on both sides; for each whole-sample shift ``L`` with ``|L dt|
    <= max_lag`` (and one more each side) the correlation coefficient of the measured
    samples and the simulation at ``t - L dt`` is taken over the samples where both
    exist. A parabola through the largest coefficient and its two neighbours places the
    peak between samples. The sums of every shift's coefficient come from six
    cross-correlations by FFT (:func:`_shifted_correlations`): a 60 s record at 5 kHz
    takes under a second, where a coefficient per shift took 12 s on a loaded machine.

    Raises:
        ValueError: the measurement is not uniform, too few common samples, or the peak
            lies at or beyond ``max_lag`` (raise ``max_lag``).
    """
    ts, vs = _series(sim_time, sim_values, "simulation")
    tm, vm = _series(meas_time, meas_values, "measurement")
    if not max_lag >= 0.0:
        raise ValueError(f"max_lag {max_lag:g} s must not be negative")
    dt = _uniform_step(tm, "the measurement")
    k = int(math.floor(max_lag / dt + 1e-9)) + 1  # shifts -k..k; the outer two are guards
    n = len(tm)
    grid = tm[0] + dt * np.arange(-k, n + k)
    eps = 1e-9 * float(ts[-1] - ts[0])
    inside = (grid >= ts[0] - eps) & (grid <= ts[-1] + eps)
    sim_grid = np.where(inside, np.interp(grid, ts, vs), np.nan)
    shifts = np.arange(-k, k + 1)
    r = _shifted_correlations(sim_grid, vm)
    if not np.any(np.isfinite(r)):
        raise ValueError(
            f"estimate_lag: the measurement ({tm[0]:g}..{tm[-1]:g} s) and the simulation "
            f"({ts[0]:g}..{ts[-1]:g} s) share fewer than {MIN_SAMPLES} samples at every lag "
            f"within ±{max_lag:g} s, or a signal is constant"
        )
    best = int(np.argmax(r))
    if best in (0, len(shifts) - 1):
        raise ValueError(
            f"estimate_lag: the correlation peaks at the edge of the search, lag "
            f"{shifts[best] * dt:+.4g} s; raise max_lag (now {max_lag:g} s)"
        )
    lo, mid, hi = r[best - 1], r[best], r[best + 1]
    curvature = lo - 2.0 * mid + hi
    delta = 0.5 * (lo - hi) / curvature if np.isfinite(curvature) and curvature < 0 else 0.0
    return float((shifts[best] + delta) * dt)


_CONSTANT = 1e-10
"""A window whose variance is below this fraction of its mean square (rounding of the
FFT sums) holds a constant signal: no correlation there."""


def _shifted_correlations(sim_grid: np.ndarray, measured: np.ndarray) -> np.ndarray:
    """Pearson's correlation coefficient of ``measured`` (N samples) with each window
    ``sim_grid[j : j + N]`` of the longer simulation (NaN where it does not exist), over
    the samples where both exist, for the shifts ``L = K - j``, ``-K..K`` in that order;
    -inf where fewer than :data:`MIN_SAMPLES` samples overlap or a signal is constant.

    Each coefficient is ``(S_sm - S_s S_m / n) / sqrt((S_ss - S_s^2 / n) (S_mm - S_m^2 /
    n))`` over the window's n valid samples; the six sums of all windows at once are
    cross-correlations (``scipy.signal.correlate``, by FFT) of the simulation, its square
    and its validity mask with the measurement, its square and ones. Both signals are
    centred on their means first, so the sums cancel no large offset."""
    valid = np.isfinite(sim_grid)
    s = np.where(valid, sim_grid, 0.0)
    if valid.any():
        s[valid] -= float(np.mean(s[valid]))
    m = measured - float(np.mean(measured))
    w = valid.astype(float)
    ones = np.ones(len(m))

    def windows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        out: np.ndarray = correlate(a, b, mode="valid", method="fft")[::-1]
        return out

    count = np.rint(windows(w, ones))
    s_s, s_ss = windows(s, ones), windows(s * s, ones)
    s_m, s_mm = windows(w, m), windows(w, m * m)
    s_sm = windows(s, m)
    with np.errstate(divide="ignore", invalid="ignore"):
        var_s = s_ss - s_s * s_s / count
        var_m = s_mm - s_m * s_m / count
        r = (s_sm - s_s * s_m / count) / np.sqrt(var_s * var_m)
    varied = (var_s > _CONSTANT * s_ss) & (var_m > _CONSTANT * s_mm)
    ok = (count >= MIN_SAMPLES) & varied & np.isfinite(r)
    out: np.ndarray = np.where(ok, r, -np.inf)
    return out


@dataclass(frozen=True, eq=False)
class AngleAlignment:
    """Simulated and measured signals against the crank angle (:func:`align_on_angle`).

    Attributes:
        angle: the crank angles compared [rad] (the measured samples', or a uniform grid),
            increasing in the direction of rotation.
        simulated: the simulated channel at each angle.
        measured: the measured signal at each angle.
        crank: the simulated crank-angle channel used.
    """

    angle: np.ndarray
    simulated: np.ndarray
    measured: np.ndarray
    crank: str


def _increasing(angle: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The samples where the angle exceeds every earlier one (the crank at rest or
    jittering back is dropped), so that the angle increases strictly."""
    before = np.concatenate(([-np.inf], np.maximum.accumulate(angle)[:-1]))
    keep = angle > before
    return angle[keep], values[keep]


def align_on_angle(
    result: Result,
    measured: MeasuredSignal,
    channel: str,
    crank_angle: MeasuredSignal,
    *,
    crank: str | None = None,
    step: float | None = None,
    initial_angle: float = 0.0,
) -> AngleAlignment:
    """Both signals against the crank angle, which removes a lag and a drift of the
    speed controller alike.

    The measurement's crank angle is ``crank_angle`` interpolated at the measured sample
    times; the simulation's is its crank channel (:func:`crank_channel`). By default the
    comparison points are the measured samples, at their angles, with the simulation
    interpolated (linearly) there; with ``step``, both signals are interpolated onto a
    uniform angle grid. Either way only the angles both signals reach are kept.

    Args:
        result: the simulation.
        measured: the measured signal.
        channel: the simulated channel it measures, e.g. ``"slider.ax"``.
        crank_angle: the measured crank angle [rad] (unit ``"rad"``), or the measured
            crank speed [rad/s] (unit ``"rad/s"``), integrated (trapezoidal rule) from
            ``initial_angle``. Its zero must be the model's (crank angle 0 at the
            simulation's angle 0).
        crank: the simulated crank-angle channel; default :func:`crank_channel`.
        step: the step [rad] of a uniform angle grid; default: the measured samples.
        initial_angle: the crank angle [rad] at the first sample of a measured speed.

    Raises:
        KeyError: a channel is missing (close matches listed).
        ValueError: no crank channel, an unknown crank unit, or the angle ranges do not
            overlap.
    """
    crank = crank or crank_channel(result)
    if crank is None:
        raise ValueError("align_on_angle: the model has no driven revolute joint; give crank=")
    sim_values, sim_angle = result[channel], result[crank]
    tm, vm = _series(measured.time, measured.values, f"measured '{measured.name}'")
    tc, vc = _series(crank_angle.time, crank_angle.values, f"measured '{crank_angle.name}'")
    unit = crank_angle.unit.replace(" ", "")
    if unit == "rad/s":
        vc = initial_angle + np.concatenate(
            ([0.0], np.cumsum(0.5 * (vc[1:] + vc[:-1]) * np.diff(tc)))
        )
    elif unit != "rad":
        raise ValueError(
            f"align_on_angle: crank signal unit {crank_angle.unit!r}: need rad or rad/s"
        )
    meas_angle = resample(tc, vc, tm)
    sign = 1.0 if sim_angle[-1] >= sim_angle[0] else -1.0
    sa, sv = _increasing(sign * sim_angle, sim_values)
    ma, mv = _increasing(sign * meas_angle, vm)
    lo, hi = max(sa[0], ma[0]), min(sa[-1], ma[-1])
    if not hi > lo:
        raise ValueError(
            f"align_on_angle: crank angles do not overlap: simulated {sa[0]:g}..{sa[-1]:g} rad, "
            f"measured {ma[0]:g}..{ma[-1]:g} rad"
        )
    if step is None:
        # The measured samples' own angles: only the simulation is interpolated, so a
        # sharp measured peak keeps its height.
        inside = (ma >= lo) & (ma <= hi)
        return AngleAlignment(sign * ma[inside], np.interp(ma[inside], sa, sv), mv[inside], crank)
    if not step > 0.0:
        raise ValueError(f"align_on_angle: step {step:g} rad must be positive")
    grid = lo + step * np.arange(int(math.floor((hi - lo) / step * (1 + 1e-12))) + 1)
    return AngleAlignment(sign * grid, np.interp(grid, sa, sv), np.interp(grid, ma, mv), crank)


def crank_channel(result: Result) -> str | None:
    """The simulated crank angle: ``<body>.angle`` of the first driver on a revolute
    joint, the body being the joint's ``body_j`` (``body_i`` when that is the ground);
    None when there is no such driver or channel."""
    joints = {str(j.get("name")): j for j in result.model.get("joints", [])}
    for driver in result.model.get("drivers", []):
        joint = joints.get(str(driver.get("joint")))
        if joint is None or "revolute" not in str(joint.get("type", "")):
            continue
        body = joint.get("body_j")
        if body in (None, "ground"):
            body = joint.get("body_i")
        channel = f"{body}.angle"
        if channel in result:
            return channel
    return None


# ------------------------------------------------------------------ measures


@dataclass(frozen=True)
class ErrorMeasures:
    """Scalar error measures of a simulated signal s against a measured one m, sampled
    at the same N instants (formulas in docs/comparison.md).

    Attributes:
        max_abs: max |s - m| [unit of the signal].
        max_percent: 100 max |s - m| / max |m| [%], the error as a percentage of the
            measured peak (the paper's "max percentage error" under this definition).
        rms: sqrt(mean((s - m)^2)) [unit].
        nrmse: rms / (max m - min m), as a fraction of the measured range [-].
        correlation: Pearson's correlation coefficient of s and m [-].
        measured_peak: max |m| [unit].
        samples: N.
    """

    max_abs: float
    max_percent: float
    rms: float
    nrmse: float
    correlation: float
    measured_peak: float
    samples: int


def error_measures(simulated: Any, measured: Any) -> ErrorMeasures:
    """The :class:`ErrorMeasures` of two equally long arrays; a measure whose
    denominator is zero (measured signal zero or constant) is NaN."""
    s = _array(simulated, "simulated")
    m = _array(measured, "measured")
    if len(s) != len(m) or len(s) == 0:
        raise ValueError(f"error_measures: {len(s)} simulated and {len(m)} measured samples")
    e = s - m
    max_abs = float(np.max(np.abs(e)))
    peak = float(np.max(np.abs(m)))
    rms = math.sqrt(float(np.mean(e * e)))
    span = float(np.max(m) - np.min(m))
    return ErrorMeasures(
        max_abs=max_abs,
        max_percent=100.0 * max_abs / peak if peak > 0.0 else math.nan,
        rms=rms,
        nrmse=rms / span if span > 0.0 else math.nan,
        correlation=_correlation(s, m) if len(s) > 1 else math.nan,
        measured_peak=peak,
        samples=len(s),
    )


def amplitude_spectrum(values: Any, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """One-sided amplitude spectrum of a uniformly sampled signal: frequencies [Hz] and
    amplitudes [unit of the signal]. The mean is removed, a Hann window w applied, and
    ``A_k = 2 |X_k| / sum(w)`` (``|X_k| / sum(w)`` at 0 Hz and at the Nyquist
    frequency), so a sine of amplitude a on a bin reads a."""
    v = _array(values, "amplitude_spectrum")
    w = np.hanning(len(v))
    spectrum = np.abs(np.fft.rfft((v - v.mean()) * w)) / float(np.sum(w))
    spectrum[1 : len(v) - len(v) // 2] *= 2.0  # every bin but 0 Hz and the Nyquist bin
    return np.fft.rfftfreq(len(v), 1.0 / rate), spectrum


@dataclass(frozen=True, eq=False)
class Spectra:
    """Amplitude spectra of the aligned signals (:func:`compare_spectra`).

    Attributes:
        frequency: bin frequencies from 0 to f_max [Hz].
        simulated: amplitude of the simulation in each bin [unit].
        measured: amplitude of the measurement in each bin [unit].
        f_max: the highest frequency compared [Hz].
        error: sqrt(sum (A_s - A_m)^2) / sqrt(sum A_m^2) over the bins 0 < f <= f_max,
            the RMS difference of the spectra relative to the measured spectrum's RMS [-].
    """

    frequency: np.ndarray
    simulated: np.ndarray
    measured: np.ndarray
    f_max: float
    error: float


def compare_spectra(
    simulated: Any, measured: Any, rate: float, f_max: float | None = None
) -> Spectra:
    """The :func:`amplitude_spectrum` of both (same length and ``rate`` [Hz]) up to
    ``f_max`` [Hz] (default and at most the Nyquist frequency), and their spectral
    error."""
    f, a_s = amplitude_spectrum(simulated, rate)
    _, a_m = amplitude_spectrum(measured, rate)
    nyquist = 0.5 * rate
    if f_max is not None and not f_max > 0.0:
        raise ValueError(f"spectrum_max {f_max:g} Hz must be positive")
    top = nyquist if f_max is None else min(float(f_max), nyquist)
    keep = f <= top * (1.0 + 1e-12)
    f, a_s, a_m = f[keep], a_s[keep], a_m[keep]
    ref = math.sqrt(float(np.sum(a_m[1:] ** 2)))
    diff = math.sqrt(float(np.sum((a_s[1:] - a_m[1:]) ** 2)))
    return Spectra(f, a_s, a_m, top, diff / ref if ref > 0.0 else math.nan)


@dataclass(frozen=True)
class CycleRow:
    """Peak-to-peak values over one crank turn (:func:`cycle_table`).

    Attributes:
        cycle: the turn's number n: the crank goes from 2 pi n to 2 pi (n + 1) (counted
            in the direction of rotation).
        start: time the crank angle passes 2 pi n [s] (simulation time).
        end: time it passes 2 pi (n + 1) [s].
        simulated: max s - min s over the samples in [start, end] [unit].
        measured: max m - min m over the same samples [unit].
        relative_difference: (simulated - measured) / measured [-]; NaN for measured 0.
    """

    cycle: int
    start: float
    end: float
    simulated: float
    measured: float
    relative_difference: float


def _passages(time: np.ndarray, angle: np.ndarray) -> list[tuple[int, float]]:
    """(n, t): the first time the angle reaches 2 pi n (in the direction of rotation,
    the angle's overall sense), for each whole n in its range."""
    sign = 1.0 if angle[-1] >= angle[0] else -1.0
    q = sign * angle / _TURN
    nearest = np.round(q)
    q = np.where(np.abs(q - nearest) < 1e-9, nearest, q)  # exact multiples, up to rounding
    reached = np.maximum.accumulate(q)
    out = []
    for n in range(int(math.ceil(q.min())), int(math.floor(reached[-1])) + 1):
        j = int(np.argmax(reached >= n))
        if j == 0 or q[j] == n:
            t = float(time[j])
        else:
            t = float(time[j - 1] + (n - q[j - 1]) / (q[j] - q[j - 1]) * (time[j] - time[j - 1]))
        out.append((n, t))
    return out


def cycle_table(
    time: Any,
    simulated: Any,
    measured: Any,
    crank_time: Any,
    crank_angle: Any,
) -> list[CycleRow]:
    """Peak-to-peak values of both signals per complete crank turn.

    Turns start and end where the crank angle passes a multiple of 2 pi, located by
    linear interpolation of ``crank_angle`` against ``crank_time`` (the simulation's
    crank channel); only turns wholly inside ``[time[0], time[-1]]`` count.

    Args:
        time: the common time base [s] of ``simulated`` and ``measured``.
        simulated, measured: the aligned signals.
        crank_time, crank_angle: the crank angle [rad] against time [s].
    """
    t, s = _series(time, simulated, "cycle_table simulated")
    m = _array(measured, "cycle_table measured")
    ct, ca = _series(crank_time, crank_angle, "crank angle")
    t0, t1 = float(t[0]), float(t[-1])
    inside = (ct > t0) & (ct < t1)
    if t0 < ct[0] or t1 > ct[-1]:
        raise ValueError("cycle_table: the crank angle does not cover the compared interval")
    edge_time = np.concatenate(([t0], ct[inside], [t1]))
    edge_angle = np.concatenate(([np.interp(t0, ct, ca)], ca[inside], [np.interp(t1, ct, ca)]))
    passages = _passages(edge_time, edge_angle)
    rows = []
    for (n, start), (_, end) in zip(passages, passages[1:], strict=False):
        span = (t >= start - 1e-12) & (t <= end + 1e-12)
        if not span.any():
            continue
        p2p_s = float(np.ptp(s[span]))
        p2p_m = float(np.ptp(m[span]))
        rel = (p2p_s - p2p_m) / p2p_m if p2p_m > 0.0 else math.nan
        rows.append(CycleRow(n, start, end, p2p_s, p2p_m, rel))
    return rows


# ------------------------------------------------------------------ compare


@dataclass(frozen=True, eq=False)
class Comparison:
    """A simulated channel against a measured signal, aligned (:func:`compare`).

    Attributes:
        channel: the simulated channel, e.g. ``"slider.ax"``.
        measured_name: the measured signal's name.
        unit: SI unit of both signals.
        lag: the measurement's lag behind the simulation [s], ``measured(t) =
            simulated(t - lag)``.
        lag_estimated: True when :func:`estimate_lag` found the lag.
        max_lag: the lag search range [s] (±).
        lowpass: the low-pass cut-off applied to both signals [Hz], or None.
        offset: the offset rule: ``"mean"`` (each signal's mean removed), a number
            (subtracted from the measurement) or None.
        simulated_offset: the value subtracted from the simulation [unit].
        measured_offset: the value subtracted from the measurement [unit].
        time: the common time base [s], simulation time (measured sample times - lag).
        rate: the sample rate of the time base [Hz] (the measurement's).
        simulated: the simulation at ``time``, conditioned.
        measured: the measurement at ``time``, conditioned.
        difference: ``simulated - measured``.
        measures: the scalar error measures.
        spectra: the amplitude spectra and the spectral error.
        crank: the crank-angle channel that delimits cycles, or None.
        cycles: peak-to-peak values per complete crank turn.
    """

    channel: str
    measured_name: str
    unit: str
    lag: float
    lag_estimated: bool
    max_lag: float
    lowpass: float | None
    offset: str | float | None
    simulated_offset: float
    measured_offset: float
    time: np.ndarray
    rate: float
    simulated: np.ndarray
    measured: np.ndarray
    difference: np.ndarray
    measures: ErrorMeasures
    spectra: Spectra
    crank: str | None
    cycles: tuple[CycleRow, ...]

    def report(self) -> str:
        """The comparison as printed lines: the lag in ms, then each measure with its
        unit, then the peak-to-peak table."""
        u = self.unit or "-"
        m = self.measures
        how = f"estimated within ±{1e3 * self.max_lag:g} ms" if self.lag_estimated else "given"
        lines = [
            f"{self.channel} against measured '{self.measured_name}' [{u}]: {m.samples} "
            f"samples at {self.rate:g} Hz, t = {self.time[0]:.4g}..{self.time[-1]:.4g} s "
            "(simulation time)",
            f"lag: {1e3 * self.lag:.3f} ms ({how}; measured(t) = simulated(t - lag))",
            f"conditioning: {self._conditioning()}",
            f"max absolute error: {m.max_abs:.4g} {u}",
            f"max error / measured peak ({m.measured_peak:.4g} {u}): {m.max_percent:.2f} %",
            f"RMS error: {m.rms:.4g} {u}",
            f"NRMSE (RMS / measured range): {100.0 * m.nrmse:.2f} %",
            f"correlation: {m.correlation:.4f}",
            f"spectral error (0..{self.spectra.f_max:g} Hz): {100.0 * self.spectra.error:.2f} %",
        ]
        return "\n".join(lines + cycle_lines(self.cycles, self.crank, u))

    def _conditioning(self) -> str:
        parts = []
        if self.lowpass is not None:
            parts.append(f"low-pass {self.lowpass:g} Hz (Butterworth {LOWPASS_ORDER}, zero phase)")
        if self.offset == "mean":
            parts.append(
                f"means removed (simulated {self.simulated_offset:.4g}, measured "
                f"{self.measured_offset:.4g} {self.unit})"
            )
        elif self.offset is not None:
            parts.append(
                f"offset {self.measured_offset:.4g} {self.unit} removed from the measurement"
            )
        return ", ".join(parts) if parts else "none"

    def to_dict(self, arrays: bool = False) -> dict[str, Any]:
        """The settings, lag, measures and cycle table (SI; ``nrmse``, ``spectral_error``
        and ``relative_difference`` as fractions); with ``arrays``, also the time base,
        both signals and the spectra. Strict JSON: NaN and infinities become None."""
        out: dict[str, Any] = {
            "channel": self.channel,
            "measured": self.measured_name,
            "unit": self.unit,
            "lag": self.lag,
            "lag_estimated": self.lag_estimated,
            "max_lag": self.max_lag,
            "lowpass": self.lowpass,
            "offset": self.offset,
            "simulated_offset": self.simulated_offset,
            "measured_offset": self.measured_offset,
            "start": float(self.time[0]),
            "end": float(self.time[-1]),
            "rate": self.rate,
            "measures": {**asdict(self.measures), "spectral_error": self.spectra.error},
            "spectrum_max": self.spectra.f_max,
            "crank": self.crank,
            "cycles": [asdict(c) for c in self.cycles],
        }
        if arrays:
            out["time"] = self.time.tolist()
            out["simulated"] = self.simulated.tolist()
            out["measured_values"] = self.measured.tolist()
            out["spectra"] = {
                "frequency": self.spectra.frequency.tolist(),
                "simulated": self.spectra.simulated.tolist(),
                "measured": self.spectra.measured.tolist(),
            }
        result: dict[str, Any] = _strict(out)
        return result


def _strict(value: Any) -> Any:
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {k: _strict(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_strict(v) for v in value]
    return value


def _same_unit(a: str, b: str) -> bool:
    def norm(u: str) -> str:
        return u.replace(" ", "").replace("**", "^").replace("·", "*")

    return not a or not b or norm(a) == norm(b)


def _dimensions(unit: str) -> set[units.Dimension]:
    """The quantities a unit can be (two for the ambiguous ``g``); none when it is empty
    or not a unit the reader knows."""
    try:
        return {dim for _, dim in units.parse_unit(unit)} if unit.strip() else set()
    except units.UnitError:
        return set()


def _check_units(channel: str, measured: MeasuredSignal) -> None:
    """A measured signal of another quantity than the channel is an error naming both
    units; the same quantity in another unit than the channel's SI one is compared as
    it is, with a warning."""
    sim_unit = channel_unit(channel)
    sim, meas = _dimensions(sim_unit), _dimensions(measured.unit)
    if sim and meas and not sim & meas:
        raise ValueError(
            f"compare: {channel} is {next(iter(sim)).noun()}, measured '{measured.name}' is "
            f"{' or '.join(sorted(d.noun() for d in meas))}: they are different quantities; "
            "give the measured column's unit (--unit, unit=) or compare it with a channel of "
            "its kind"
        )
    if not _same_unit(sim_unit, measured.unit):
        warnings.warn(
            f"compare: {channel} is in {sim_unit}, measured '{measured.name}' in "
            f"{measured.unit}; the values are compared as they are",
            ComparisonWarning,
            stacklevel=3,
        )


def _check_record_length(time: np.ndarray, max_lag: float, name: str) -> None:
    """A warning when the record is shorter than the lag search window (2 max_lag): the
    correlation then rests on the record's ends and may peak at a wrong lag."""
    span = float(time[-1] - time[0])
    if span < 2.0 * max_lag:
        warnings.warn(
            f"compare: measured '{name}' lasts {span:.4g} s, shorter than the lag search "
            f"window of ±{max_lag:g} s ({2.0 * max_lag:g} s): the lag estimate may lock onto "
            "a wrong one; give the lag (--lag), a smaller search (--max-lag), or a longer "
            "record",
            ComparisonWarning,
            stacklevel=3,
        )


def cycle_lines(cycles: Sequence[CycleRow], crank: str | None, unit: str) -> list[str]:
    """The peak-to-peak table of :meth:`Comparison.report`: one line per crank turn up to
    :data:`CYCLE_LINES` turns; beyond, their spread and the :data:`WORST_CYCLES` turns
    that differ most."""
    if not cycles:
        return ["peak-to-peak per crank turn: no complete turn in the interval"]
    rows = list(cycles)
    lines = []
    if len(rows) > CYCLE_LINES:
        # A long run has hundreds of turns: their spread, then the worst ones.
        diffs = np.array([c.relative_difference for c in rows])
        finite = diffs[np.isfinite(diffs)]
        spread = (
            f"mean {100.0 * finite.mean():+.2f} %, RMS {100.0 * np.sqrt(np.mean(finite**2)):.2f}"
            f" %, from {100.0 * finite.min():+.2f} to {100.0 * finite.max():+.2f} %"
            if len(finite)
            else "undefined (measured peak-to-peak 0)"
        )
        lines.append(
            f"peak-to-peak per crank turn ({crank}): {len(rows)} turns, difference {spread}"
        )
        worst = np.argsort(-np.abs(np.where(np.isfinite(diffs), diffs, -np.inf)))
        rows = [rows[k] for k in sorted(worst[:WORST_CYCLES])]
        lines.append(
            f"the {len(rows)} turns that differ most (every turn: 'cycles' of comparison.json, "
            f"Comparison.cycles), [{unit}]:"
        )
    else:
        lines.append(f"peak-to-peak per crank turn ({crank}), [{unit}]:")
    lines.append("  turn  start [s]    end [s]   simulated    measured  difference")
    for c in rows:
        lines.append(
            f"  {c.cycle:4d} {c.start:10.4f} {c.end:10.4f} {c.simulated:11.4g} "
            f"{c.measured:11.4g} {100.0 * c.relative_difference:9.2f} %"
        )
    return lines


def compare(
    result: Result,
    measured: MeasuredSignal,
    channel: str,
    *,
    lag: float | None = None,
    max_lag: float = 0.05,
    lowpass: float | None = None,
    offset: str | float | None = "mean",
    spectrum_max: float | None = None,
    crank: str | None = None,
) -> Comparison:
    """A simulated channel against a measured signal, aligned, with every error measure.

    Steps: (1) with ``lowpass``, both signals are filtered on their own time bases
    (:func:`lowpass`); (2) the lag is estimated (:func:`estimate_lag`) unless given;
    (3) the common time base is the measured sample times less the lag that fall in the
    simulated interval, where the simulation is interpolated linearly; (4) offsets are
    removed; (5) :func:`error_measures`, :func:`compare_spectra`, :func:`cycle_table`.

    Args:
        result: the simulation.
        measured: the measured signal, uniformly sampled, SI (:class:`MeasuredSignal`).
        channel: the simulated channel it measures, e.g. ``"slider.ax"``.
        lag: the measurement's lag [s] (``measured(t) = simulated(t - lag)``); None:
            estimated.
        max_lag: the estimate's search range, ± [s] (default 0.05).
        lowpass: a cut-off [Hz] applied to both signals (zero phase), below the
            measurement's Nyquist frequency; None: no filter. Without it the simulation
            is sampled at the measured instants with no anti-aliasing.
        offset: ``"mean"`` removes each signal's mean over the common interval (an
            accelerometer's bias and the simulation's mean alike); a number [SI] is
            subtracted from the measurement only (a known bias); None removes nothing.
        spectrum_max: the highest frequency of the spectra [Hz]; default the Nyquist
            frequency of the measurement.
        crank: the crank-angle channel for the cycle table; default
            :func:`crank_channel` (no table when there is none).

    Warns (:class:`ComparisonWarning`) when the measured unit is another unit of the
    channel's quantity (the values are compared as they are), and when the lag is
    estimated from a record shorter than the search window ``2 max_lag``.

    Raises:
        KeyError: ``channel`` or ``crank`` is not in the result (close matches listed).
        ValueError: the measured signal is another quantity than the channel (e.g. a
            length against an acceleration), is not uniformly sampled, does not overlap
            the simulated interval after the lag, or a setting is out of range.
    """
    sim_values = result[channel]
    sim_time = result.time
    unit = channel_unit(channel) or measured.unit
    _check_units(channel, measured)
    tm, vm = _series(measured.time, measured.values, f"measured '{measured.name}'")
    dt = _uniform_step(tm, f"measured '{measured.name}'")
    if lag is None:
        _check_record_length(tm, max_lag, measured.name)
    crank_name = crank if crank is not None else crank_channel(result)
    crank_angle = result[crank_name] if crank_name is not None else None
    if lowpass is not None:
        sim_values = _lowpass(sim_time, sim_values, lowpass)
        vm = _lowpass(tm, vm, lowpass)
    estimated = lag is None
    if lag is None:
        lag = estimate_lag(sim_time, sim_values, tm, vm, max_lag=max_lag)
    shifted = tm - lag
    eps = 1e-9 * dt
    keep = (shifted >= sim_time[0] - eps) & (shifted <= sim_time[-1] + eps)
    if np.count_nonzero(keep) < MIN_SAMPLES:
        raise ValueError(
            f"compare: measured '{measured.name}' ({tm[0]:g}..{tm[-1]:g} s) shifted by the lag "
            f"{lag:g} s does not overlap the simulated interval ({sim_time[0]:g}.."
            f"{sim_time[-1]:g} s) in at least {MIN_SAMPLES} samples"
        )
    time = np.clip(shifted[keep], sim_time[0], sim_time[-1])
    sim = np.interp(time, sim_time, sim_values)
    meas = vm[keep]
    sim_offset = meas_offset = 0.0
    if isinstance(offset, str):
        if offset != "mean":
            raise ValueError(f"compare: offset {offset!r}: give 'mean', a number or None")
        sim_offset, meas_offset = float(np.mean(sim)), float(np.mean(meas))
    elif offset is not None:
        meas_offset = float(offset)
    sim, meas = sim - sim_offset, meas - meas_offset
    rate = 1.0 / dt
    cycles: list[CycleRow] = []
    if crank_angle is not None:
        cycles = cycle_table(time, sim, meas, sim_time, crank_angle)
    for a in (time, sim, meas):
        a.flags.writeable = False
    difference = sim - meas
    difference.flags.writeable = False
    return Comparison(
        channel=channel,
        measured_name=measured.name,
        unit=unit,
        lag=float(lag),
        lag_estimated=estimated,
        max_lag=max_lag,
        lowpass=lowpass,
        offset=offset,
        simulated_offset=sim_offset,
        measured_offset=meas_offset,
        time=time,
        rate=rate,
        simulated=sim,
        measured=meas,
        difference=difference,
        measures=error_measures(sim, meas),
        spectra=compare_spectra(sim, meas, rate, spectrum_max),
        crank=crank_name,
        cycles=tuple(cycles),
    )
