"""The report's tables as plain data: a title, column labels and rows of numbers or
text; the page formats numbers, sorts where asked and seeks the animation to a row's
time where a column holds one."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..results import Result, channel_unit, clearance_joints
from ..statistics import ContactStatistics, Deviation
from .encode import strict

__all__ = [
    "Table",
    "key_value_table",
    "model_table",
    "options_table",
    "run_statistics_table",
    "contact_table",
    "impact_table",
    "deviation_table",
]


@dataclass(frozen=True)
class Table:
    """One table of the report.

    Attributes:
        id: the HTML id (``impacts``, ``contact-statistics``...).
        title: the heading above it.
        columns: column labels, units in brackets.
        rows: one list of cells per row: numbers (formatted by the page) or text.
        seek: index of a column of times [s]: clicking a row moves the animation there.
        sortable: clicking a heading sorts by that column.
        note: a line under the title.
    """

    id: str
    title: str
    columns: list[str]
    rows: list[list[Any]]
    seek: int | None = None
    sortable: bool = False
    note: str = ""
    row_classes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = strict(
            {
                "id": self.id,
                "title": self.title,
                "columns": self.columns,
                "rows": self.rows,
                "seek": self.seek,
                "sortable": self.sortable,
                "note": self.note,
                "row_classes": self.row_classes,
            }
        )
        return d


def key_value_table(id: str, title: str, items: Iterable[tuple[str, Any]]) -> Table:
    """Two columns: what, value (None shown as '-')."""
    return Table(id, title, ["", ""], [[k, "-" if v is None else v] for k, v in items])


def model_table(result: Result, source: str | None = None) -> Table:
    """Name, file, element counts and each clearance joint's resolved contact data."""
    model = result.model
    items: list[tuple[str, Any]] = [("name", model.get("name") or "-")]
    if source:
        items.append(("file", source))
    for kind in ("bodies", "joints", "drivers", "forces"):
        names = [str(e.get("name")) for e in model.get(kind, [])]
        items.append((kind, f"{len(names)}: {', '.join(names)}" if names else "0"))
    g = model.get("gravity")
    if g is not None:
        items.append(("gravity [m/s^2]", "(" + ", ".join(f"{float(x):g}" for x in g) + ")"))
    # A spatial joint of several contact points is listed by its name, not its points'.
    for joint in dict.fromkeys([*clearance_joints(result), *result.clearances]):
        data = result.clearances.get(joint)
        if not data:
            continue
        items.append(
            (
                f"{joint}",
                f"clearance {1e3 * data['clearance']:.4g} mm, bearing radius "
                f"{1e3 * data['bearing_radius']:.4g} mm, journal radius "
                f"{1e3 * data['journal_radius']:.4g} mm, K {data['stiffness']:.4g} N/m^"
                f"{data['exponent']:g}",
            )
        )
    return key_value_table("model", "Model", items)


def options_table(result: Result) -> Table:
    """Every run option as the result records it."""
    return key_value_table(
        "options", "Options", [(str(k), _text(v)) for k, v in result.options.items()]
    )


def run_statistics_table(result: Result) -> Table:
    """Status, samples and the engine's counters."""
    items: list[tuple[str, Any]] = [("status", result.status)]
    if result.message:
        items.append(("message", result.message))
    span = f"0..{result.time[-1]:g} s" if len(result.time) else "-"
    items.append(("samples", f"{len(result.time)} ({span})"))
    names = {"wall_time": "wall time [s]"}
    for k, v in result.stats.items():
        items.append((names.get(k, k.replace("_", " ")), v))
    for w in result.warnings:
        items.append(("warning", w))
    return key_value_table("run-statistics", "Run statistics", items)


def _text(v: Any) -> Any:
    if isinstance(v, (list, tuple)):
        return ", ".join(str(x) for x in v)
    if isinstance(v, bool):
        return "yes" if v else "no"
    return v


def contact_table(stats: Sequence[ContactStatistics]) -> Table:
    """One row per clearance joint (:func:`jointgap.statistics.contact_statistics`)."""
    columns = [
        "joint",
        "impacts",
        "free flight [%]",
        "impact [%]",
        "contact [%]",
        "peak force [N]",
        "max penetration [µm]",
        "onset speed mean [m/s]",
        "onset speed max [m/s]",
    ]
    rows = [
        [
            s.joint,
            s.impacts,
            100.0 * s.free_flight,
            100.0 * s.impact,
            100.0 * s.contact,
            s.peak_force,
            1e6 * s.max_penetration,
            s.onset_speed_mean,
            s.onset_speed_max,
        ]
        for s in stats
    ]
    note = (
        ""
        if all(s.complete for s in stats)
        else "the run failed: statistics up to where it stopped"
    )
    return Table("contact-statistics", "Contact statistics", columns, rows, note=note)


def impact_table(result: Result) -> Table:
    """Every impact of every clearance joint, in joint then time order; a row click
    moves the animation to the onset."""
    columns = [
        "joint",
        "#",
        "onset time [s]",
        "onset speed [m/s]",
        "peak force [N]",
        "max penetration [µm]",
        "duration [ms]",
    ]
    rows = []
    for joint, impacts in result.impacts.items():
        for k, i in enumerate(impacts, 1):
            rows.append(
                [
                    joint,
                    k,
                    i.onset_time,
                    i.onset_speed,
                    i.peak_force,
                    1e6 * i.max_penetration,
                    1e3 * i.duration,
                ]
            )
    total = sum(len(v) for v in result.impacts.values())
    per = ", ".join(f"{j}: {len(v)}" for j, v in result.impacts.items())
    note = f"{total} impacts ({per}); click a row to see it" if total else "no impacts"
    return Table("impacts", "Impacts", columns, rows, seek=2, sortable=True, note=note)


def deviation_table(deviations: Sequence[Deviation]) -> Table:
    """RMS and peak of the clearance run less the ideal one, per channel."""
    columns = ["channel", "unit", "RMS", "RMS [% of ideal range]", "peak", "peak [%]", "at t [s]"]
    rows = [
        [
            d.channel,
            d.unit,
            d.rms,
            100.0 * d.rms_relative,
            d.peak,
            100.0 * d.peak_relative,
            d.peak_time,
        ]
        for d in deviations
    ]
    return Table("deviation", "Deviation from the ideal run", columns, rows, seek=6)


def channel_label(channel: str) -> str:
    """``slider.ax [m/s^2]``."""
    unit = channel_unit(channel)
    return f"{channel} [{unit}]" if unit else channel


def mapping_rows(d: Mapping[str, Any]) -> list[tuple[str, Any]]:
    return [(str(k), _text(v)) for k, v in d.items()]
