"""Simulation against measurement (jointgap.comparison): conditioning, lag, measures,
cycle table, spectra, figure, errors. Every measure is checked against a hand
computation on a few samples written here; the lag against records built here."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap.comparison import (
    Comparison,
    align_on_angle,
    amplitude_spectrum,
    compare,
    compare_spectra,
    crank_channel,
    cycle_table,
    error_measures,
    estimate_lag,
    lowpass,
    remove_offset,
    resample,
)
from jointgap.plots import comparison_figure
from jointgap.results import Result

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
MEAS_RATE = 5000.0  # [Hz], the paper's accelerometer
SAMPLE = 1.0 / MEAS_RATE
OMEGA = 300.0 * 2.0 * math.pi / 60.0  # founding case crank speed [rad/s]
RAMP = 0.2  # [s]


@dataclass
class Signal:
    """A measured signal as compare() sees it."""

    time: np.ndarray
    values: np.ndarray
    name: str = "accelerometer"
    unit: str = "m/s^2"


def sample(time: np.ndarray, values: np.ndarray, lag: float, t_meas: np.ndarray) -> Signal:
    """The record measured(t) = simulated(t - lag) at the times where the simulation
    exists."""
    shifted = t_meas - lag
    keep = (shifted >= time[0]) & (shifted <= time[-1])
    return Signal(t_meas[keep], np.interp(shifted[keep], time, values))


def synthetic(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A 'simulation' at 50 kHz over 0.6 s: two sines plus sharp decaying pulses at
    random instants (impacts)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 0.6, 2e-5)
    v = 40.0 * np.sin(2 * np.pi * 5.0 * t) + 10.0 * np.sin(2 * np.pi * 37.0 * t + 0.4)
    for t0 in rng.uniform(0.02, 0.58, 12):
        dt = t - t0
        v += np.where(
            dt >= 0, 200.0 * np.exp(-np.abs(dt) / 4e-4) * np.cos(2 * np.pi * 900 * dt), 0.0
        )
    return t, v


# ------------------------------------------------------------------ measures by hand


def test_error_measures_by_hand() -> None:
    # s - m = [-1, 1, -1, 1, 0]; means 3 and 3; ds = [-2, 0, -1, 2, 1], dm = [-1, -1, 0, 1, 1]
    s = np.array([1.0, 3.0, 2.0, 5.0, 4.0])
    m = np.array([2.0, 2.0, 3.0, 4.0, 4.0])
    e = error_measures(s, m)
    assert e.max_abs == 1.0
    assert e.max_percent == pytest.approx(100.0 * 1.0 / 4.0)  # 25 % of the peak 4
    assert e.rms == pytest.approx(math.sqrt(4.0 / 5.0))
    assert e.nrmse == pytest.approx(math.sqrt(0.8) / 2.0)  # range 4 - 2
    assert e.correlation == pytest.approx(5.0 / math.sqrt(10.0 * 4.0))  # 0.7906
    assert e.measured_peak == 4.0 and e.samples == 5


def test_max_percent_uses_the_largest_magnitude_of_the_measurement() -> None:
    # peak |m| = 6 (a negative peak); max |s - m| = 3 -> 50 %; rms sqrt(9 / 3), range 8
    s = np.array([-3.0, 1.0, 2.0])
    m = np.array([-6.0, 1.0, 2.0])
    e = error_measures(s, m)
    assert e.max_percent == pytest.approx(50.0)
    assert e.nrmse == pytest.approx(math.sqrt(9.0 / 3.0) / 8.0)
    # a linear map of the measurement correlates perfectly
    assert error_measures(1.0 + 0.5 * m, m).correlation == pytest.approx(1.0)
    assert error_measures(-m, m).correlation == pytest.approx(-1.0)


def test_measures_with_zero_denominators_are_nan() -> None:
    e = error_measures([1.0, 2.0, 3.0], [0.0, 0.0, 0.0])
    assert e.max_abs == 3.0 and e.rms == pytest.approx(math.sqrt(14.0 / 3.0))
    assert math.isnan(e.max_percent) and math.isnan(e.nrmse) and math.isnan(e.correlation)
    with pytest.raises(ValueError, match="3 simulated and 2 measured"):
        error_measures([1.0, 2.0, 3.0], [1.0, 2.0])


def test_amplitude_spectrum_reads_a_sine_amplitude() -> None:
    rate, n = 1000.0, 1000
    t = np.arange(n) / rate
    f, a = amplitude_spectrum(3.0 * np.sin(2 * np.pi * 50.0 * t) + 7.0, rate)
    assert f[1] == pytest.approx(1.0) and f[-1] == pytest.approx(500.0)
    assert f[np.argmax(a)] == pytest.approx(50.0)
    assert a.max() == pytest.approx(3.0, rel=1e-2)  # Hann, amplitude-corrected, on a bin
    assert a[0] < 1e-6  # the mean (7) is removed


def test_spectral_error_by_hand() -> None:
    rate = 1000.0
    t = np.arange(800) / rate
    m = np.sin(2 * np.pi * 50.0 * t)
    # twice the measured spectrum: |A_s - A_m| = A_m in every bin -> error 1
    sp = compare_spectra(2.0 * m, m, rate)
    assert sp.error == pytest.approx(1.0)
    assert sp.f_max == 500.0 and sp.frequency[-1] == pytest.approx(500.0)
    assert compare_spectra(m, m, rate).error == 0.0
    limited = compare_spectra(m, m, rate, f_max=120.0)
    assert limited.frequency[-1] <= 120.0 and limited.f_max == 120.0
    assert compare_spectra(m, m, rate, f_max=1e6).f_max == 500.0  # at most Nyquist
    with pytest.raises(ValueError, match="must be positive"):
        compare_spectra(m, m, rate, f_max=0.0)


def test_cycle_table_by_hand() -> None:
    # the crank turns at 0.5 rev/s: passes 0, 2 pi, 4 pi at t = 0, 2, 4
    time = np.arange(5.0)
    angle = np.pi * time
    s = np.array([0.0, 1.0, 0.0, 2.0, 0.0])
    m = np.array([0.0, 2.0, 0.0, 2.0, -2.0])
    rows = cycle_table(time, s, m, time, angle)
    assert [(r.cycle, r.start, r.end) for r in rows] == [(0, 0.0, 2.0), (1, 2.0, 4.0)]
    assert [(r.simulated, r.measured) for r in rows] == [(1.0, 2.0), (2.0, 4.0)]
    assert [r.relative_difference for r in rows] == [-0.5, -0.5]
    # clockwise: the same turns; half a turn missing at the start: one turn only
    assert len(cycle_table(time, s, m, time, -angle)) == 2
    assert [(r.start, r.end) for r in cycle_table(time, s, m, time, angle + np.pi)] == [(1.0, 3.0)]


# ------------------------------------------------------------------ conditioning


def test_lowpass_keeps_the_low_component_with_zero_phase() -> None:
    rate = 10_000.0
    t = np.arange(0.0, 1.0, 1.0 / rate)
    slow = np.sin(2 * np.pi * 10.0 * t)
    out = lowpass(t, slow + 0.5 * np.sin(2 * np.pi * 1000.0 * t), 100.0)
    interior = slice(1000, -1000)  # away from the ends
    assert np.max(np.abs(out[interior] - slow[interior])) < 1e-3  # no delay, no gain change
    with pytest.raises(ValueError, match="Nyquist frequency 5000 Hz"):
        lowpass(t, slow, 5000.0)
    with pytest.raises(ValueError, match="not sampled uniformly"):
        lowpass(t**2, slow, 100.0)


def test_remove_offset_and_resample() -> None:
    assert remove_offset([1.0, 2.0, 6.0]).tolist() == [-2.0, -1.0, 3.0]
    assert remove_offset([1.0, 2.0, 6.0], 1.0).tolist() == [0.0, 1.0, 5.0]
    with pytest.raises(ValueError, match="'median'"):
        remove_offset([1.0], "median")
    assert resample([0.0, 1.0, 2.0], [0.0, 10.0, 0.0], [0.5, 1.5]).tolist() == [5.0, 5.0]
    with pytest.raises(ValueError, match="leave the signal's range"):
        resample([0.0, 1.0, 2.0], [0.0, 10.0, 0.0], [1.5, 2.5])


# ------------------------------------------------------------------ lag


@pytest.mark.parametrize("lag", [0.01, 0.0123, -0.0071])
def test_estimate_lag_of_a_synthetic_record(lag: float) -> None:
    t, v = synthetic()
    rng = np.random.default_rng(1)
    meas = sample(t, v, lag, np.arange(0.0, 0.6, SAMPLE))
    noisy = meas.values + rng.normal(0.0, 3.0, len(meas.values)) + 5.0  # noise and bias
    assert estimate_lag(t, v, meas.time, noisy) == pytest.approx(lag, abs=SAMPLE)


def test_lag_beyond_the_search_range_is_named() -> None:
    t, v = synthetic()
    meas = sample(t, v, 0.01, np.arange(0.0, 0.6, SAMPLE))
    with pytest.raises(ValueError, match="raise max_lag"):
        estimate_lag(t, v, meas.time, meas.values, max_lag=0.004)


def test_estimate_lag_of_the_founding_case(engine: None, founding: Result) -> None:
    """The paper's set-up: slider acceleration at 5 kHz, 10 ms late, with noise."""
    rng = np.random.default_rng(2)
    ax = founding["slider.ax"]
    meas = sample(founding.time, ax, 0.01, np.arange(0.0, 0.5, SAMPLE))
    noisy = meas.values + rng.normal(0.0, 0.05 * np.std(ax), len(meas.values))
    lag = estimate_lag(founding.time, ax, meas.time, noisy)
    assert lag == pytest.approx(0.01, abs=SAMPLE)
    c = compare(founding, Signal(meas.time, noisy), "slider.ax", lowpass=1000.0)
    assert c.lag_estimated and c.lag == pytest.approx(0.01, abs=SAMPLE)
    assert c.measures.correlation > 0.95


# ------------------------------------------------------------------ compare


@pytest.fixture(scope="module")
def founding() -> Result:
    """The founding clearance case over 0.5 s at 50 kHz."""
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    return jointgap.load(EXAMPLES / "slider_crank_clearance.toml").simulate(0.5, rate=50_000)


def turn_times() -> list[float]:
    """When the founding crank passes 0, 2 pi, 4 pi: theta = OMEGA t^2 / (2 RAMP) up to
    RAMP (half a turn, pi), then pi + OMEGA (t - RAMP)."""
    return [0.0, RAMP + math.pi / OMEGA, RAMP + 3.0 * math.pi / OMEGA]  # 0, 0.3, 0.5 s


def test_cycle_table_of_the_founding_case(engine: None, founding: Result) -> None:
    assert crank_channel(founding) == "crank.angle"
    rng = np.random.default_rng(3)
    meas = sample(founding.time, founding["slider.ax"], 0.01, np.arange(0.0, 0.52, SAMPLE))
    meas.values += rng.normal(0.0, 2.0, len(meas.values))
    c = compare(founding, meas, "slider.ax", lag=0.01)
    assert not c.lag_estimated and c.time[0] == 0.0 and c.time[-1] == pytest.approx(0.5)
    t0, t1, t2 = turn_times()
    assert len(c.cycles) == 2  # the crank turns twice in 0.5 s
    for row, (start, end) in zip(c.cycles, [(t0, t1), (t1, t2)], strict=True):
        assert row.start == pytest.approx(start, abs=1e-5)
        assert row.end == pytest.approx(end, abs=1e-5)
        span = (c.time >= row.start - 1e-12) & (c.time <= row.end + 1e-12)
        assert row.simulated == pytest.approx(np.ptp(c.simulated[span]))
        assert row.measured == pytest.approx(np.ptp(c.measured[span]))
        assert row.relative_difference == pytest.approx(
            (row.simulated - row.measured) / row.measured
        )
    # a record from 0.1 s holds one complete turn, one from 0.05 s to 0.45 s none
    late = sample(founding.time, founding["slider.ax"], 0.0, np.linspace(0.1, 0.5, 2001))
    assert [r.cycle for r in compare(founding, late, "slider.ax", lag=0.0).cycles] == [1]
    mid = sample(founding.time, founding["slider.ax"], 0.0, np.arange(0.05, 0.45, SAMPLE))
    assert compare(founding, mid, "slider.ax", lag=0.0).cycles == ()


def test_compare_report_and_json(engine: None, founding: Result) -> None:
    meas = sample(founding.time, founding["slider.ax"], 0.01, np.arange(0.0, 0.52, SAMPLE))
    meas.values += 3.0  # an accelerometer bias
    c = compare(founding, meas, "slider.ax", lag=0.01, spectrum_max=1500.0)
    assert isinstance(c, Comparison) and c.unit == "m/s^2" and c.rate == pytest.approx(5000.0)
    assert c.measured_offset - c.simulated_offset == pytest.approx(3.0)  # means removed
    assert c.measures.max_abs < 1e-9 and c.measures.correlation == pytest.approx(1.0)
    assert c.spectra.f_max == 1500.0
    np.testing.assert_allclose(c.difference, c.simulated - c.measured)
    text = c.report()
    for line in ("lag: 10.000 ms (given", "max error / measured peak", "NRMSE", "correlation"):
        assert line in text
    assert "m/s^2" in text and "turn  start [s]" in text
    d = json.loads(json.dumps(c.to_dict(arrays=True), allow_nan=False))
    assert d["lag"] == 0.01 and d["measures"]["max_percent"] < 1e-9 and len(d["cycles"]) == 2
    assert len(d["time"]) == len(d["simulated"]) == len(d["measured_values"])
    # a known bias subtracted from the measurement only
    biased = compare(founding, meas, "slider.ax", lag=0.01, offset=3.0)
    assert biased.simulated_offset == 0.0 and biased.measures.max_abs < 1e-9
    # NaN measures become null
    zero = Signal(meas.time, np.zeros_like(meas.values))
    flat = compare(founding, zero, "slider.ax", lag=0.0, offset=None).to_dict()
    assert flat["measures"]["max_percent"] is None
    json.dumps(flat, allow_nan=False)


def test_compare_errors_are_named(engine: None, founding: Result) -> None:
    meas = sample(founding.time, founding["slider.ax"], 0.0, np.arange(0.0, 0.5, SAMPLE))
    with pytest.raises(KeyError, match="close matches: .*slider.ax"):
        compare(founding, meas, "slider.acc")
    with pytest.raises(KeyError, match="no channel 'crank.angel'"):
        compare(founding, meas, "slider.ax", crank="crank.angel")
    late = Signal(meas.time + 10.0, meas.values)
    with pytest.raises(ValueError, match="does not overlap the simulated interval"):
        compare(founding, late, "slider.ax", lag=0.0)
    with pytest.raises(ValueError, match="share fewer than"):
        compare(founding, late, "slider.ax")
    jitter = Signal(meas.time**1.1, meas.values)
    with pytest.raises(ValueError, match="not sampled uniformly"):
        compare(founding, jitter, "slider.ax")
    with pytest.raises(ValueError, match="Nyquist"):
        compare(founding, meas, "slider.ax", lowpass=2500.0)
    with pytest.warns(UserWarning, match=r"in m/s\^2, measured .accelerometer. in g"):
        compare(founding, Signal(meas.time, meas.values, unit="g"), "slider.ax", lag=0.0)


# ------------------------------------------------------------------ crank angle


def test_align_on_angle_removes_lag_and_speed_error() -> None:
    """A 'simulation' turning at 5 rev/s and a record of a crank at 5.2 rev/s, 7 ms late:
    against the crank angle the two signals agree."""
    t = np.arange(0.0, 0.5, 1e-5)
    theta = 2 * np.pi * 5.0 * t
    sim = Result(
        time=t,
        channels=["crank.angle", "slider.ax"],
        data=np.vstack([theta, np.sin(theta) + 0.3 * np.sin(3 * theta)]),
        model={
            "joints": [{"name": "pin", "type": "revolute", "body_i": "ground", "body_j": "crank"}],
            "drivers": [{"name": "motor", "joint": "pin"}],
        },
    )
    tm = np.arange(0.0, 0.5, SAMPLE)
    theta_m = 2 * np.pi * 5.2 * np.clip(tm - 0.007, 0.0, None)
    values = Signal(tm, np.sin(theta_m) + 0.3 * np.sin(3 * theta_m))
    angle = Signal(tm, theta_m, "crank angle", "rad")
    a = align_on_angle(sim, values, "slider.ax", angle)
    assert a.crank == "crank.angle" and a.angle[0] == pytest.approx(0.0, abs=1e-9)
    assert a.angle[-1] == pytest.approx(theta[-1], abs=0.05)  # the simulation's range
    np.testing.assert_allclose(a.simulated, a.measured, atol=1e-3)
    assert error_measures(a.simulated, a.measured).correlation > 0.999999
    # the measured crank speed, integrated from 0
    speed = Signal(tm, np.gradient(theta_m, tm), "crank speed", "rad/s")
    b = align_on_angle(sim, values, "slider.ax", speed, step=0.01)
    assert np.diff(b.angle) == pytest.approx(0.01)
    np.testing.assert_allclose(b.simulated, b.measured, atol=0.05)
    with pytest.raises(ValueError, match="need rad or rad/s"):
        align_on_angle(sim, values, "slider.ax", Signal(tm, theta_m, "crank", "deg"))


# ------------------------------------------------------------------ figure


def test_comparison_figure_axes_and_lines(engine: None, founding: Result) -> None:
    meas = sample(founding.time, founding["slider.ax"], 0.01, np.arange(0.0, 0.52, SAMPLE))
    c = compare(founding, meas, "slider.ax", lowpass=1000.0)
    fig = comparison_figure(c)
    signal, diff, spectrum = fig.axes
    assert signal.get_ylabel() == "slider.ax [m/s$^2$]"
    assert diff.get_ylabel() == "difference [m/s$^2$]"
    assert diff.get_xlabel() == "simulation time [s]"
    assert spectrum.get_xlabel() == "frequency [Hz]"
    assert spectrum.get_ylabel() == "amplitude [m/s$^2$]" and spectrum.get_yscale() == "log"
    assert [ln.get_gid() for ln in signal.lines if ln.get_gid()] == ["simulated", "measured"]
    assert [ln.get_gid() for ln in diff.lines] == ["difference"]
    assert [ln.get_gid() for ln in spectrum.lines] == ["spectrum-simulated", "spectrum-measured"]
    np.testing.assert_allclose(np.asarray(signal.lines[0].get_ydata(), dtype=float), c.simulated)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend == ["simulated", "measured (accelerometer)"]
    assert "lag 10.00 ms" in signal.get_title()
    with pytest.raises(ValueError, match="1 labels, need 2"):
        comparison_figure(c, labels=["only one"])
