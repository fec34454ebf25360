"""Measured records (jointgap.measured): reading files in their units, the errors of bad
files, the CSV round trip, and synthetic records with a known rate, lag, noise and offset."""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from jointgap.measured import (
    MeasuredDataError,
    MeasuredSignal,
    check_overlap,
    read_measured,
    synthetic_record,
)
from jointgap.results import Result

G = 9.80665

WriteFile = Callable[..., Path]


@pytest.fixture
def write(tmp_path: Path) -> WriteFile:
    """Writes dedented text to tmp_path/<name> and returns the path."""

    def write(text: str, name: str = "record.csv") -> Path:
        path = tmp_path / name
        path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
        return path

    return write


# --- reading ---------------------------------------------------------------------------


def test_comma_file_with_header(write: WriteFile) -> None:
    path = write(
        """
        time,slider.ax
        0.0,1.5
        0.0002,-2.0
        0.0004,3.25
        """
    )
    sig = read_measured(path, "slider.ax")
    np.testing.assert_array_equal(sig.time, [0.0, 0.0002, 0.0004])
    np.testing.assert_array_equal(sig.values, [1.5, -2.0, 3.25])
    assert sig.name == "slider.ax"
    assert sig.unit == "m/s^2"  # no unit given: SI, named after the channel
    assert sig.source == str(path)
    assert not sig.values.flags.writeable


def test_whitespace_file_with_comments_and_blank_lines(write: WriteFile) -> None:
    path = write(
        """
        # accelerometer on the slider, 5 kHz
        # second comment

        t\tacc   other
        0.000   1.0   7   # first sample

        0.001\t2.0   8
        # a comment between rows
        0.002   3.0   9
        """,
        "record.txt",
    )
    sig = read_measured(path, "acc", time_column="t")
    np.testing.assert_array_equal(sig.time, [0.0, 0.001, 0.002])
    np.testing.assert_array_equal(sig.values, [1.0, 2.0, 3.0])
    assert sig.unit == ""  # unknown quantity, no unit given
    by_index = read_measured(path, 2, time_column=0)
    np.testing.assert_array_equal(by_index.values, [7.0, 8.0, 9.0])


def test_semicolon_and_explicit_delimiter(write: WriteFile) -> None:
    path = write("time;ax\n0;1\n1;2\n")
    assert read_measured(path, "ax").values.tolist() == [1.0, 2.0]
    path = write("time|ax\n0|1\n1|2\n", "pipe.txt")
    assert read_measured(path, "ax", delimiter="|").values.tolist() == [1.0, 2.0]


def test_file_without_header_by_index(write: WriteFile) -> None:
    path = write("0.0 10\n0.5 20\n1.0 30\n", "plain.txt")
    sig = read_measured(path, 1, time_column=0, unit="mm")
    np.testing.assert_allclose(sig.values, [0.01, 0.02, 0.03])
    assert sig.unit == "m"
    assert sig.name == "column 1"


@pytest.mark.parametrize(
    ("unit", "factor", "si"),
    [
        ("g", G, "m/s^2"),
        ("m/s^2", 1.0, "m/s^2"),
        ("mm", 1e-3, "m"),
        ("mm/s", 1e-3, "m/s"),
        ("N", 1.0, "N"),
        ("kN", 1e3, "N"),
        ("N*m", 1.0, "N*m"),
        ("N*mm", 1e-3, "N*m"),
    ],
)
def test_units_convert_to_si(write: WriteFile, unit: str, factor: float, si: str) -> None:
    path = write("time,x\n0,1.5\n0.1,-2\n")
    sig = read_measured(path, "x", unit=unit)
    np.testing.assert_allclose(sig.values, [1.5 * factor, -2 * factor], rtol=1e-15)
    assert sig.unit == si


def test_header_bracket_units(write: WriteFile) -> None:
    path = write(
        """
        time [ms], slider.ax [g], crank.torque [N*m]
        0, 1, 2
        2, 0.5, 4
        """
    )
    sig = read_measured(path, "slider.ax")
    np.testing.assert_allclose(sig.values, [G, 0.5 * G])
    np.testing.assert_allclose(sig.time, [0.0, 0.002])
    assert sig.name == "slider.ax"
    assert sig.unit == "m/s^2"
    # a bracket in the requested name is ignored for matching; an explicit unit wins
    torque = read_measured(path, "crank.torque [N*m]", unit="kN*m", time_unit="s")
    np.testing.assert_allclose(torque.values, [2000.0, 4000.0])
    np.testing.assert_allclose(torque.time, [0.0, 2.0])


def test_whitespace_header_with_bracket_units(write: WriteFile) -> None:
    path = write("time [s]   ax [mm/s^2]\n0 1000\n0.1 2000\n", "record.txt")
    sig = read_measured(path, "ax")
    np.testing.assert_allclose(sig.values, [1.0, 2.0])
    assert sig.unit == "m/s^2"


def test_case_insensitive_name(write: WriteFile) -> None:
    path = write("Time,Slider.AX\n0,1\n1,2\n")
    assert read_measured(path, "slider.ax").values.tolist() == [1.0, 2.0]


def test_rate_instead_of_time_column(write: WriteFile) -> None:
    path = write("ax [g]\n1\n2\n3\n4\n", "rate.txt")
    sig = read_measured(path, "ax", time_column=None, rate="5 kHz")
    np.testing.assert_allclose(sig.time, [0.0, 2e-4, 4e-4, 6e-4])
    np.testing.assert_allclose(sig.values, np.array([1, 2, 3, 4]) * G)
    assert sig.rate == pytest.approx(5000.0)
    plain = read_measured(path, 0, time_column=None, rate=1000)
    np.testing.assert_allclose(plain.time, [0.0, 1e-3, 2e-3, 3e-3])


# --- errors of bad files -------------------------------------------------------------


def test_missing_column_lists_the_available_ones(write: WriteFile) -> None:
    path = write("time,slider.ax [m/s^2],crank.torque\n0,1,2\n1,2,3\n")
    with pytest.raises(MeasuredDataError) as err:
        read_measured(path, "slider.vx")
    msg = str(err.value)
    assert "record.csv:1" in msg and "'slider.vx'" in msg
    assert "time, slider.ax, crank.torque" in msg


def test_missing_time_column_suggests_rate(write: WriteFile) -> None:
    path = write("t,ax\n0,1\n1,2\n")
    with pytest.raises(MeasuredDataError, match=r"no time column 'time'.*t, ax.*rate"):
        read_measured(path, "ax")


def test_index_out_of_range(write: WriteFile) -> None:
    path = write("time,ax\n0,1\n1,2\n")
    with pytest.raises(MeasuredDataError, match=r"no data column 5: the file has 2 columns"):
        read_measured(path, 5)


def test_name_without_header(write: WriteFile) -> None:
    path = write("0,1\n1,2\n")
    with pytest.raises(MeasuredDataError, match="no header row.*0-based index"):
        read_measured(path, "ax", time_column=0)


def test_non_numeric_cell(write: WriteFile) -> None:
    path = write(
        """
        # comment
        time,ax
        0,1
        0.1,abc
        """
    )
    with pytest.raises(MeasuredDataError) as err:
        read_measured(path, "ax")
    msg = str(err.value)
    assert "record.csv:4" in msg and "column 'ax'" in msg and "'abc'" in msg


@pytest.mark.parametrize("cell", ["nan", "inf", ""])
def test_non_finite_or_empty_cell(write: WriteFile, cell: str) -> None:
    path = write(f"time,ax\n0,1\n0.1,{cell}\n")
    with pytest.raises(MeasuredDataError, match=r"record\.csv:3: column 'ax'.*not a finite"):
        read_measured(path, "ax")


def test_short_row(write: WriteFile) -> None:
    path = write("time,ax,ay\n0,1,2\n0.1,2\n")
    with pytest.raises(MeasuredDataError, match=r"record\.csv:3: 2 fields, expected 3"):
        read_measured(path, "ax")


@pytest.mark.parametrize("times", [(0.0, 0.1, 0.1, 0.3), (0.0, 0.1, 0.05, 0.3)])
def test_time_must_increase_strictly(write: WriteFile, times: tuple[float, ...]) -> None:
    rows = "".join(f"{t},{k}\n" for k, t in enumerate(times))
    path = write("time,ax\n" + rows)
    with pytest.raises(MeasuredDataError) as err:
        read_measured(path, "ax")
    msg = str(err.value)
    assert "record.csv:4" in msg and "line 3" in msg
    assert f"from {times[1]} (line 3) to {times[2]} (line 4)" in msg


@pytest.mark.parametrize(
    "text", ["", "\n\n", "# only a comment\n", "time,ax\n", "time,ax  # header\n# end\n"]
)
def test_empty_file(write: WriteFile, text: str) -> None:
    path = write(text)
    with pytest.raises(MeasuredDataError, match=r"record\.csv: no data rows"):
        read_measured(path, "ax")


def test_too_few_samples(write: WriteFile) -> None:
    path = write("time,ax\n0,1\n")
    with pytest.raises(MeasuredDataError, match=r"record\.csv:2: only 1 data row"):
        read_measured(path, "ax")


def test_unknown_unit(write: WriteFile) -> None:
    path = write("time,ax [furlong]\n0,1\n1,2\n")
    with pytest.raises(MeasuredDataError, match=r"column 'ax': unknown unit 'furlong'.*line 1"):
        read_measured(path, "ax")
    with pytest.raises(MeasuredDataError, match=r"column 'ax': unknown unit 'gee'"):
        read_measured(path, "ax", unit="gee")
    with pytest.raises(MeasuredDataError, match=r"time column 'time': 'mm' is not a unit of"):
        read_measured(path, "ax", unit="g", time_unit="mm")


def test_both_or_neither_time_column_and_rate(write: WriteFile) -> None:
    path = write("time,ax\n0,1\n1,2\n")
    with pytest.raises(MeasuredDataError, match="not both"):
        read_measured(path, "ax", rate=5000)
    with pytest.raises(MeasuredDataError, match="not neither"):
        read_measured(path, "ax", time_column=None)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(MeasuredDataError, match=r"nothere\.csv: cannot read"):
        read_measured(tmp_path / "nothere.csv", "ax")


# --- signal, round trip, overlap -------------------------------------------------------


def _signal() -> MeasuredSignal:
    t = np.arange(7) / 5000.0 + 0.01
    return MeasuredSignal(t, np.sin(1e3 * t) / 3, "slider.ax", "m/s^2", "test")


def test_round_trip(tmp_path: Path) -> None:
    sig = _signal()
    path = tmp_path / "out.csv"
    sig.to_csv(path)
    lines = path.read_text().splitlines()
    assert "# time [s], slider.ax [m/s^2]" in lines
    assert "time,slider.ax" in lines
    back = read_measured(path, "slider.ax")
    np.testing.assert_array_equal(back.time, sig.time)
    np.testing.assert_array_equal(back.values, sig.values)
    assert (back.name, back.unit) == (sig.name, sig.unit)


def test_round_trip_keeps_the_unit_of_an_unknown_name(tmp_path: Path) -> None:
    sig = MeasuredSignal(
        np.array([0.0, 1.0]), np.array([1.0, 2.0]), "acc (synthetic)", "m/s^2", "x\ny"
    )
    sig.to_csv(tmp_path / "out.csv")
    back = read_measured(tmp_path / "out.csv", "acc (synthetic)")
    assert back.unit == "m/s^2"
    assert back.values.tolist() == [1.0, 2.0]


def test_signal_checks_lengths() -> None:
    with pytest.raises(ValueError, match="3 times but 2 values"):
        MeasuredSignal(np.arange(3.0), np.arange(2.0), "x", "m", "test")


def test_overlap() -> None:
    sig = _signal()  # t = 0.01 .. 0.0112 s
    assert sig.overlap(0.0, 0.011) == pytest.approx((0.01, 0.011))
    assert check_overlap(sig, 0.0, 1.0) == pytest.approx((0.01, 0.0112))
    assert sig.overlap(0.0, 0.01) is None  # touching is not overlapping
    with pytest.raises(MeasuredDataError) as err:
        check_overlap(sig, 0.02, 0.5)
    assert str(err.value) == (
        "test: the measured signal (t = 0.01..0.0112 s) does not overlap the "
        "simulated interval (t = 0.02..0.5 s)"
    )


# --- synthetic records -----------------------------------------------------------------

F = 50.0  # Hz, of the analytic slider acceleration


def _analytic(t_end: float = 0.2, rate: float = 50_000.0, f: float = F) -> Result:
    """A cheap Result: slider.ax = sin(2 pi f t), slider.vx alongside."""
    t = np.arange(round(t_end * rate) + 1) / rate
    ax = np.sin(2 * np.pi * f * t)
    return Result(time=t, channels=["slider.vx", "slider.ax"], data=np.array([np.cos(t), ax]))


def test_synthetic_sampling_and_lag() -> None:
    result = _analytic()
    rec = synthetic_record(result, "slider.ax", rate=5000.0, lag=0.01)
    assert rec.name == "slider.ax" and rec.unit == "m/s^2"
    assert rec.time[0] == pytest.approx(0.01) and rec.time[-1] == pytest.approx(0.2)
    assert len(rec) == 951
    np.testing.assert_allclose(np.diff(rec.time), 2e-4, rtol=1e-9)
    np.testing.assert_allclose(rec.time * 5000.0, np.round(rec.time * 5000.0), atol=1e-9)
    # measured(t) = simulated(t - lag)
    expected = np.interp(rec.time - 0.01, result.time, result["slider.ax"])
    np.testing.assert_allclose(rec.values, expected, atol=1e-12)
    np.testing.assert_allclose(rec.values, np.sin(2 * np.pi * F * (rec.time - 0.01)), atol=1e-5)
    assert "lag 0.01 s" in rec.source


def test_synthetic_negative_lag_and_duration() -> None:
    result = _analytic()
    rec = synthetic_record(result, "slider.ax", rate="5 kHz", lag="-4 ms", duration=0.1)
    assert rec.time[0] == pytest.approx(0.0) and rec.time[-1] == pytest.approx(0.1)
    np.testing.assert_allclose(rec.values, np.sin(2 * np.pi * F * (rec.time + 0.004)), atol=1e-5)
    full = synthetic_record(result, "slider.ax", lag=-0.004)
    assert full.time[-1] == pytest.approx(0.196)
    with pytest.raises(ValueError, match="longer than"):
        synthetic_record(result, "slider.ax", duration=0.5)


def test_synthetic_noise_offset_and_seed() -> None:
    result = _analytic(t_end=2.0, rate=20_000.0)
    clean = synthetic_record(result, "slider.ax")
    rec = synthetic_record(result, "slider.ax", noise=0.5, offset=-G, seed=7)
    err = rec.values - clean.values
    assert len(err) > 9000
    assert np.std(err) == pytest.approx(0.5, rel=0.04)
    assert np.mean(err) == pytest.approx(-G, abs=4 * 0.5 / np.sqrt(len(err)))
    again = synthetic_record(result, "slider.ax", noise=0.5, offset=-G, seed=7)
    np.testing.assert_array_equal(rec.values, again.values)
    other = synthetic_record(result, "slider.ax", noise=0.5, offset=-G, seed=8)
    assert not np.array_equal(rec.values, other.values)
    in_g = synthetic_record(result, "slider.ax", offset="1 g")
    np.testing.assert_allclose(in_g.values - clean.values, G)


def test_synthetic_band_limit_is_zero_phase() -> None:
    t = np.arange(20_001) / 50_000.0
    slow, fast = np.sin(2 * np.pi * 20 * t), 0.5 * np.sin(2 * np.pi * 3000 * t)
    result = Result(time=t, channels=["slider.ax"], data=np.array([slow + fast]))
    rec = synthetic_record(result, "slider.ax", lag=0.01, band_limit="200 Hz")
    inner = (rec.time > 0.1) & (rec.time < 0.3)  # away from the filter's end effects
    want = np.sin(2 * np.pi * 20 * (rec.time - 0.01))
    np.testing.assert_allclose(rec.values[inner], want[inner], atol=2e-3)
    with pytest.raises(ValueError, match="below half the run's sampling rate"):
        synthetic_record(result, "slider.ax", band_limit=30_000)


def test_synthetic_errors() -> None:
    result = _analytic(t_end=0.01)
    with pytest.raises(KeyError, match="slider.ay"):
        synthetic_record(result, "slider.ay")
    with pytest.raises(ValueError, match="fewer than 2 samples"):
        synthetic_record(result, "slider.ax", lag=0.0099)
    with pytest.raises(ValueError, match="noise must be"):
        synthetic_record(result, "slider.ax", noise=-1.0)


def test_synthetic_record_round_trip(tmp_path: Path) -> None:
    rec = synthetic_record(_analytic(), "slider.ax", noise=0.1)
    rec.to_csv(tmp_path / "rec.csv")
    back = read_measured(tmp_path / "rec.csv", "slider.ax")
    np.testing.assert_array_equal(back.values, rec.values)
    np.testing.assert_array_equal(back.time, rec.time)
    assert back.unit == "m/s^2"


def test_synthetic_record_of_the_founding_case(engine: None) -> None:
    import jointgap

    root = Path(__file__).resolve().parent.parent
    result = jointgap.load(root / "examples" / "slider_crank_clearance.toml").simulate(
        t_end=0.05, rate=20_000
    )
    rec = synthetic_record(result, "slider.ax", rate=5000, lag=0.01)
    assert rec.unit == "m/s^2" and len(rec) == 201
    expected = np.interp(rec.time - 0.01, result.time, result["slider.ax"])
    np.testing.assert_allclose(rec.values, expected, rtol=0, atol=1e-9)
    check_overlap(rec, float(result.time[0]), float(result.time[-1]))
