"""The lag search of jointgap.comparison (estimate_lag), whose correlation coefficients of
every shift come from cross-correlations by FFT: against a direct computation written
here (one coefficient per shift, each over the samples where both signals exist) and
against the known shift of a closed-form record."""

from __future__ import annotations

import math

import numpy as np
import pytest
from jointgap.comparison import MIN_SAMPLES, estimate_lag


def signal(t: np.ndarray) -> np.ndarray:
    """A closed-form 'simulation': a 5 Hz and a 37 Hz sine and a sharp pulse every 0.2 s
    (an impact per crank turn of the founding case)."""
    phase = np.mod(t, 0.2) - 0.1
    return (
        40.0 * np.sin(2 * np.pi * 5.0 * t)
        + 10.0 * np.sin(2 * np.pi * 37.0 * t + 0.4)
        + 300.0 * np.exp(-(phase**2) / (2 * 4e-4**2))
    )


def direct_lag(ts: np.ndarray, vs: np.ndarray, tm: np.ndarray, vm: np.ndarray, max_lag: float):  # type: ignore[no-untyped-def]
    """The documented search, shift by shift: the simulation interpolated at ``t_i - L dt``
    where it exists, ``np.corrcoef`` over those samples, the parabola through the
    largest coefficient and its neighbours."""
    dt = (tm[-1] - tm[0]) / (len(tm) - 1)
    k = math.floor(max_lag / dt + 1e-9) + 1
    shifts = range(-k, k + 1)
    r = []
    for shift in shifts:
        at = tm - shift * dt
        inside = (at >= ts[0] - 1e-9 * (ts[-1] - ts[0])) & (at <= ts[-1] + 1e-9 * (ts[-1] - ts[0]))
        if inside.sum() < MIN_SAMPLES:
            r.append(-math.inf)
            continue
        r.append(float(np.corrcoef(np.interp(at[inside], ts, vs), vm[inside])[0, 1]))
    j = int(np.argmax(r))
    lo, mid, hi = r[j - 1], r[j], r[j + 1]
    delta = 0.5 * (lo - hi) / (lo - 2 * mid + hi) if lo - 2 * mid + hi < 0 else 0.0
    return (j - k + delta) * dt


@pytest.mark.parametrize(
    "lag, start, rate",
    [(0.0123, 0.0, 5000.0), (-0.0071, 0.03, 5000.0), (0.0317, -0.02, 2000.0)],
)
def test_the_search_finds_a_known_shift_as_the_direct_search_does(lag, start, rate) -> None:  # type: ignore[no-untyped-def]
    # A 2 s simulation at 20 kHz; the record, 2.1 s of it with noise and an offset,
    # starts before and ends after the simulation, so the shifts overlap it partly.
    ts = np.arange(0.0, 2.0 + 1e-12, 5e-5)
    vs = signal(ts)
    rng = np.random.default_rng(7)
    tm = start + np.arange(round(2.1 * rate)) / rate
    vm = signal(tm - lag) + rng.normal(0.0, 5.0, len(tm)) + 12.0
    found = estimate_lag(ts, vs, tm, vm, max_lag=0.05)
    dt = 1.0 / rate
    assert found == pytest.approx(lag, abs=dt)
    # The same coefficients as the direct sums: the same lag to rounding.
    assert found == pytest.approx(direct_lag(ts, vs, tm, vm, 0.05), abs=1e-6 * dt)


def test_a_long_record_keeps_its_lag() -> None:
    # 60 s at 5 kHz (300 000 samples, 501 shifts): the whole-record search the long
    # comparisons run, within one sample of the shift.
    ts = np.arange(0.0, 60.0 + 1e-9, 1e-4)
    tm = 0.01 + np.arange(round(59.99 * 5000)) / 5000.0
    vm = signal(tm - 0.01) + np.random.default_rng(1).normal(0.0, 5.0, len(tm))
    assert estimate_lag(ts, signal(ts), tm, vm) == pytest.approx(0.01, abs=2e-4)


def test_a_constant_signal_has_no_lag() -> None:
    ts = np.linspace(0.0, 1.0, 10_001)
    tm = np.arange(0.0, 1.0, 2e-4)
    with pytest.raises(ValueError, match="or a signal is constant"):
        estimate_lag(ts, np.full(len(ts), 3.0), tm, signal(tm))
    with pytest.raises(ValueError, match="or a signal is constant"):
        estimate_lag(ts, signal(ts), tm, np.full(len(tm), -2.0))
