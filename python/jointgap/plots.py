"""The paper's figures of a result (matplotlib, no display needed).

One function per figure, each returning a :class:`matplotlib.figure.Figure` built
without pyplot, so no display is needed and no global matplotlib state changes:

* :func:`time_series_figure`: any channel against time;
* :func:`slider_figures`: slider displacement [mm], velocity [m/s], acceleration [m/s^2];
* :func:`torque_figures`: the torque [N m] of every motor (driver);
* :func:`contact_force_figure`: the normal contact force [N] of a clearance joint;
* :func:`orbit_figure`: the journal centre inside the clearance circle [mm], equal axes;
* :func:`figure`: the overview, every time series above in one figure (for a mechanism
  without a slider: the bodies' positions and angles).

Time series accept one result or several, overlaid with a legend: an ideal run and a
clearance run are labelled ``"ideal"`` and ``"clearance"`` unless ``labels`` says
otherwise, the ideal one drawn as a black dashed line on top of the clearance one. For an
ideal run the contact force figure shows the magnitude of that joint's reaction force.
A failed run is marked where it stopped (red dotted line, or a red cross on the orbit).

:func:`figure_set` builds every figure of a result under a stable name, and
:func:`save_figure_set` writes them (``figure``, ``slider_displacement``,
``slider_velocity``, ``slider_acceleration``, ``motor_torque``,
``contact_force_<joint>``, ``orbit_<joint>``) as PNG (200 dpi), SVG or PDF. Sizes suit a
paper: single figures 3.5 in wide (one column), the overview 7 in (two columns), every
text 9 pt; saved SVG and PDF carry no date, so reruns give identical files.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import matplotlib as mpl
import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.lines import Line2D
from matplotlib.patches import Circle
from matplotlib.textpath import text_to_path

from .results import (
    Result,
    channel_unit,
    clearance_joints,
    effort_channels,
    guided_bodies,
)

if TYPE_CHECKING:
    from .comparison import Comparison

__all__ = [
    "FIGURE_FORMATS",
    "PNG_DPI",
    "MODE_NAMES",
    "clearance_joints",
    "radial_clearance",
    "resolved_clearance",
    "time_series_figure",
    "slider_figures",
    "torque_figures",
    "contact_force_figure",
    "orbit_figure",
    "comparison_figure",
    "figure",
    "figure_set",
    "save_figures",
    "save_figure",
    "save_figure_set",
]

FIGURE_FORMATS = ("png", "svg")
"""Formats written by default; ``"pdf"`` may be asked for as well."""
PNG_DPI = 200
"""Resolution of saved PNG files [dots per inch]."""
MODE_NAMES = {0: "free flight", 1: "impact", 2: "continuous contact"}
"""The values of a clearance joint's ``<joint>.mode`` channel."""

_FORMATS = ("png", "svg", "pdf")
_FONT_SIZE = 9.0  # [pt], at the saved size
_SINGLE = (3.5, 2.6)  # one paper column [in]
_ORBIT = (3.5, 3.9)
_WIDE = 7.0  # two paper columns [in]
_PANEL_HEIGHT = 1.7  # [in]
_RC: dict[Any, Any] = {  # keys: matplotlib rcParams
    "font.size": _FONT_SIZE,
    "axes.titlesize": _FONT_SIZE,
    "axes.labelsize": _FONT_SIZE,
    "xtick.labelsize": _FONT_SIZE,
    "ytick.labelsize": _FONT_SIZE,
    "legend.fontsize": _FONT_SIZE,
    "figure.titlesize": _FONT_SIZE + 1,
    "axes.linewidth": 0.6,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "lines.linewidth": 0.7,
    "legend.frameon": False,
    "svg.hashsalt": "jointgap",  # stable element ids: identical files on reruns
    "pdf.fonttype": 42,  # TrueType, not Type 3: what journals ask for
}
_MODE_COLOURS = {0: "tab:blue", 1: "tab:red", 2: "tab:green"}


@contextmanager
def _style() -> Iterator[None]:
    """Paper style while figures are built and saved; global rcParams are restored."""
    with mpl.rc_context(_RC):
        yield


# ------------------------------------------------------------------ model queries


def radial_clearance(result: Result, joint: str) -> float:
    """The radial clearance c of a clearance joint [m], as the engine resolved it
    (:func:`resolved_clearance`)."""
    return float(resolved_clearance(result, joint)["clearance"])


def resolved_clearance(result: Result, joint: str) -> dict[str, Any]:
    """A clearance joint's contact data as the engine resolved them (radii, clearance,
    stiffness, exponent): the run's, or, for a result saved without them, the engine's
    resolution of the result's model (:meth:`jointgap.Model.clearance_data`)."""
    if joint in result.clearances:
        return dict(result.clearances[joint])
    from .model import Model

    resolved = Model.from_dict(result.model).clearance_data()
    if joint not in resolved:
        raise ValueError(f"no clearance joint '{joint}' in the model of the result")
    return resolved[joint]


def _bearing_body(result: Result, joint: str) -> str:
    for j in result.model.get("joints", []):
        if j.get("name") == joint:
            return str(j.get("body_i", ""))
    return ""


def _torque_channels(result: Result) -> list[str]:
    return [c for c in effort_channels(result) if c.endswith(".torque")]


# ------------------------------------------------------------------ runs and series

Getter = Callable[[Result], np.ndarray | None]
"""The values of one plotted quantity of a result, in plotted units; None if absent."""


@dataclass(frozen=True)
class _Run:
    result: Result
    label: str
    style: dict[str, Any]


def _as_list(results: Result | Sequence[Result]) -> list[Result]:
    out = [results] if isinstance(results, Result) else list(results)
    if not out:
        raise ValueError("no result to plot")
    return out


def _runs(results: Result | Sequence[Result], labels: Sequence[str] | None) -> list[_Run]:
    """Each result with its legend label and line style: an ideal run next to a
    clearance run is black, dashed and on top; the others take the colour cycle."""
    rs = _as_list(results)
    with_clearance = [bool(clearance_joints(r)) for r in rs]
    if labels is not None:
        names = [str(label) for label in labels]
        if len(names) != len(rs):
            raise ValueError(f"{len(names)} labels for {len(rs)} results")
    else:
        names = ["clearance" if c else "ideal" for c in with_clearance]
        if len(set(names)) < len(names):
            names = [str(r.model.get("name") or f"result {k + 1}") for k, r in enumerate(rs)]
        if len(set(names)) < len(names):
            names = [f"{n} #{k + 1}" for k, n in enumerate(names)]
    mixed = any(with_clearance) and not all(with_clearance)
    runs, colour = [], 0
    for r, name, clear in zip(rs, names, with_clearance, strict=True):
        if mixed and not clear:
            style = {"color": "black", "linestyle": "--", "linewidth": 0.9, "zorder": 3}
        else:
            style = {"color": f"C{colour}", "linewidth": 0.7, "zorder": 2}
            colour += 1
        runs.append(_Run(r, name, style))
    return runs


def _channel(channel: str, scale: float = 1.0) -> Getter:
    def get(result: Result) -> np.ndarray | None:
        return scale * result[channel] if channel in result else None

    return get


def _contact_force(joint: str) -> Getter:
    """The normal contact force of a clearance joint, or the magnitude of the reaction
    force of the ideal joint of that name [N]."""

    def get(result: Result) -> np.ndarray | None:
        if f"{joint}.fn" in result:
            return result[f"{joint}.fn"]
        if f"{joint}.fx" in result and f"{joint}.fy" in result:
            magnitude: np.ndarray = np.hypot(result[f"{joint}.fx"], result[f"{joint}.fy"])
            return magnitude
        return None

    return get


def _unit_text(unit: str) -> str:
    return unit.replace("^2", "$^2$").replace("*", " ")


def _default_label(channel: str) -> str:
    unit = channel_unit(channel)
    return f"{channel} [{_unit_text(unit)}]" if unit else channel


# ------------------------------------------------------------------ drawing helpers

Panel = tuple[str, list[tuple[str, Getter]]]
"""A y label and the (name, values) lines of one set of axes."""


def _finish_axes(ax: Axes) -> None:
    ax.grid(True, linewidth=0.3, alpha=0.6)
    ax.tick_params(labelsize=_FONT_SIZE)  # kept for ticks made at a later draw too
    ax.margins(x=0.0)


def _plot_panel(ax: Axes, runs: Sequence[_Run], panel: Panel) -> int:
    """Draws the lines of a panel for every run; returns how many lines it drew."""
    ylabel, lines = panel
    drawn = 0
    for run in runs:
        for k, (name, get) in enumerate(lines):
            values = get(run.result)
            if values is None:
                continue
            if len(lines) == 1:
                label = run.label
            elif len(runs) == 1:
                label = name
            else:
                label = f"{name} ({run.label})"
            # Several lines (bodies, drivers): colour by line, line style by run.
            style = run.style if len(lines) == 1 else {**run.style, "color": f"C{k}"}
            line = ax.plot(run.result.time, values, label=label, **style)[0]
            line.set_in_layout(False)  # clipped to the axes: no need to measure it
            drawn += 1
    ax.set_ylabel(ylabel)
    _finish_axes(ax)
    return drawn


def _mark_failures(ax: Axes, runs: Sequence[_Run]) -> None:
    for run in runs:
        r = run.result
        if not r.ok and len(r.time):
            t = float(r.time[-1])
            prefix = f"{run.label} " if len(runs) > 1 else ""
            ax.axvline(
                t,
                color="red",
                linestyle=":",
                linewidth=0.9,
                label=f"{prefix}failed, t = {t:.4g} s",
                zorder=4,
            )


def _legend(
    fig: Figure,
    ax: Axes,
    loc: Literal["outside upper center", "outside lower center"] = "outside upper center",
) -> None:
    """One legend outside the axes (never over the data) when there is more than one line."""
    handles, labels = ax.get_legend_handles_labels()
    if len(handles) > 1:
        fig.legend(handles, labels, loc=loc, ncols=_legend_columns(fig, labels))


def _legend_columns(
    fig: Figure, labels: Sequence[str], most: int = 3, handle: float = 2.0, spacing: float = 2.0
) -> int:
    """The most legend columns (up to ``most``) whose entries fit the figure's width, from
    the labels' widths at 9 pt and the handle length, text pad (0.8) and column spacing in
    font sizes (matplotlib fills the columns one after the other)."""
    font = FontProperties(size=_FONT_SIZE)
    widths = [
        text_to_path.get_text_width_height_descent(x, font, ismath=False)[0] / 72.0 for x in labels
    ]
    pad = (handle + 0.8 + spacing) * _FONT_SIZE / 72.0  # [in]
    for n in range(min(most, len(labels)), 1, -1):
        rows = -(-len(labels) // n)
        width = sum(pad + max(widths[k * rows : (k + 1) * rows], default=0.0) for k in range(n))
        if width <= fig.get_figwidth() - 0.1:
            return n
    return 1


def _series_figure(runs: Sequence[_Run], panel: Panel, title: str | None = None) -> Figure:
    with _style():
        fig = Figure(figsize=_SINGLE, layout="constrained")
        ax = fig.add_subplot()
        if _plot_panel(ax, runs, panel) == 0:
            raise ValueError(f"no result holds the values of '{panel[0]}'")
        _mark_failures(ax, runs)
        ax.set_xlabel("time [s]")
        if title:
            ax.set_title(title)
        _legend(fig, ax)
    return fig


# ------------------------------------------------------------------ figures


def time_series_figure(
    results: Result | Sequence[Result],
    channel: str,
    *,
    ylabel: str | None = None,
    scale: float = 1.0,
    labels: Sequence[str] | None = None,
    title: str | None = None,
) -> Figure:
    """One channel against time [s], one line per result (the results lacking it are
    left out).

    Args:
        results: a result, or several to overlay (e.g. ideal and clearance runs).
        channel: the channel, e.g. ``"slider.vx"``.
        ylabel: the y label; default the channel and its SI unit.
        scale: factor from SI to the plotted unit (1000 for mm when ``ylabel`` says mm).
        labels: legend labels, one per result; default ``"ideal"``/``"clearance"``, or the
            model names.
        title: an axes title; default none.

    Raises:
        ValueError: no result holds the channel.
    """
    label = ylabel if ylabel is not None else _default_label(channel)
    return _series_figure(
        _runs(results, labels), (label, [(channel, _channel(channel, scale))]), title
    )


def _slider_panels(result: Result) -> list[tuple[str, Panel]]:
    panels: list[tuple[str, Panel]] = []
    for body, axis in guided_bodies(result):
        for stem, quantity, unit, channel, scale in (
            ("displacement", "displacement", "mm", f"{body}.{axis}", 1000.0),
            ("velocity", "velocity", "m/s", f"{body}.v{axis}", 1.0),
            ("acceleration", "acceleration", "m/s$^2$", f"{body}.a{axis}", 1.0),
        ):
            if channel in result:
                ylabel = f"{body} {quantity} [{unit}]"
                panels.append((f"{body}_{stem}", (ylabel, [(channel, _channel(channel, scale))])))
    return panels


def slider_figures(
    results: Result | Sequence[Result], *, labels: Sequence[str] | None = None
) -> dict[str, Figure]:
    """Displacement [mm], velocity [m/s] and acceleration [m/s^2] of each slider (a body
    guided by a prismatic joint on the ground) against time, overlaying the results;
    keys ``<slider>_displacement``, ``<slider>_velocity``, ``<slider>_acceleration``
    (empty for a mechanism without a slider). The sliders are those of the first result."""
    runs = _runs(results, labels)
    return {name: _series_figure(runs, panel) for name, panel in _slider_panels(runs[0].result)}


def torque_figures(
    results: Result | Sequence[Result], *, labels: Sequence[str] | None = None
) -> dict[str, Figure]:
    """The torque [N m] of each driver against time, overlaying the results; keys
    ``<driver>_torque`` (``motor_torque`` for the founding case)."""
    runs = _runs(results, labels)
    out: dict[str, Figure] = {}
    for channel in _torque_channels(runs[0].result):
        driver = channel[: -len(".torque")]
        panel: Panel = (f"{driver} torque [N m]", [(channel, _channel(channel))])
        out[f"{driver}_torque"] = _series_figure(runs, panel)
    return out


def contact_force_figure(
    results: Result | Sequence[Result],
    joint: str,
    *,
    labels: Sequence[str] | None = None,
    friction: bool = False,
) -> Figure:
    """The normal contact force [N] of a clearance joint against time, overlaying the
    results; for an ideal run, the magnitude of the reaction force of the joint of that
    name. ``friction=True`` adds the friction (tangential) force of the clearance runs."""
    lines: list[tuple[str, Getter]] = [("normal", _contact_force(joint))]
    if friction:
        lines.append(("friction", _channel(f"{joint}.ft")))
    ylabel = "contact force [N]"
    return _series_figure(_runs(results, labels), (ylabel, lines), title=joint)


def orbit_figure(result: Result, joint: str, *, by_mode: bool = True) -> Figure:
    """The journal centre relative to the bearing centre, in the bearing body's frame
    [mm], inside the clearance circle of radius c (drawn), equal axes.

    The whole path is one line (gid ``journal-centre``, data ``1000 * ex``, ``1000 * ey``);
    with ``by_mode`` and a ``<joint>.mode`` channel, the samples in free flight, impact
    and continuous contact are drawn over it in their own colours. The circle is a
    :class:`matplotlib.patches.Circle` (gid ``clearance-circle``).

    Raises:
        ValueError: the joint is no clearance joint of the result's model, or its
            eccentricity channels are missing.
    """
    c_mm = 1000.0 * radial_clearance(result, joint)
    if f"{joint}.ex" not in result or f"{joint}.ey" not in result:
        raise ValueError(f"the result has no channels {joint}.ex and {joint}.ey")
    ex = 1000.0 * result[f"{joint}.ex"]
    ey = 1000.0 * result[f"{joint}.ey"]
    modes = result[f"{joint}.mode"] if by_mode and f"{joint}.mode" in result else None
    with _style():
        fig = Figure(figsize=_ORBIT, layout="constrained")
        ax = fig.add_subplot()
        circle = Circle(
            (0.0, 0.0),
            c_mm,
            fill=False,
            edgecolor="black",
            linewidth=0.8,
            gid="clearance-circle",
            zorder=1,
        )
        ax.add_patch(circle)
        # The legend shows the circle as a line, not as the square handle of a patch.
        handles: list[Artist] = [Line2D([], [], color="black", linewidth=0.8)]
        names = [f"clearance c = {c_mm:g} mm"]
        ax.plot([0.0], [0.0], marker="+", color="0.4", markersize=6, linestyle="none")
        (path,) = ax.plot(
            ex,
            ey,
            color="0.75" if modes is not None else "C0",
            linewidth=0.5,
            label="journal centre",
            gid="journal-centre",
            zorder=2,
        )
        if modes is None:
            handles.append(path)
            names.append("journal centre")
        else:
            for mode, name in MODE_NAMES.items():
                mask = modes == mode
                if not mask.any():
                    continue
                if mode == 1:  # impacts last a few samples: dots, to be seen
                    x, y = ex[mask], ey[mask]
                    style: dict[str, Any] = {"marker": "o", "markersize": 1.5, "linestyle": "none"}
                else:
                    segment = mask.copy()
                    segment[1:] |= mask[:-1]  # each sample's step to the next one
                    x, y = np.where(segment, ex, np.nan), np.where(segment, ey, np.nan)
                    style = {"linewidth": 0.6}
                (line,) = ax.plot(
                    x,
                    y,
                    color=_MODE_COLOURS[mode],
                    label=name,
                    gid=f"mode-{mode}",
                    zorder=3,
                    **style,
                )
                handles.append(line)
                names.append(name)
        if not result.ok and len(result.time):
            (cross,) = ax.plot(
                [ex[-1]], [ey[-1]], marker="x", color="red", linestyle="none", zorder=4
            )
            handles.append(cross)
            names.append(f"failed, t = {float(result.time[-1]):.4g} s")
        for line in ax.lines:
            line.set_in_layout(False)
        reach = max(c_mm, float(np.nanmax(np.hypot(ex, ey))) if len(ex) else 0.0)
        ax.set_xlim(-1.15 * reach, 1.15 * reach)
        ax.set_ylim(-1.15 * reach, 1.15 * reach)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("$e_x$ [mm]")
        ax.set_ylabel("$e_y$ [mm]")
        bearing = _bearing_body(result, joint)
        ax.set_title(f"{joint}, {bearing} frame" if bearing else joint)
        ax.grid(True, linewidth=0.3, alpha=0.6)
        ax.tick_params(labelsize=_FONT_SIZE)
        fig.legend(
            handles,
            names,
            loc="outside upper center",
            ncols=_legend_columns(fig, names, 2, handle=1.2, spacing=1.0),
            handlelength=1.2,
            columnspacing=1.0,
        )
    return fig


def _body_panels(result: Result) -> list[Panel]:
    bodies = [b["name"] for b in result.model.get("bodies", [])]
    if not bodies:
        bodies = sorted({c.split(".")[0] for c in result.channels if c.endswith(".angle")})
    panels: list[Panel] = []
    for quantity, label, scale in (
        ("x", "x [m]", 1.0),
        ("y", "y [m]", 1.0),
        ("angle", "angle [deg]", 180.0 / np.pi),
    ):
        lines = [
            (b, _channel(f"{b}.{quantity}", scale)) for b in bodies if f"{b}.{quantity}" in result
        ]
        if lines:
            panels.append((label, lines))
    return panels


def _overview_panels(result: Result) -> list[Panel]:
    panels = [panel for _, panel in _slider_panels(result)]
    if not panels:
        panels = _body_panels(result)
    torques = _torque_channels(result)
    if torques:
        name = torques[0][: -len(".torque")] if len(torques) == 1 else "driver"
        panels.append((f"{name} torque [N m]", [(c, _channel(c)) for c in torques]))
    for joint in clearance_joints(result):
        if f"{joint}.fn" in result:
            panels.append((f"{joint} contact force [N]", [(joint, _contact_force(joint))]))
    return panels


def figure(
    result: Result, ideal: Result | None = None, *, labels: Sequence[str] | None = None
) -> Figure:
    """The overview of a result, one panel per quantity against a shared time axis:
    slider displacement [mm], velocity [m/s], acceleration [m/s^2], motor torque [N m]
    and the contact force [N] of each clearance joint; for a mechanism without a slider,
    the bodies' x [m], y [m] and angle [deg] instead of the slider's motion.

    Args:
        result: the result; its model decides the panels.
        ideal: an ideal run of the same mechanism, overlaid (labels ``"clearance"`` and
            ``"ideal"`` by default).
        labels: legend labels of ``result`` and ``ideal``, in that order.

    Raises:
        ValueError: the result holds no channel to plot.
    """
    runs = _runs([result] if ideal is None else [result, ideal], labels)
    panels = _overview_panels(result)
    if not panels:
        raise ValueError("the result holds no channel to plot (positions, slider motion)")
    with _style():
        fig = Figure(figsize=(_WIDE, _PANEL_HEIGHT * len(panels) + 0.7), layout="constrained")
        axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
        for ax, panel in zip(axes, panels, strict=True):
            _plot_panel(ax, runs, panel)
            _mark_failures(ax, runs)
            if len(panel[1]) > 1:  # several bodies or drivers: a legend per panel
                ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=_FONT_SIZE)
        axes[-1].set_xlabel("time [s]")
        if all(len(panel[1]) == 1 for panel in panels):
            _legend(fig, axes[0], "outside lower center")
        title = str(result.model.get("name") or "jointgap result")
        if not result.ok:
            title += (
                f" (run failed at t = {float(result.time[-1]):.4g} s)"
                if len(result.time)
                else " (failed)"
            )
        fig.suptitle(title)
    return fig


def figure_set(
    result: Result, ideal: Result | None = None, *, labels: Sequence[str] | None = None
) -> dict[str, Figure]:
    """Every figure of a result by file stem: ``figure`` (the overview),
    ``<slider>_displacement``, ``<slider>_velocity``, ``<slider>_acceleration``,
    ``<driver>_torque``, and for each clearance joint ``contact_force_<joint>`` and
    ``orbit_<joint>``. ``ideal`` and ``labels`` as in :func:`figure`."""
    results = [result] if ideal is None else [result, ideal]
    out = {"figure": figure(result, ideal, labels=labels)}
    out |= slider_figures(results, labels=labels)
    out |= torque_figures(results, labels=labels)
    for joint in clearance_joints(result):
        if f"{joint}.fn" in result:
            out[f"contact_force_{_safe(joint)}"] = contact_force_figure(
                results, joint, labels=labels
            )
        if f"{joint}.ex" in result and f"{joint}.ey" in result:
            out[f"orbit_{_safe(joint)}"] = orbit_figure(result, joint)
    return out


# ------------------------------------------------------------------ saving


def _safe(name: str) -> str:
    return re.sub(r"[^\w.-]", "_", name)


def _check_formats(formats: Sequence[str]) -> list[str]:
    out = [f.lower().lstrip(".") for f in ([formats] if isinstance(formats, str) else formats)]
    bad = [f for f in out if f not in _FORMATS]
    if bad:
        raise ValueError(f"unknown figure format {bad[0]!r}; known: {', '.join(_FORMATS)}")
    return out


def save_figures(
    figures: Mapping[str, Figure],
    directory: str | PathLike[str],
    formats: Sequence[str] = FIGURE_FORMATS,
) -> list[Path]:
    """Writes ``<directory>/<name>.<format>`` for each figure and format (directory
    created; PNG at :data:`PNG_DPI`, SVG and PDF without a date); returns the paths."""
    fmts = _check_formats(formats)
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    with _style():
        for name, fig in figures.items():
            for fmt in fmts:
                path = out / f"{name}.{fmt}"
                metadata = {"svg": {"Date": None}, "pdf": {"CreationDate": None}}.get(fmt)
                fig.savefig(path, format=fmt, dpi=PNG_DPI, metadata=metadata)
                paths.append(path)
    return paths


def save_figure(
    result: Result,
    directory: str | PathLike[str],
    stem: str = "figure",
    *,
    ideal: Result | None = None,
    labels: Sequence[str] | None = None,
    formats: Sequence[str] = FIGURE_FORMATS,
) -> list[Path]:
    """Writes the overview (:func:`figure`) as ``<directory>/<stem>.png`` and ``.svg``
    (or ``formats``); returns the paths."""
    return save_figures({stem: figure(result, ideal, labels=labels)}, directory, formats)


def save_figure_set(
    result: Result,
    directory: str | PathLike[str],
    *,
    ideal: Result | None = None,
    labels: Sequence[str] | None = None,
    formats: Sequence[str] = FIGURE_FORMATS,
) -> list[Path]:
    """Writes every figure of :func:`figure_set` into ``directory``, one file per figure
    and format, named by the figure's stem; returns the paths."""
    return save_figures(figure_set(result, ideal, labels=labels), directory, formats)


# ------------------------------------------------------------------ comparison


def comparison_figure(comparison: Comparison, *, labels: Sequence[str] | None = None) -> Figure:
    """Three panels, two columns wide: the aligned signals overlaid (simulated, measured)
    against simulation time, with the crank-turn boundaries dotted; their difference
    (simulated - measured); and their amplitude spectra. Lines carry gids
    ``simulated``, ``measured``, ``difference``, ``spectrum-simulated``,
    ``spectrum-measured``.

    Args:
        comparison: the comparison (:func:`jointgap.comparison.compare`).
        labels: legend labels of the simulation and the measurement; default
            ``"simulated"`` and the measured signal's name.
    """
    c = comparison
    names = list(labels) if labels is not None else ["simulated", f"measured ({c.measured_name})"]
    if len(names) != 2:
        raise ValueError(f"comparison_figure: {len(names)} labels, need 2")
    unit = _unit_text(c.unit) if c.unit else "-"
    with _style():
        fig = Figure(figsize=(_WIDE, 3 * _PANEL_HEIGHT + 0.9), layout="constrained")
        signal, diff, spectrum = fig.subplots(3, 1)
        diff.sharex(signal)
        # The measurement thin and black over the simulation: both stay visible.
        signal.plot(c.time, c.simulated, color="C0", linewidth=1.0, label=names[0], gid="simulated")
        signal.plot(
            c.time, c.measured, color="black", linewidth=0.5, label=names[1], gid="measured"
        )
        from .comparison import CYCLE_LINES

        # Turn boundaries help over a few turns; hundreds would grey the panel out.
        for row in c.cycles if len(c.cycles) <= CYCLE_LINES else ():
            for t in (row.start, row.end):
                signal.axvline(t, color="0.5", linestyle=":", linewidth=0.6, zorder=1)
        signal.set_ylabel(f"{c.channel} [{unit}]")
        diff.plot(c.time, c.difference, color="C3", gid="difference")
        diff.set_ylabel(f"difference [{unit}]")
        diff.set_xlabel("simulation time [s]")
        s = c.spectra  # log scale, without the 0 Hz bin (the means are removed)
        for amplitude, label, gid, style in (
            (s.simulated, names[0], "spectrum-simulated", {"color": "C0", "linewidth": 1.0}),
            (s.measured, names[1], "spectrum-measured", {"color": "black", "linewidth": 0.5}),
        ):
            spectrum.semilogy(s.frequency[1:], amplitude[1:], label=label, gid=gid, **style)
        spectrum.set_xlabel("frequency [Hz]")
        spectrum.set_ylabel(f"amplitude [{unit}]")
        for ax in (signal, diff, spectrum):
            ax.grid(True, linewidth=0.3, alpha=0.6)
            ax.tick_params(labelsize=_FONT_SIZE)
            ax.margins(x=0.0)
        m = c.measures
        signal.set_title(
            f"lag {1e3 * c.lag:.2f} ms, max error {m.max_percent:.1f} % of the measured peak, "
            f"NRMSE {100.0 * m.nrmse:.1f} %, r = {m.correlation:.3f}"
        )
        handles, texts = signal.get_legend_handles_labels()
        fig.legend(handles, texts, loc="outside upper center", ncols=2)
    return fig
