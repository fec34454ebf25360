"""The report's tables as plain data: a title, column labels and rows of numbers or
text; the page formats numbers, sorts where asked and seeks the animation to a row's
time where a column holds one."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..results import Result, channel_unit, clearance_joints, impact_units
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
    types = {str(j.get("name")): str(j.get("type")) for j in model.get("joints", [])}
    for joint in dict.fromkeys([*clearance_joints(result), *result.clearances]):
        data = result.clearances.get(joint)
        if not data:
            continue
        items.append((f"{joint}", _contact_data(types.get(joint, ""), data)))
    return key_value_table("model", "Model", items)


def _contact_data(type_: str, data: Mapping[str, float]) -> str:
    """A contact joint's resolved data in words, as its type reads the engine's radii
    and clearance: a block's half gap in its guide, half a play, half a gear mesh's
    backlash along the line of action."""
    mm = {k: 1e3 * float(data[k]) for k in ("clearance", "bearing_radius", "journal_radius")}
    k, n = float(data["stiffness"]), float(data["exponent"])
    if type_ == "clearance_translational":
        return (
            f"half gap {mm['clearance']:.4g} mm, guide half-width {mm['bearing_radius']:.4g} "
            f"mm, block half-height {mm['journal_radius']:.4g} mm, K {k:.4g} N/m^{n:g}"
        )
    if type_ == "revolute_with_play":
        half = math.degrees(float(data["clearance"]))
        return f"half play {half:.4g} deg, K {k:.4g} N*m/rad^{n:g}"
    if type_ == "prismatic_with_play":
        return f"half play {mm['clearance']:.4g} mm, K {k:.4g} N/m^{n:g}"
    if type_ == "gear_pair":
        return (
            f"pitch radii {mm['bearing_radius']:.4g} and {mm['journal_radius']:.4g} mm, half "
            f"backlash along the line of action {1e3 * mm['clearance']:.4g} µm, K {k:.4g} "
            f"N/m^{n:g}"
        )
    return (
        f"clearance {mm['clearance']:.4g} mm, bearing radius {mm['bearing_radius']:.4g} mm, "
        f"journal radius {mm['journal_radius']:.4g} mm, K {k:.4g} N/m^{n:g}"
    )


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


def _units(contacts: Sequence[str], model: Mapping[str, Any] | None) -> list[str] | None:
    """Per contact, the units of its onset speed, peak and penetration (µ-scaled) where
    some contact's differ from m/s, N and µm (a revolute joint's play: rad/s, N*m, µrad),
    else None: the columns' titles then say them."""
    if model is None:
        return None
    units = [impact_units(model, c) for c in contacts]
    if all(u["onset_speed"] == "m/s" for u in units):
        return None
    return [f"{u['onset_speed']}, {u['peak_force']}, µ{u['max_penetration']}" for u in units]


def _with_units(
    columns: list[str], rows: list[list[Any]], units: list[str] | None
) -> tuple[list[str], list[list[Any]]]:
    """A "units" column after the first where :func:`_units` gives one, the columns'
    units then named as alternatives."""
    if units is None:
        return columns, rows
    alternatives = {
        "[m/s]": "[m/s or rad/s]",
        "[N]": "[N or N*m]",
        "[µm]": "[µm or µrad]",
    }
    named = []
    for c in columns:
        for a, b in alternatives.items():
            c = c.replace(a, b)
        named.append(c)
    return (
        [named[0], "units", *named[1:]],
        [[r[0], u, *r[1:]] for r, u in zip(rows, units, strict=True)],
    )


def contact_table(
    stats: Sequence[ContactStatistics], model: Mapping[str, Any] | None = None
) -> Table:
    """One row per clearance joint (:func:`jointgap.statistics.contact_statistics`); with
    the model, a joint whose contact turns (a revolute joint's play) has its units said
    in a column of their own."""
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
    columns, rows = _with_units(columns, rows, _units([s.joint for s in stats], model))
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
    units = _units([str(r[0]) for r in rows], result.model)
    columns, rows = _with_units(columns, rows, units)
    seek = 2 if units is None else 3
    return Table("impacts", "Impacts", columns, rows, seek=seek, sortable=True, note=note)


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


def channel_label(channel: str, model: Mapping[str, Any] | None = None) -> str:
    """``slider.ax [m/s^2]``; with the model, in its joint type's unit
    (:func:`jointgap.results.channel_unit`)."""
    unit = channel_unit(channel, model)
    return f"{channel} [{unit}]" if unit else channel


def mapping_rows(d: Mapping[str, Any]) -> list[tuple[str, Any]]:
    return [(str(k), _text(v)) for k, v in d.items()]
