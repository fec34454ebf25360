"""Contact statistics and deviation from the ideal run (jointgap.statistics) against
direct computations from the channels and the impact list."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from jointgap.results import Result
from jointgap.statistics import (
    contact_statistics,
    default_deviation_channels,
    deviation_from_ideal,
    deviation_table,
    format_statistics,
    statistics_table,
)

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
T_END = 0.5
RATE = 10_000


def _run(name: str, **options: object) -> Result:
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    import jointgap

    return jointgap.load(EXAMPLES / name).simulate(**{"t_end": T_END, "rate": RATE, **options})


@pytest.fixture(scope="module")
def founding() -> Result:
    """The founding case at 10 kHz (21 impacts in 0.5 s)."""
    return _run("slider_crank_clearance.toml")


@pytest.fixture(scope="module")
def founding_every_step() -> Result:
    """The founding case with every accepted step added to the 10 kHz samples."""
    return _run("slider_crank_clearance.toml", every_step=True)


@pytest.fixture(scope="module")
def ideal() -> Result:
    return _run("slider_crank_ideal.toml")


def _entries_into_impact(mode: np.ndarray) -> int:
    """Number of samples in mode 1 whose predecessor is not (a run starting in mode 1
    counts once)."""
    is_impact = mode == 1
    return int(is_impact[0]) + int(np.count_nonzero(is_impact[1:] & ~is_impact[:-1]))


# --- impact count ----------------------------------------------------------------------


def test_impact_count_equals_entries_into_mode_1_at_every_step(founding_every_step, engine):
    # Rate samples alone could hide an impact: in the founding case a separation at
    # t = 0.272799 s is followed by the next onset 42 us later, less than the 100 us
    # between samples at 10 kHz. With every_step=True every onset and every separation
    # ends a step (the engine locates them as events), so each impact has a sample in
    # mode 1 at its onset and each free flight a sample in mode 0 at its separation: the
    # sampled mode then shows every impact.
    r = founding_every_step
    impacts = r.impacts["rod_slider"]
    [s] = contact_statistics(r)
    assert s.impacts == len(impacts) == 21
    assert _entries_into_impact(r["rod_slider.mode"]) == s.impacts
    for i in impacts:
        k = int(np.argmin(np.abs(r.time - i.onset_time)))
        assert r.time[k] == pytest.approx(i.onset_time, abs=1e-12)
        assert r["rod_slider.mode"][k] == 1


def test_rate_samples_never_show_more_impacts_than_the_list(founding, engine):
    [s] = contact_statistics(founding)
    assert s.impacts == len(founding.impacts["rod_slider"]) == 21
    assert _entries_into_impact(founding["rod_slider.mode"]) <= s.impacts


# --- time fractions --------------------------------------------------------------------


@pytest.mark.parametrize("run", ["founding", "founding_every_step"])
def test_time_fractions_are_the_engines_time_in_each_mode(run, request, engine):
    r = request.getfixturevalue(run)
    [s] = contact_statistics(r)
    times = np.array(r.mode_time["rod_slider"])
    assert times.sum() == pytest.approx(T_END, rel=1e-12)
    assert [s.free_flight, s.impact, s.contact] == pytest.approx(times / T_END, abs=1e-12)
    assert s.free_flight + s.impact + s.contact == pytest.approx(1.0, abs=1e-12)
    # In contact (mode 1 or 2) against the exact intervals of the impact list: onsets and
    # separations end steps, so whatever the sampling there is no resolution error.
    impacts = r.impacts["rod_slider"]
    exact = sum(
        (i.duration if math.isfinite(i.duration) else r.time[-1] - i.onset_time) for i in impacts
    ) / (r.time[-1] - r.time[0])
    assert s.impact + s.contact == pytest.approx(exact, abs=1e-12)
    # Against the mode channel of every step held from record to record, which sees the
    # change from impact to continuous contact at the same step ends (or a sample
    # between them).
    steps = request.getfixturevalue("founding_every_step")
    mode = steps["rod_slider.mode"].astype(int)
    held = np.bincount(mode[:-1], weights=np.diff(steps.time), minlength=3) / T_END
    assert [s.free_flight, s.impact, s.contact] == pytest.approx(held, abs=1e-3)


# --- peaks and onset speeds ------------------------------------------------------------


def test_peaks_and_onset_speeds_from_the_impacts_and_channels(founding, engine):
    r = founding
    [s] = contact_statistics(r)
    frame = r.impacts_frame()
    # The impact list holds peaks over accepted steps as well as samples: larger here.
    assert frame["peak_force"].max() > r["rod_slider.fn"].max()
    assert s.peak_force == max(frame["peak_force"].max(), r["rod_slider.fn"].max())
    assert s.peak_force == pytest.approx(3052, rel=1e-3)
    assert s.max_penetration == max(
        frame["max_penetration"].max(), r["rod_slider.penetration"].max()
    )
    assert s.onset_speed_mean == pytest.approx(frame["onset_speed"].mean(), rel=1e-14)
    assert s.onset_speed_max == frame["onset_speed"].max()
    assert s.span == T_END and s.complete


# --- deviation from the ideal run ------------------------------------------------------


def test_deviation_equals_a_direct_computation(founding, ideal, engine):
    assert default_deviation_channels(founding) == ["slider.ax", "motor.torque"]
    devs = deviation_from_ideal(founding, ideal)
    assert [d.channel for d in devs] == ["slider.ax", "motor.torque"]
    for d in devs:
        diff = founding[d.channel] - ideal[d.channel]
        # Over time, trapezoidal: on an even grid the mean with half-weight ends.
        squares = diff**2
        mean = (squares.sum() - 0.5 * (squares[0] + squares[-1])) / (len(squares) - 1)
        assert d.rms == pytest.approx(np.sqrt(mean), rel=1e-12)
        assert d.peak == np.max(np.abs(diff))
        assert d.peak_time == founding.time[np.argmax(np.abs(diff))]
        span = np.ptp(ideal[d.channel])
        assert d.rms_relative == pytest.approx(d.rms / span, rel=1e-12)
        assert d.peak_relative == pytest.approx(d.peak / span, rel=1e-12)
        assert d.samples == len(founding.time)
    table = deviation_table(devs)
    assert list(table["unit"]) == ["m/s^2", "N*m"]


def test_deviation_interpolates_an_ideal_run_on_another_grid(founding, engine):
    coarse = _run("slider_crank_ideal.toml", rate=3_000, t_end=0.3)
    [d] = deviation_from_ideal(founding, coarse, ["slider.ax"])
    inside = founding.time <= 0.3
    diff = founding["slider.ax"][inside] - np.interp(
        founding.time[inside], coarse.time, coarse["slider.ax"]
    )
    assert d.samples == np.count_nonzero(inside)
    t = founding.time[inside]
    mean = np.trapezoid(diff**2, t) / (t[-1] - t[0])
    assert d.rms == pytest.approx(np.sqrt(mean), rel=1e-12)
    assert d.peak == pytest.approx(np.max(np.abs(diff)), rel=1e-12)


def test_deviation_errors(founding, ideal, engine):
    with pytest.raises(KeyError, match="ideal run: no channel 'rod_slider.fn'"):
        deviation_from_ideal(founding, ideal, ["rod_slider.fn"])
    later = Result(ideal.time + 10.0, ideal.channels, ideal.data, model=ideal.model)
    with pytest.raises(ValueError, match="share no time span"):
        deviation_from_ideal(founding, later)


# --- other models and runs -------------------------------------------------------------


def test_two_clearance_joints_give_two_rows(engine):
    r = _run("slider_crank_two_clearances.toml", t_end=0.1, rate=2_000)
    stats = contact_statistics(r)
    assert [s.joint for s in stats] == ["crank_rod", "rod_slider"]
    assert [s.impacts for s in stats] == [len(r.impacts[s.joint]) for s in stats]
    table = statistics_table(stats)
    assert list(table["joint"]) == ["crank_rod", "rod_slider"]
    assert len(format_statistics(stats).splitlines()) == 2


def test_a_model_without_clearance_joints_has_no_statistics(engine):
    r = _run("pendulum.toml", t_end=0.1, rate=100)
    assert contact_statistics(r) == []
    assert statistics_table([]).empty
    assert format_statistics([]) == ""


def test_a_joint_without_impacts_keeps_json_valid(engine):
    r = _run("slider_crank_clearance.toml", t_end=0.005)  # first onset at 5.7 ms
    [s] = contact_statistics(r)
    assert s.impacts == 0 and s.peak_force == 0.0 and s.max_penetration == 0.0
    assert math.isnan(s.onset_speed_mean) and math.isnan(s.onset_speed_max)
    assert s.free_flight == 1.0
    d = s.to_dict()
    assert d["onset_speed_mean"] is None and d["onset_speed_max"] is None
    json.dumps(d, allow_nan=False)
    assert "onset speed" not in format_statistics([s])


def test_a_failed_run_gives_statistics_of_what_it_computed(engine):
    r = _run("slider_crank_clearance.toml", max_steps=500)
    assert not r.ok
    [s] = contact_statistics(r)
    assert not s.complete and s.span == r.time[-1] < T_END
    assert s.impacts == len(r.impacts["rod_slider"]) > 0
    assert s.free_flight + s.impact + s.contact == pytest.approx(1.0)
    assert "run failed" in format_statistics([s])


def test_without_the_mode_channel_the_fractions_come_from_the_engine(engine):
    r = _run("slider_crank_clearance.toml", t_end=0.05, channels=["slider.*"])
    [s] = contact_statistics(r)
    assert s.impacts == len(r.impacts["rod_slider"]) > 0
    assert s.free_flight + s.impact + s.contact == pytest.approx(1.0, abs=1e-12)
    # A result without the engine's times and without the channel: unknown.
    bare = Result(r.time, r.channels, r.data, model=r.model, impacts=r.impacts)
    [s] = contact_statistics(bare)
    assert math.isnan(s.free_flight) and s.to_dict()["contact"] is None
    assert s.peak_force == max(i.peak_force for i in r.impacts["rod_slider"])


def test_summary_text_and_json(founding, ideal, engine):
    stats = contact_statistics(founding)
    devs = deviation_from_ideal(founding, ideal)
    text = format_statistics(stats, devs)
    first, *others = text.splitlines()
    assert first.startswith("rod_slider: 21 impacts; free flight ")
    [s] = stats
    expected = (
        f"peak force {s.peak_force:.0f} N; max penetration {1e6 * s.max_penetration:.2f} µm; "
        f"onset speed mean {s.onset_speed_mean:.2g} m/s"
    )
    assert expected in first and "peak force 30" in first
    assert [line.split(" vs ideal")[0] for line in others] == ["slider.ax", "motor.torque"]
    assert "m/s^2" in others[0] and "N*m" in others[1]
    json.dumps([x.to_dict() for x in [*stats, *devs]], allow_nan=False)
    table = statistics_table(stats)
    assert table.loc[0, "impacts"] == 21 and table.loc[0, "joint"] == "rod_slider"
