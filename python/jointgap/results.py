"""Results of a run: named channels against time, with the run's model and options.

Channels are named ``<element>.<quantity>`` (``slider.ax``, ``motor.torque``,
``system.kinetic_energy``), SI units; :func:`channel_unit` gives each one's unit. A
result saved with :meth:`Result.save` (``results.csv`` + ``summary.json``) holds the model
and the options, so the run can be repeated from the folder alone::

    r = Result.load("out/run1")
    again = jointgap.Model.from_dict(r.model).simulate(**r.run_arguments())
"""

from __future__ import annotations

import csv
import difflib
import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypedDict

import numpy as np

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped]

__all__ = [
    "Result",
    "RunStatus",
    "RunStats",
    "StageTimes",
    "Impact",
    "channel_unit",
    "impact_units",
    "RESULTS_CSV",
    "RESULTS_PARQUET",
    "SUMMARY_JSON",
    "IMPACTS_CSV",
    "model_channels",
    "require_channel",
]

RESULTS_CSV = "results.csv"
RESULTS_PARQUET = "results.parquet"
"""Where a streamed result's samples are (instead of ``results.csv``)."""
SUMMARY_JSON = "summary.json"
IMPACTS_CSV = "impacts.csv"
CSV_BLOCK = 65_536
"""Rows per block that :meth:`Result.to_csv` writes between progress calls."""
WriteProgress = Callable[[int, int], object]
"""``progress(rows_written, rows)`` of :meth:`Result.to_csv` and :meth:`Result.save`."""
IMPACT_COLUMNS = ("joint", "onset_time", "onset_speed", "peak_force", "max_penetration", "duration")
"""Columns of ``impacts.csv`` and of :meth:`Result.impacts_frame`."""

CLEARANCE_TYPES = (
    "clearance_revolute",
    "clearance_spherical",
    "clearance_cylindrical",
    "lubricated_revolute",
    "clearance_translational",
    "revolute_with_play",
    "prismatic_with_play",
    "gear_pair",
    "lubricated_cylindrical",
)
"""The joint types with contact: contact force elements with impact lists."""

MULTI_POINT_TYPES = ("clearance_cylindrical", "clearance_translational", "lubricated_cylindrical")
"""The joint types of several contact points, whose impact lists and contact channels
are named by point, ``<joint>.p1``, ``<joint>.p2``, ..."""

_ROTATION_PLAY_UNITS = {"penetration": "rad", "penetration_rate": "rad/s"}
_JOINT_UNITS: dict[str, dict[str, str]] = {"revolute_with_play": _ROTATION_PLAY_UNITS}
"""Per joint type, the units of its channels that differ from the quantity's usual one
(:func:`channel_unit`): a revolute joint's play penetrates by an angle."""

RunStatus = Literal["finished", "failed", "interrupted"]
"""How a run ended (:attr:`Result.status`): it reached its end time, it stopped early
(:attr:`Result.message` says why and when), or Ctrl-C stopped it."""


class StageTimes(TypedDict):
    """Where a run's time went, in seconds per stage (``stats["profile"]`` of a run asked
    for ``profile=True``); each stage excludes the stages it calls, and what they leave
    of ``total`` is the integrators' own arithmetic."""

    forces: float
    linear_solves: float
    jacobians: float
    output: float
    events: float
    projection: float
    total: float


class RunStats(TypedDict, total=False):
    """The engine's counters of one run (:attr:`Result.stats`), as ``summary.json`` holds
    them; a result built by hand may leave any of them out."""

    accepted_steps: int
    rejected_steps: int
    rhs_evaluations: int
    """Evaluations of the equations of motion (each one an augmented solve)."""
    jacobian_evaluations: int
    newton_iterations: int
    """Newton iterations of the implicit method (each evaluates every stage it solves)."""
    projections: int
    """Position and velocity projections onto the constraints."""
    events: int
    """Located contact onsets and separations."""
    method: str
    """The integrator that ran: ``dopri5``, ``sdirk4``, ``radau5``, or for ``auto`` the
    methods it used and when (``auto: dopri5, sdirk4 from t = ...``)."""
    wall_time: float
    """Wall-clock time of the run [s]: integration and output, and compiling and
    assembling the model only where it was not prepared already (loading a model
    prepares it, so a loaded model's runs leave that out)."""
    profile: StageTimes | None
    """Time per stage when the run was asked to measure it, else None."""
    compiled: str
    """How the equations of motion ran (docs/compiled.md): ``"native code: ..."`` with
    the compiled paths, their operations, the compile time and the evaluations each way,
    or ``"interpreted: <why>"``."""
    compile_time: float
    """Seconds spent compiling native code during the run (part of ``wall_time``)."""


@dataclass(frozen=True)
class Impact:
    """One impact of a clearance joint, from the located contact onset to separation.

    Attributes:
        joint: the clearance joint.
        onset_time: time of the contact onset [s].
        onset_speed: penetration rate at onset, the approach speed [m/s; rad/s for a
            revolute joint's play, see :func:`impact_units`].
        peak_force: largest normal force during the contact [N; the stop's torque in N*m
            for a revolute joint's play].
        max_penetration: largest penetration during the contact [m; rad for a revolute
            joint's play].
        duration: time from onset to separation [s]; NaN if still in contact at the end.
    """

    joint: str
    onset_time: float
    onset_speed: float
    peak_force: float
    max_penetration: float
    duration: float

    @classmethod
    def from_dict(cls, joint: str, d: Mapping[str, Any]) -> Impact:
        """From the engine's summary entry (``duration`` null while in contact)."""

        def num(key: str) -> float:
            v = d.get(key)
            return math.nan if v is None else float(v)

        return cls(
            joint,
            num("onset_time"),
            num("onset_speed"),
            num("peak_force"),
            num("max_penetration"),
            num("duration"),
        )


def contact_name(entry: Mapping[str, Any]) -> str:
    """The name of an entry of the engine's impact lists: its joint's, or ``joint.p<i>``
    for point ``i`` of a joint of several contact points (as its channels are named)."""
    point = entry.get("point")
    return str(entry["joint"]) if point is None else f"{entry['joint']}.p{point}"


def _impacts(value: Any) -> dict[str, list[Impact]]:
    """The engine's ``[{joint, point, impacts: [...]}]`` (or a dict name -> list) as a
    dict name -> list of Impact, named by :func:`contact_name`."""
    if isinstance(value, Mapping):
        items = list(value.items())
    else:
        items = [(contact_name(entry), entry.get("impacts", [])) for entry in value or []]
    out: dict[str, list[Impact]] = {}
    for joint, impacts in items:
        out[str(joint)] = [
            i if isinstance(i, Impact) else Impact.from_dict(str(joint), i) for i in impacts
        ]
    return out


_UNITS = {
    "x": "m",
    "y": "m",
    "angle": "rad",
    "vx": "m/s",
    "vy": "m/s",
    "omega": "rad/s",
    "ax": "m/s^2",
    "ay": "m/s^2",
    "alpha": "rad/s^2",
    "fx": "N",
    "fy": "N",
    "force": "N",
    "moment": "N*m",
    "torque": "N*m",
    "kinetic_energy": "J",
    "potential_energy": "J",
    "driver_work": "J",
    "load_work": "J",
    "damper_dissipation": "J",
    "contact_dissipation": "J",
    "friction_dissipation": "J",
    "energy_balance": "J",
    "travel": "m",
    "speed": "m/s",
    # Largest residual over rows that mix lengths and angles.
    "constraint_error": "m or rad",
    "fn": "N",
    "ft": "N",
    "penetration": "m",
    "penetration_rate": "m/s",
    "ex": "m",
    "ey": "m",
    "slip": "m/s",
    # lubricated revolute joints
    "eccentricity_ratio": "",
    "attitude": "rad",
    "film_thickness": "m",
    "film_fx": "N",
    "film_fy": "N",
    "peak_pressure": "Pa",
    "film_mode": "",
    "friction_torque": "N*m",
    # translational clearance joints
    "tilt": "rad",
    "offset": "m",
    # joints with play
    "play_angle": "rad",
    "play_travel": "m",
    # gear pairs
    "mesh": "m",
    "torque_1": "N*m",
    "torque_2": "N*m",
    "stiffness": "N/m^n",
    # spatial models
    "z": "m",
    "vz": "m/s",
    "az": "m/s^2",
    "e0": "",
    "e1": "",
    "e2": "",
    "e3": "",
    "wx": "rad/s",
    "wy": "rad/s",
    "wz": "rad/s",
    "alphax": "rad/s^2",
    "alphay": "rad/s^2",
    "alphaz": "rad/s^2",
    "fz": "N",
    "mx": "N*m",
    "my": "N*m",
    "mz": "N*m",
    "ez": "m",
    "fnx": "N",
    "fny": "N",
    "fnz": "N",
    "ftx": "N",
    "fty": "N",
    "ftz": "N",
    "yaw": "rad",
    "pitch": "rad",
    "roll": "rad",
    "wgx": "rad/s",
    "wgy": "rad/s",
    "wgz": "rad/s",
    "alphagx": "rad/s^2",
    "alphagy": "rad/s^2",
    "alphagz": "rad/s^2",
}


def channel_unit(channel: str, model: Mapping[str, Any] | None = None) -> str:
    """The SI unit of a channel, from its quantity: ``channel_unit("slider.ax") == "m/s^2"``;
    ``""`` when unknown. Given the model (SI dictionary), a joint's channel takes its
    joint type's unit where that differs (a revolute joint's play penetrates in rad) and
    a gear mesh's stiffness its law's exponent (``N/m`` for n = 1)."""
    quantity = channel.rsplit(".", 1)[-1]
    joint = _joint_of(channel, model) if model is not None else None
    if joint is not None:
        special = _JOINT_UNITS.get(str(joint.get("type")), {})
        if quantity in special:
            return special[quantity]
        if quantity == "stiffness" and joint.get("type") == "gear_pair":
            n = float(joint.get("gear", {}).get("normal_law", {}).get("exponent", math.nan))
            return "N/m" if n == 1 else f"N/m^{n:g}" if math.isfinite(n) else "N/m^n"
    return _UNITS.get(quantity, "")


def impact_units(model: Mapping[str, Any], contact: str) -> dict[str, str]:
    """The units of an impact list's columns (``onset_speed``, ``peak_force``,
    ``max_penetration``) for contact ``contact`` (a joint, or ``joint.p<i>``) of ``model``
    (SI dictionary): a revolute joint's play has its onset speed in rad/s, its peak in
    N*m (the stop's torque) and its penetration in rad."""
    joint = _joint_of(f"{contact}.fn", model)
    if joint is not None and joint.get("type") == "revolute_with_play":
        return {"onset_speed": "rad/s", "peak_force": "N*m", "max_penetration": "rad"}
    return {"onset_speed": "m/s", "peak_force": "N", "max_penetration": "m"}


def _joint_of(channel: str, model: Mapping[str, Any]) -> Mapping[str, Any] | None:
    """The joint of ``model`` whose channel ``channel`` is (``joint.q`` or
    ``joint.p<i>.q``), or None."""
    parts = channel.split(".")
    if len(parts) < 2:
        return None
    return next((j for j in model.get("joints", []) if j.get("name") == parts[0]), None)


@dataclass(frozen=True, eq=False)
class Result:
    """The outcome of one run.

    Attributes:
        time: sample times [s].
        channels: channel names, in model order.
        data: samples, one row per channel (``data[k]`` is ``channels[k]``); for a run
            streamed to disk, a :class:`~jointgap._stream.StoredChannels` that reads each
            row from the file when it is asked for.
        stats: run counters (:class:`RunStats`): accepted_steps, rejected_steps,
            rhs_evaluations, jacobian_evaluations, newton_iterations, projections, events,
            method, wall_time [s], profile, compiled, compile_time [s].
        status: ``"finished"``, ``"failed"`` or ``"interrupted"`` (Ctrl-C,
            :data:`RunStatus`); the data of a failed or interrupted run stop where the
            run did.
        message: why and when a failed or interrupted run stopped; ``""`` otherwise.
        warnings: the engine's non-fatal notes.
        model: the model that ran (SI dictionary, :meth:`jointgap.Model.to_dict`).
        options: the run options, every one written out.
        impacts: per clearance joint (in model order), its impacts in time order; see
            :meth:`impacts_frame` for one table.
        clearances: per clearance joint, its contact data as the engine resolved them
            (SI): ``bearing_radius``, ``journal_radius``, ``clearance``, ``stiffness``
            (computed from the materials when the model does not give it), ``exponent``.
        wear: for a run with ``wear_cells``, per clearance_revolute joint the wear it
            accumulated per unit wear coefficient k [1/Pa] (docs/wear.md): ``angles``
            [rad] (the grid's cell centres, 2 pi c / N in each part's body frame),
            ``bearing_depth`` and ``journal_depth`` [Pa m] (int p ds per cell: k times
            it is the worn depth [m]), ``load_distance`` [N m] (int F_n ds),
            ``bearing_volume`` and ``journal_volume`` [N m] (k times them the worn
            volume [m^3]); empty otherwise.
        samples: for a run that recorded every step as well as its rate
            (``every_step=True`` with a ``rate``), the indices of the output samples (at
            ``k / rate`` and the end time) among the records, as the engine marked them;
            ``None`` when every record is an output sample (see :attr:`sample_index`).
        mode_time: per clearance joint, the time [s] it spent in free flight, impact
            and continuous contact (modes 0, 1, 2), summed by the engine over the accepted
            steps: exact at onsets and separations whatever the output rate.
        peaks: per channel, the largest absolute value the engine saw: over the
            records, and over every accepted step when the run asked for
            ``step_peaks`` (an impact's spike can fall between samples).
    """

    time: np.ndarray
    channels: list[str]
    data: np.ndarray
    stats: RunStats = field(default_factory=lambda: RunStats())
    status: RunStatus = "finished"
    message: str = ""
    warnings: list[str] = field(default_factory=list)
    model: dict[str, Any] = field(default_factory=dict)
    options: dict[str, Any] = field(default_factory=dict)
    impacts: dict[str, list[Impact]] = field(default_factory=dict)
    clearances: dict[str, dict[str, float]] = field(default_factory=dict)
    wear: dict[str, dict[str, Any]] = field(default_factory=dict)
    samples: np.ndarray | None = None
    mode_time: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    peaks: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        from ._stream import StoredChannels

        object.__setattr__(self, "impacts", _impacts(self.impacts))
        object.__setattr__(self, "clearances", _clearances(self.clearances))
        object.__setattr__(self, "wear", _wear(self.wear))
        time = _frozen(self.time)
        object.__setattr__(self, "time", time)
        if not isinstance(self.data, StoredChannels):
            data = _frozen(self.data).reshape(len(self.channels), len(time))
            object.__setattr__(self, "data", data)
        object.__setattr__(self, "_index", {name: k for k, name in enumerate(self.channels)})
        if self.samples is not None:
            samples = np.array(self.samples, dtype=np.int64).reshape(-1)
            samples.flags.writeable = False
            object.__setattr__(self, "samples", samples)
        peaks = (
            self.peaks
            if isinstance(self.peaks, Mapping)
            else dict(zip(self.channels, self.peaks, strict=True))
        )
        object.__setattr__(self, "peaks", {str(k): float(v) for k, v in peaks.items()})
        mode_time = {str(j): tuple(float(x) for x in v) for j, v in self.mode_time.items()}
        object.__setattr__(self, "mode_time", mode_time)

    @property
    def sample_index(self) -> np.ndarray:
        """Indices of the output samples among the records: :attr:`samples` for a run
        that recorded every step as well as its rate, else every record (the samples
        at the rate, or without a rate the steps)."""
        if self.samples is not None:
            return self.samples
        return np.arange(len(self.time))

    @property
    def ok(self) -> bool:
        """True when the run reached its end time."""
        return self.status == "finished"

    @property
    def interrupted(self) -> bool:
        """True when Ctrl-C stopped the run (its data stop where it did)."""
        return self.status == "interrupted"

    def __getitem__(self, channel: str) -> np.ndarray:
        """The samples of one channel (read-only); KeyError lists close matches."""
        k = self._index.get(channel)  # type: ignore[attr-defined]
        if k is None:
            require_channel(self.channels, channel)
        row: np.ndarray = self.data[k]
        return row

    def __contains__(self, channel: object) -> bool:
        return channel in self._index  # type: ignore[attr-defined]

    def __repr__(self) -> str:
        span = f"t = 0..{self.time[-1]:g} s" if len(self.time) else "no samples"
        tail = "" if self.ok else f", {self.message}"
        return (
            f"<Result {self.model.get('name', '')!r}: {self.status}, {len(self.time)} samples, "
            f"{span}, {len(self.channels)} channels{tail}>"
        )

    def run_arguments(self) -> dict[str, Any]:
        """The options as keyword arguments of :meth:`jointgap.Model.simulate`."""
        return dict(self.options)

    # ------------------------------------------------------------------ spatial bodies

    def euler_angles(self, body: str, convention: str = "ZYX") -> np.ndarray:
        """A spatial body's orientation as Euler angles [rad], one row ``(a, b, c)`` per
        sample: intrinsic turns about the axes ``convention`` names (``R = R1(a) R2(b)
        R3(c)``, the model file's convention; ``ZYX`` is yaw, pitch, roll), of the frame
        whose quaternion the channels ``<body>.e0 .. e3`` give (the body's principal
        frame). Computed by SciPy's ``Rotation`` from the quaternion."""
        convention = str(convention)
        if len(convention) != 3 or not set(convention) <= set("XYZ"):
            raise ValueError(
                f"convention {convention!r}: three of X, Y, Z, e.g. 'ZYX' (intrinsic turns)"
            )
        angles: np.ndarray = self._rotation(body).as_euler(convention)
        return angles

    def angular_velocity(self, body: str, frame: str = "ground") -> np.ndarray:
        """A spatial body's angular velocity [rad/s], one row ``(wx, wy, wz)`` per
        sample, in global axes (``frame="ground"``: the engine's channels ``<body>.wgx
        .wgy .wgz``) or in the axes of its principal frame (``frame="body"``: the
        channels ``<body>.wx .wy .wz``)."""
        if frame not in ("ground", "body"):
            raise ValueError(f"frame {frame!r}: 'ground' or 'body'")
        names = "wx wy wz" if frame == "body" else "wgx wgy wgz"
        return np.stack([self[f"{body}.{q}"] for q in names.split()], axis=1)

    def _rotation(self, body: str) -> Any:
        """SciPy's ``Rotation`` of a body's samples, from ``<body>.e0 .. e3`` (scalar
        first; SciPy takes the scalar last)."""
        from scipy.spatial.transform import Rotation  # type: ignore[import-untyped]

        q = np.stack([self[f"{body}.e{k}"] for k in (1, 2, 3, 0)], axis=1)
        return Rotation.from_quat(q)

    # ------------------------------------------------------------------ export

    def to_pandas(self) -> pd.DataFrame:
        """A DataFrame with a ``time`` column first, then the channels in model order."""
        import pandas as pd

        columns = {"time": self.time, **{c: self.data[k] for k, c in enumerate(self.channels)}}
        return pd.DataFrame(columns)

    def to_csv(self, path: str | PathLike[str], progress: WriteProgress | None = None) -> None:
        """Writes ``time`` then every channel, one row per sample, shortest exact floats
        (each reads back to the same double), with pyarrow's CSV writer in blocks of
        :data:`CSV_BLOCK` rows: a 60 s run of the founding case at 10 kHz took 21 s in
        Python's csv module. ``progress(rows_written, rows)`` is called after each block."""
        import pyarrow as pa
        import pyarrow.csv as pa_csv

        from ._stream import arrow_column

        names = ["time", *self.channels]
        schema = pa.schema([(name, pa.float64()) for name in names])
        # The header as the channels are named, unquoted (pyarrow quotes every name).
        options = pa_csv.WriteOptions(include_header=False, quoting_style="none")
        rows = len(self.time)
        with open(path, "wb") as f, pa_csv.CSVWriter(f, schema, write_options=options) as writer:
            f.write((",".join(names) + "\n").encode())
            for start in range(0, rows, CSV_BLOCK):
                block = slice(start, min(rows, start + CSV_BLOCK))
                columns = [arrow_column(self.time[block])]
                columns += [arrow_column(self.data[k][block]) for k in range(len(self.channels))]
                writer.write_batch(pa.RecordBatch.from_arrays(columns, schema=schema))
                if progress is not None:
                    progress(block.stop, rows)

    def impacts_frame(self) -> pd.DataFrame:
        """Every impact of every clearance joint, one row each, columns ``joint,
        onset_time, onset_speed, peak_force, max_penetration, duration`` (SI)."""
        import pandas as pd

        rows = [
            [getattr(i, c) for c in IMPACT_COLUMNS] for lst in self.impacts.values() for i in lst
        ]
        return pd.DataFrame(rows, columns=list(IMPACT_COLUMNS))

    def impacts_to_csv(self, path: str | PathLike[str]) -> None:
        """Writes :meth:`impacts_frame` as CSV, shortest exact floats."""
        with open(path, "w", newline="") as f:
            writer = csv.writer(f, lineterminator="\n")
            writer.writerow(IMPACT_COLUMNS)
            for lst in self.impacts.values():
                for i in lst:
                    writer.writerow([i.joint, *(repr(getattr(i, c)) for c in IMPACT_COLUMNS[1:])])

    def summary(self) -> dict[str, Any]:
        """What ``summary.json`` holds: model, options, stats, status, message, warnings."""
        return {
            "model": self.model,
            "options": self.options,
            "stats": self.stats,
            "status": self.status,
            "message": self.message,
            "warnings": self.warnings,
            "channels": self.channels,
            "clearances": self.clearances,
            "wear": {
                joint: {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in w.items()}
                for joint, w in self.wear.items()
            },
            "mode_time": self.mode_time,
            "peaks": self.peaks,
            "samples": None if self.samples is None else self.samples.tolist(),
        }

    @property
    def stored(self) -> Path | None:
        """The Parquet file of a result streamed to disk; ``None`` when held in memory."""
        from ._stream import StoredChannels

        return self.data.path if isinstance(self.data, StoredChannels) else None

    def save(self, directory: str | PathLike[str], progress: WriteProgress | None = None) -> Path:
        """Writes ``results.csv`` (``results.parquet`` for a streamed result) and
        ``summary.json`` into ``directory`` (created), and ``impacts.csv`` when the model
        has clearance joints. ``progress`` as in :meth:`to_csv`."""
        import shutil

        out = Path(directory)
        out.mkdir(parents=True, exist_ok=True)
        stored = self.stored
        if stored is None:
            self.to_csv(out / RESULTS_CSV, progress)
        elif stored.resolve() != (out / RESULTS_PARQUET).resolve():
            shutil.copyfile(stored, out / RESULTS_PARQUET)
        if self.impacts:
            self.impacts_to_csv(out / IMPACTS_CSV)
        with open(out / SUMMARY_JSON, "w") as f:
            json.dump(_jsonable(self.summary()), f, indent=2)
            f.write("\n")
        return out

    @classmethod
    def load(cls, directory: str | PathLike[str]) -> Result:
        """Reads a result written by :meth:`save` (a streamed one stays on disk)."""
        from ._stream import StoredChannels, read_time

        folder = Path(directory)
        with open(folder / SUMMARY_JSON) as f:
            summary = json.load(f)
        data: Any
        if (folder / RESULTS_PARQUET).exists():
            time = read_time(folder / RESULTS_PARQUET)
            channels = list(summary.get("channels", []))
            data = StoredChannels(folder / RESULTS_PARQUET, channels, len(time))
        else:
            time, channels, data = _read_results_csv(folder / RESULTS_CSV)
        impacts: dict[str, list[Impact]] = {
            j["name"]: []
            for j in summary.get("model", {}).get("joints", [])
            if j.get("type") in CLEARANCE_TYPES and j.get("type") not in MULTI_POINT_TYPES
        }
        if (folder / IMPACTS_CSV).exists():
            with open(folder / IMPACTS_CSV, newline="") as f:
                for row in csv.DictReader(f):
                    impact = Impact(row["joint"], *(float(row[c]) for c in IMPACT_COLUMNS[1:]))
                    impacts.setdefault(impact.joint, []).append(impact)
        return cls(
            time=time,
            channels=channels,
            data=data,
            stats=summary.get("stats", {}),
            status=summary.get("status", "finished"),
            message=summary.get("message", ""),
            warnings=summary.get("warnings", []),
            model=summary.get("model", {}),
            options=summary.get("options", {}),
            impacts=impacts,
            clearances=summary.get("clearances", {}),
            wear=summary.get("wear", {}),
            samples=summary.get("samples"),
            mode_time=summary.get("mode_time", {}),
            peaks=summary.get("peaks", {}),
        )


def _read_results_csv(path: Path) -> tuple[np.ndarray, list[str], np.ndarray]:
    """``(time, channels, data[n_channels, n_samples])`` of a ``results.csv``, parsed in
    bulk by pyarrow into one float64 array per column (a list of Python floats per value
    took 3.2 times the file's size: 7.8 GB for a 60 s run)."""
    import pyarrow as pa
    import pyarrow.csv as pa_csv

    from ._stream import numpy_column

    with open(path, newline="") as f:
        header = next(csv.reader(f), [])
    if header[:1] != ["time"]:
        raise ValueError(f"{path}: the first column must be 'time'")
    try:
        table = pa_csv.read_csv(
            path,
            convert_options=pa_csv.ConvertOptions(
                column_types={name: pa.float64() for name in header}
            ),
        )
    except pa.ArrowInvalid as exc:
        raise ValueError(f"{path}: {exc}") from None
    values = np.empty((len(header), table.num_rows))
    for k in range(len(header)):
        at = 0
        for chunk in table.column(k).chunks:
            values[k, at : at + len(chunk)] = numpy_column(chunk)
            at += len(chunk)
    values.flags.writeable = False
    return values[0], header[1:], values[1:]


def _frozen(values: Any) -> np.ndarray:
    """A read-only float64 array of ``values``: the array itself when it already is one
    (a long run's samples are not copied again), else a frozen copy."""
    if isinstance(values, np.ndarray) and values.dtype == np.float64 and not values.flags.writeable:
        return values
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


def require_channel(channels: Sequence[str], channel: str) -> None:
    """KeyError naming ``channel`` and its close matches when ``channels`` lacks it: for
    checking a channel before a run as a result's lookup does after it."""
    if channel in channels:
        return
    close = difflib.get_close_matches(channel, channels, n=6, cutoff=0.6)
    element = channel.split(".", 1)[0]
    close += [c for c in channels if c.split(".", 1)[0] == element and c not in close]
    if close:
        raise KeyError(f"no channel '{channel}'; close matches: {', '.join(close[:8])}")
    raise KeyError(f"no channel '{channel}' ({len(channels)} channels, see Result.channels)")


def model_channels(model: Mapping[str, Any]) -> list[str]:
    """Every channel a run of ``model`` (SI dictionary, :meth:`jointgap.Model.to_dict`)
    records by default, in model order, named by the engine without a run: for choosing
    what a run records (``simulate(channels=...)``) before it starts."""
    from . import _jointgap

    return _jointgap.channel_names(json.dumps(model))


def guided_bodies(result: Result) -> list[tuple[str, str]]:
    """``(body, "x", "y" or "z")`` for every body on a prismatic joint (with or without
    play, or in a guide with clearance), the coordinate being the one closest to the
    guide's axis (``("slider", "x")`` in a slider-crank)."""
    out: list[tuple[str, str]] = []
    for joint in result.model.get("joints", []):
        if joint.get("type") not in ("prismatic", "prismatic_with_play", "clearance_translational"):
            continue
        body = joint["body_j"] if joint["body_j"] != "ground" else joint["body_i"]
        axis = [abs(float(v)) for v in joint.get("axis") or (1.0, 0.0)]
        pair = (str(body), "xyz"[axis.index(max(axis))])  # the first of equal ones
        if pair not in out:
            out.append(pair)
    return out


def slider_channels(result: Result) -> list[str]:
    """Position, velocity and acceleration along its guide of every body on a prismatic
    joint (``slider.x``, ``slider.vx``, ``slider.ax`` in a slider-crank), those recorded."""
    chosen = [f"{b}.{q}{c}" for b, c in guided_bodies(result) for q in ("", "v", "a")]
    return [c for c in chosen if c in result]


def clearance_joints(result: Result) -> list[str]:
    """The clearance joints of a result in model order, named as their impact lists
    are (a joint of several contact points by its points, ``joint.p1``, ...; then any
    others that only the impact list names, for a result built without its model)."""
    names = []
    for joint in result.model.get("joints", []):
        if joint.get("type") in CLEARANCE_TYPES:
            # a joint of several contact points (cylindrical) by its points, p1, p2, ...
            points = [c for c in result.impacts if c.startswith(f"{joint['name']}.p")]
            names += points or [str(joint["name"])]
    return names + [j for j in result.impacts if j not in names]


def effort_channels(result: Result) -> list[str]:
    """Every driver's torque or force channel, those recorded."""
    drivers = result.model.get("drivers", [])
    chosen = [f"{d['name']}.{q}" for d in drivers for q in ("torque", "force")]
    return [c for c in chosen if c in result]


def main_channels(result: Result) -> list[str]:
    """The channels worth a glance: slider motion along the guide, driver efforts (or,
    without a slider or driver, the first bodies' angles and speeds), and the
    constraint error."""
    chosen = slider_channels(result) + effort_channels(result)
    if not chosen:
        for body in result.model.get("bodies", [])[:3]:
            chosen += [f"{body['name']}.angle", f"{body['name']}.omega"]
    chosen.append("system.constraint_error")
    return [c for c in dict.fromkeys(chosen) if c in result]


def _clearances(value: Any) -> dict[str, dict[str, float]]:
    """The engine's list of ``{"joint": .., ...}`` (or a saved dict) keyed by joint."""
    if isinstance(value, Mapping):
        return {str(k): {q: float(x) for q, x in v.items()} for k, v in value.items()}
    return {str(d["joint"]): {q: float(x) for q, x in d.items() if q != "joint"} for d in value}


WEAR_ARRAYS = ("angles", "bearing_depth", "journal_depth")
"""The arrays of a joint's wear in :attr:`Result.wear`; its other entries are floats."""


def _wear(value: Any) -> dict[str, dict[str, Any]]:
    """The engine's list of ``{"joint": .., ...}`` (or a saved dict) keyed by joint, its
    grids as frozen float arrays."""
    items = value.items() if isinstance(value, Mapping) else ((d["joint"], d) for d in value)
    return {
        str(joint): {
            k: _frozen(v) if k in WEAR_ARRAYS else float(v) for k, v in w.items() if k != "joint"
        }
        for joint, w in items
    }


def _jsonable(value: Any) -> Any:
    """NaN and infinities as strings so that summary.json stays strict JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    if isinstance(value, Mapping):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value
