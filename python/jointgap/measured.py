"""Measured signals: read a test record (CSV or whitespace text), or make a synthetic one.

The founding case was fitted against an accelerometer on the slider, sampled at 5 kHz,
whose record lags the simulation by about 0.01 s (docs/physics.md section 5). This module
brings such a record into SI (:func:`read_measured`), checks it covers the simulated
interval (:func:`check_overlap`), and makes a synthetic record from a run with a known
rate, lag, band limit, noise and offset (:func:`synthetic_record`), so that the comparison
and the lag estimate can be tested against known answers.

Files: one optional header row of column names, each name optionally followed by its unit
in brackets (``slider.ax [m/s^2]``); comment lines and trailing comments (``#`` unless told);
blank lines. Fields are separated by commas, semicolons or whitespace (detected from the
first row unless given). The line just before the header may be a comment giving every
column with its unit (``# time [s], slider.ax [m/s^2]``), as :meth:`MeasuredSignal.to_csv`
writes it.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from . import units
from .errors import MeasuredDataError, UnitError
from .results import Result, channel_unit
from .units import Dimension

__all__ = [
    "MeasuredDataError",
    "MeasuredSignal",
    "check_overlap",
    "read_measured",
    "synthetic_record",
]


@dataclass(frozen=True, eq=False)
class MeasuredSignal:
    """One measured (or synthetic) signal, SI.

    Attributes:
        time: sample times [s], strictly increasing (read-only array).
        values: samples in SI (read-only array, same length as ``time``).
        name: the column's name (e.g. ``slider.ax``).
        unit: the SI unit of ``values`` (e.g. ``m/s^2``); ``""`` when unknown.
        source: where it came from: the file's path or a description.
    """

    time: np.ndarray
    values: np.ndarray
    name: str
    unit: str
    source: str

    def __post_init__(self) -> None:
        time = np.array(self.time, dtype=float).reshape(-1)
        values = np.array(self.values, dtype=float).reshape(-1)
        if time.shape != values.shape:
            raise ValueError(f"{len(time)} times but {len(values)} values")
        time.flags.writeable = False
        values.flags.writeable = False
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "values", values)

    def __len__(self) -> int:
        return len(self.time)

    def __repr__(self) -> str:
        span = f"t = {self.time[0]:g}..{self.time[-1]:g} s" if len(self) else "no samples"
        return f"<MeasuredSignal {self.name!r} [{self.unit}]: {len(self)} samples, {span}>"

    @property
    def rate(self) -> float:
        """The sampling rate [Hz], from the median step (NaN with fewer than 2 samples)."""
        if len(self) < 2:
            return math.nan
        return float(1.0 / np.median(np.diff(self.time)))

    def overlap(self, t_start: float, t_end: float) -> tuple[float, float] | None:
        """The common part of the record and ``[t_start, t_end]`` [s]; ``None`` when the
        two do not share an interval of positive length."""
        if not len(self):
            return None
        lo = max(float(self.time[0]), float(t_start))
        hi = min(float(self.time[-1]), float(t_end))
        return (lo, hi) if lo < hi else None

    def to_csv(self, path: str | PathLike[str]) -> None:
        """Writes ``time,<name>`` (shortest exact floats) after a comment line with the
        units, ``# time [s], <name> [<unit>]``, so that :func:`read_measured` reads the
        units back."""
        unit = self.unit if _parses(self.unit) else ""
        label = f"{self.name} [{unit}]" if unit else self.name
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        with open(path, "w", newline="", encoding="utf-8") as f:
            source = " ".join(self.source.split())
            f.write(f"# jointgap measured signal: {source}\n")
            f.write(f"# time [s], {label}\n")
            writer = csv.writer(f, lineterminator="\n")
            writer.writerow(["time", self.name])
            writer.writerows(
                (repr(float(t)), repr(float(v)))
                for t, v in zip(self.time, self.values, strict=True)
            )


def check_overlap(signal: MeasuredSignal, t_start: float, t_end: float) -> tuple[float, float]:
    """The common interval of a record and a simulated interval [s]; raises
    :class:`MeasuredDataError` when there is none (a comparison would be empty)."""
    common = signal.overlap(t_start, t_end)
    if common is None:
        span = f"t = {signal.time[0]:g}..{signal.time[-1]:g} s" if len(signal) else "empty"
        raise MeasuredDataError(
            f"{signal.source}: the measured signal ({span}) does not overlap the "
            f"simulated interval (t = {float(t_start):g}..{float(t_end):g} s)"
        )
    return common


# ---------------------------------------------------------------------------- reading

_BRACKET = re.compile(r"^(.*?)\s*\[([^\]]*)\]\s*$")
# A whitespace-separated field, keeping a bracketed unit with its name: "slider.ax [m/s^2]".
_WS_FIELD = re.compile(r"[^\s\[\]]+(?:\s*\[[^\]]*\])?|\[[^\]]*\]")


def _split_label(label: str) -> tuple[str, str | None]:
    """``"slider.ax [m/s^2]"`` -> ``("slider.ax", "m/s^2")``; no bracket -> unit None."""
    m = _BRACKET.match(label)
    if m is None:
        return label.strip(), None
    return m.group(1).strip(), m.group(2).strip() or None


def _fields(text: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return _WS_FIELD.findall(text)
    row = next(csv.reader([text], delimiter=delimiter, skipinitialspace=True), [])
    return [f.strip() for f in row]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _parses(unit: str) -> bool:
    try:
        units.parse_unit(unit)
    except UnitError:
        return False
    return True


def _unit_factor(unit: str, prefer: Dimension | None) -> tuple[float, Dimension]:
    """Factor to SI and dimension of a column's unit. ``g`` is standard gravity here
    (a measured signal is an acceleration far more often than a mass) unless the
    column's name says it is a mass."""
    options = units.parse_unit(unit)
    if len(options) > 1:
        matching = [o for o in options if o[1] == prefer]
        options = matching or [o for o in options if o[1] != units.MASS] or options
    factor, dim = options[0]
    return float(factor), dim


def _dimension_of(channel: str) -> Dimension | None:
    """The dimension of a channel's SI unit (``slider.ax`` -> acceleration), if known."""
    unit = channel_unit(channel)
    if not unit or not _parses(unit):
        return None
    return units.parse_unit(unit)[0][1]


@dataclass
class _Table:
    """What the text of a file holds, before columns are chosen."""

    path: str
    delimiter: str | None
    header: list[str] | None  # the header's fields, brackets included
    header_line: int
    comment_units: list[str | None] | None  # units from the comment line before the header
    rows: list[tuple[int, list[str]]]  # (line number, fields)

    @property
    def width(self) -> int:
        return len(self.header) if self.header is not None else len(self.rows[0][1])

    def names(self) -> list[str]:
        assert self.header is not None
        return [_split_label(h)[0] for h in self.header]

    def label(self, index: int) -> str:
        return self.names()[index] if self.header is not None else f"column {index}"

    def unit(self, index: int) -> str | None:
        """The unit the file gives a column: its header bracket, else the unit comment."""
        if self.header is not None:
            unit = _split_label(self.header[index])[1]
            if unit is not None:
                return unit
        if self.comment_units is not None:
            return self.comment_units[index]
        return None


def _read_table(path: str, delimiter: str | None, comment: str | None) -> _Table:
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise MeasuredDataError(f"{path}: not UTF-8 text ({exc.reason})") from None
    except OSError as exc:
        raise MeasuredDataError(f"{path}: cannot read ({exc.strerror or exc})") from None
    auto = delimiter is None
    delim = None if delimiter is None or delimiter.isspace() else delimiter
    header: list[str] | None = None
    header_line = 0
    last_comment: str | None = None
    comment_units: list[str | None] | None = None
    rows: list[tuple[int, list[str]]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if comment and line.startswith(comment):
            if header is None and not rows:
                last_comment = line[len(comment) :].strip()
            continue
        if comment:
            line = line.split(comment, 1)[0].strip()
        if not line:
            continue
        if auto and header is None and not rows:
            delim = "," if "," in line else ";" if ";" in line else None
        fields = _fields(line, delim)
        # A first row without any number is the header; one with a bad cell is data.
        if header is None and not rows and not any(_is_number(f) for f in fields):
            header, header_line = fields, lineno
            comment_units = _comment_units(last_comment, header, delim)
            continue
        rows.append((lineno, fields))
    return _Table(path, delim, header, header_line, comment_units, rows)


def _comment_units(
    comment: str | None, header: list[str], delimiter: str | None
) -> list[str | None] | None:
    """Units from a comment like ``time [s], slider.ax [m/s^2]`` naming the header's
    columns in order; None when the comment is something else."""
    if comment is None:
        return None
    labels = [_split_label(f) for f in _fields(comment, delimiter)]
    names = [_split_label(h)[0] for h in header]
    if [n for n, _ in labels] != names:
        return None
    return [u for _, u in labels]


def _column(table: _Table, spec: str | int, role: str) -> int:
    """The 0-based index of a column given by name or index."""
    where = f"{table.path}:{table.header_line}" if table.header is not None else table.path
    if isinstance(spec, bool) or not isinstance(spec, (int, str)):
        raise TypeError(f"the {role} column must be a name or a 0-based index, not {spec!r}")
    if isinstance(spec, int):
        if not 0 <= spec < table.width:
            raise MeasuredDataError(
                f"{where}: no {role} column {spec}: the file has {table.width} columns "
                f"(0-based indices 0..{table.width - 1})"
            )
        return spec
    if table.header is None:
        raise MeasuredDataError(
            f"{table.path}: no header row, so no column is named '{spec}'; give the "
            f"{role} column as a 0-based index (0..{table.width - 1})"
        )
    names = table.names()
    wanted = _split_label(spec)[0]
    if wanted in names:
        return names.index(wanted)
    folded = [k for k, n in enumerate(names) if n.casefold() == wanted.casefold()]
    if len(folded) == 1:
        return folded[0]
    hint = " (or pass time_column=None and a sampling rate)" if role == "time" else ""
    raise MeasuredDataError(
        f"{where}: no {role} column '{spec}'; the columns are: {', '.join(names)}{hint}"
    )


def _numbers(table: _Table, index: int) -> tuple[np.ndarray, list[str]]:
    """The column's cells as floats, with their texts; errors name file:line."""
    out = np.empty(len(table.rows))
    texts: list[str] = []
    where_width = f"as the header at line {table.header_line}" if table.header else "as row 1"
    for k, (lineno, fields) in enumerate(table.rows):
        if len(fields) != table.width:
            raise MeasuredDataError(
                f"{table.path}:{lineno}: {len(fields)} fields, expected {table.width} "
                f"({where_width})"
            )
        cell = fields[index]
        value = float(cell) if _is_number(cell) else math.nan
        if not math.isfinite(value):
            raise MeasuredDataError(
                f"{table.path}:{lineno}: column '{table.label(index)}': "
                f"'{cell}' is not a finite number"
            )
        out[k] = value
        texts.append(cell)
    return out, texts


def read_measured(
    path: str | PathLike[str],
    column: str | int,
    *,
    time_column: str | int | None = "time",
    rate: float | str | None = None,
    unit: str | None = None,
    time_unit: str | None = None,
    delimiter: str | None = None,
    comment: str | None = "#",
) -> MeasuredSignal:
    """Reads one column of a measured record and converts it to SI.

    Args:
        path: a CSV or whitespace-separated text file.
        column: the data column, by header name (a bracketed unit in the header is
            ignored for matching; case-insensitive when unambiguous) or 0-based index.
        time_column: the time column (name or 0-based index); ``None`` with ``rate``.
        rate: the sampling rate [Hz] (a number or a string like ``"5 kHz"``) of a file
            without a time column: sample k is at ``t = k / rate``, k = 0, 1, ...
            Give exactly one of ``time_column`` and ``rate``.
        unit: the data column's unit (``"m/s^2"``, ``"g"`` = 9.80665 m/s^2, ``"mm"``,
            ``"N"``, ``"N*m"``, ``"mm/s"``); default: the header's bracket, else the unit
            comment line, else the values are taken as SI.
        time_unit: the time column's unit; default: the header's bracket, else ``s``.
        delimiter: the field separator; default: ``,`` if the first row has one, else
            ``;`` if it has one, else whitespace.
        comment: the text that starts a comment (whole line or trailing); None: none.

    Returns:
        The signal in SI; its ``unit`` is the SI unit of the given unit, or, with no unit
        anywhere, :func:`jointgap.channel_unit` of the column's name (``""`` if unknown).

    Raises:
        MeasuredDataError: with file and line where there is one: a missing column (the
            available ones are listed), a cell that is not a finite number, a time that
            does not increase strictly, fewer than 2 samples, an unknown unit, both or
            neither of ``time_column`` and ``rate``.
    """
    source = str(path)
    if (time_column is None) == (rate is None):
        raise MeasuredDataError(
            f"{source}: give either a time column or a sampling rate, not "
            + ("both (pass time_column=None with rate)" if rate is not None else "neither")
        )
    table = _read_table(source, delimiter, comment)
    if not table.rows:
        raise MeasuredDataError(f"{source}: no data rows (empty, or only a header and comments)")
    if len(table.rows) < 2:
        raise MeasuredDataError(
            f"{source}:{table.rows[0][0]}: only 1 data row; a signal needs at least 2 samples"
        )

    index = _column(table, column, "data")
    name = table.label(index)
    raw, _ = _numbers(table, index)
    given = unit if unit is not None else table.unit(index)
    origin = f" (from the header, line {table.header_line})" if unit is None else ""
    if given is None:
        si_unit = channel_unit(name)
        values = raw
    else:
        try:
            factor, dim = _unit_factor(given, _dimension_of(name))
        except UnitError as exc:
            raise MeasuredDataError(f"{source}: column '{name}': {exc}{origin}") from None
        si_unit = dim.si_unit()
        values = raw * factor

    if rate is not None:
        try:
            hz = units.to_si(rate, units.FREQUENCY)
        except UnitError as exc:
            raise MeasuredDataError(f"{source}: sampling rate {exc}") from None
        if not hz > 0:
            raise MeasuredDataError(f"{source}: the sampling rate must be positive, not {rate}")
        time = np.arange(len(values)) / hz
    else:
        assert time_column is not None
        t_index = _column(table, time_column, "time")
        if t_index == index:
            raise MeasuredDataError(f"{source}: the time and data columns are both '{name}'")
        t_name = table.label(t_index)
        t_raw, t_texts = _numbers(table, t_index)
        t_given = time_unit or table.unit(t_index) or "s"
        try:
            options = [f for f, d in units.parse_unit(t_given) if d == units.TIME]
        except UnitError as exc:
            raise MeasuredDataError(f"{source}: time column '{t_name}': {exc}") from None
        if not options:
            raise MeasuredDataError(
                f"{source}: time column '{t_name}': '{t_given}' is not a unit of time"
            )
        time = t_raw * float(options[0])
        steps = np.diff(time)
        bad = np.flatnonzero(~(steps > 0))
        if bad.size:
            k = int(bad[0])
            raise MeasuredDataError(
                f"{source}:{table.rows[k + 1][0]}: time goes from {t_texts[k]} (line "
                f"{table.rows[k][0]}) to {t_texts[k + 1]} (line {table.rows[k + 1][0]}) "
                f"[{t_given}]; the time column must increase strictly"
            )
    return MeasuredSignal(time=time, values=values, name=name, unit=si_unit, source=source)


# ---------------------------------------------------------------------------- synthesis


def synthetic_record(
    result: Result,
    channel: str,
    *,
    rate: float | str = 5000.0,
    lag: float | str = 0.01,
    noise: float | str = 0.0,
    offset: float | str = 0.0,
    band_limit: float | str | None = None,
    seed: int = 0,
    duration: float | str | None = None,
) -> MeasuredSignal:
    """A synthetic measurement of a simulated channel, with known errors to recover.

    Lag convention: **measured(t) = simulated(t - lag)**: the record lags the simulation
    by ``lag`` seconds (a positive lag delays it, as the speed controller did in the
    founding case). Samples lie on the record's clock grid ``t = k / rate`` (k integer)
    and only where the delayed simulation exists: for a run over ``[t0, t_end]``,
    ``t`` in ``[t0 + max(lag, 0), t_end + min(lag, 0)]``, cut to its first ``duration``
    seconds when given.

    Between the run's samples the channel is interpolated linearly, so the run should be
    sampled well above ``rate`` (20-50 kHz for 5 kHz) or the impact peaks are flattened.

    Args:
        result: a run holding ``channel``.
        channel: e.g. ``slider.ax``.
        rate: the record's sampling rate [Hz] (number or ``"5 kHz"``).
        lag: the measurement's delay [s] (may be negative).
        noise: standard deviation of additive white Gaussian noise, in the channel's SI
            unit (or a string with units, ``"0.5 m/s^2"``).
        offset: a constant added to every sample (a sensor bias, or gravity), same units.
        band_limit: cut-off [Hz] of a zero-phase 4th-order Butterworth low-pass applied
            to the run's samples before sampling and noise (an anti-alias filter without
            phase lag, so the lag stays exactly ``lag``); must be below half the run's
            sampling rate. None: no filter.
        seed: seed of the noise generator (same seed, same noise).
        duration: the record's length [s]; default: all that is available.

    Returns:
        A :class:`MeasuredSignal` named like the channel, in the channel's SI unit,
        its ``source`` saying it is synthetic and with which settings.
    """
    t_sim = np.asarray(result.time, dtype=float)
    y_sim = np.asarray(result[channel], dtype=float)
    if len(t_sim) < 2:
        raise ValueError(f"the run has {len(t_sim)} samples; a record needs at least 2")
    if np.any(np.diff(t_sim) < 0):
        raise ValueError("the run's sample times decrease")
    hz = units.to_si(rate, units.FREQUENCY)
    if not hz > 0:
        raise ValueError(f"rate must be positive, not {rate!r}")
    delay = units.to_si(lag, units.TIME)
    dim = _dimension_of(channel) or units.DIMENSIONLESS
    sigma = units.to_si(noise, dim)
    bias = units.to_si(offset, dim)
    if sigma < 0:
        raise ValueError(f"noise must be a standard deviation >= 0, not {noise!r}")

    t0, t1 = float(t_sim[0]), float(t_sim[-1])
    start, end = t0 + max(delay, 0.0), t1 + min(delay, 0.0)
    if duration is not None:
        length = units.to_si(duration, units.TIME)
        if not length > 0:
            raise ValueError(f"duration must be positive, not {duration!r}")
        if start + length > end * (1 + 1e-12) + 1e-12:
            raise ValueError(
                f"duration {length:g} s is longer than the {max(end - start, 0.0):g} s the "
                f"run covers with lag {delay:g} s (t = {start:g}..{end:g} s)"
            )
        end = start + length
    k = np.arange(math.ceil(start * hz - 1e-9), math.floor(end * hz + 1e-9) + 1)
    if len(k) < 2:
        raise ValueError(
            f"the run (t = {t0:g}..{t1:g} s) with lag {delay:g} s leaves fewer than 2 samples "
            f"at {hz:g} Hz"
        )
    time = k / hz

    if band_limit is not None:
        t_sim, y_sim = _low_pass(t_sim, y_sim, units.to_si(band_limit, units.FREQUENCY))
    values = np.interp(np.clip(time - delay, t0, t1), t_sim, y_sim)
    rng = np.random.default_rng(seed)
    if sigma > 0:
        values = values + rng.normal(0.0, sigma, len(values))
    values = values + bias

    cut = "none" if band_limit is None else f"{units.to_si(band_limit, units.FREQUENCY):g} Hz"
    source = (
        f"synthetic record of {channel}: rate {hz:g} Hz, lag {delay:g} s, noise {sigma:g}, "
        f"offset {bias:g}, band limit {cut}, seed {seed}"
    )
    return MeasuredSignal(
        time=time,
        values=values,
        name=channel,
        unit=channel_unit(channel),
        source=source,
    )


def _low_pass(t: np.ndarray, y: np.ndarray, cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero-phase 4th-order Butterworth low-pass on a uniform grid at the run's median
    step (the run's samples are resampled to it first when they are not uniform)."""
    from scipy.signal import butter, sosfiltfilt  # type: ignore[import-untyped,unused-ignore]

    steps = np.diff(t)
    h = float(np.median(steps[steps > 0]))
    fs = 1.0 / h
    if not 0 < cutoff < fs / 2:
        raise ValueError(
            f"band_limit {cutoff:g} Hz must be positive and below half the run's sampling "
            f"rate ({fs / 2:g} Hz)"
        )
    grid = t[0] + h * np.arange(int(math.floor((t[-1] - t[0]) / h + 1e-9)) + 1)
    on_grid = np.interp(grid, t, y)
    sos = butter(4, cutoff, btype="low", fs=fs, output="sos")
    if len(grid) <= 3 * (2 * len(sos) + 1):
        raise ValueError(f"the run has too few samples ({len(grid)}) to filter")
    return grid, np.asarray(sosfiltfilt(sos, on_grid), dtype=float)
