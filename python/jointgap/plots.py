"""Figures of a result (matplotlib, no display needed).

For a slider-crank (a result with ``slider.x``): slider displacement [mm], velocity
[m/s] and acceleration [m/s^2] and the motor torque [N m] against time. For any other
mechanism: the positions (x, y) and angles of the bodies against time.

Figures are built on :class:`matplotlib.figure.Figure` directly, without pyplot, so
they need no display and change no global matplotlib state.
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .results import Result

__all__ = ["figure", "save_figure", "FIGURE_FORMATS"]

FIGURE_FORMATS = ("png", "svg")


def figure(result: Result) -> Figure:
    """The standard figure of a result (see the module documentation)."""
    if "slider.x" in result:
        panels = _slider_crank_panels(result)
    else:
        panels = _body_panels(result)
    if not panels:
        raise ValueError("the result holds no channel to plot (positions, slider motion)")
    fig = Figure(figsize=(8.0, 2.2 * len(panels) + 0.8), layout="constrained")
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (ylabel, lines) in zip(axes, panels, strict=True):
        for label, values in lines:
            ax.plot(result.time, values, label=label, linewidth=1.0)
        ax.set_ylabel(ylabel)
        ax.grid(True, linewidth=0.3)
        if len(lines) > 1:
            ax.legend(loc="best", fontsize="small")
        if not result.ok and len(result.time):
            ax.axvline(result.time[-1], color="red", linestyle="--", linewidth=0.8)
    axes[-1].set_xlabel("time [s]")
    title = result.model.get("name") or "jointgap result"
    if not result.ok:
        title += f" ({result.message})"
    fig.suptitle(title)
    return fig


Panel = tuple[str, list[tuple[str, np.ndarray]]]


def _slider_crank_panels(result: Result) -> list[Panel]:
    panels: list[Panel] = [
        (label, [(channel, scale * result[channel])])
        for channel, label, scale in (
            ("slider.x", "slider displacement [mm]", 1000.0),
            ("slider.vx", "slider velocity [m/s]", 1.0),
            ("slider.ax", "slider acceleration [m/s$^2$]", 1.0),
        )
        if channel in result
    ]
    torques = _driver_channels(result, "torque")
    if torques:
        panels.append(("motor torque [N m]", [(c, result[c]) for c in torques]))
    return panels


def _driver_channels(result: Result, quantity: str) -> list[str]:
    names: Sequence[str] = [d["name"] for d in result.model.get("drivers", [])]
    if not names:  # a result without its model: any channel of that quantity
        return [c for c in result.channels if c.endswith("." + quantity)]
    return [f"{n}.{quantity}" for n in names if f"{n}.{quantity}" in result]


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
            (b, scale * result[f"{b}.{quantity}"]) for b in bodies if f"{b}.{quantity}" in result
        ]
        if lines:
            panels.append((label, lines))
    return panels


def save_figure(result: Result, directory: str | PathLike[str], stem: str = "figure") -> list[Path]:
    """Writes ``<directory>/<stem>.png`` and ``.svg``; returns the paths."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    fig = figure(result)
    paths = [out / f"{stem}.{fmt}" for fmt in FIGURE_FORMATS]
    for path in paths:
        fig.savefig(path, dpi=150)
    return paths
