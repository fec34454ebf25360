"""The figures of a wear prediction (matplotlib, no display needed): each joint's worn
bearing and journal as polar profiles around their original circles (the wear
magnified so that it shows), and the history: the deepest wear and the worn volume, the
clearance, the peak contact force and the watched peak against the cycles."""

from __future__ import annotations

import math
from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from .plots import _style, save_figures

if TYPE_CHECKING:
    from ._wear_prediction import WearPrediction

__all__ = ["profile_figure", "history_figure", "wear_figures"]

_SIZE = (7.0, 3.6)  # two paper columns [in]
_SHOWN = 0.25  # the deepest wear drawn as this fraction of the radius


def profile_figure(p: WearPrediction, joint: str) -> Figure:
    """The bearing (left) and the journal (right) of ``joint``, each in its body frame:
    the original circle dashed, the profile after each update, the wear magnified by
    the factor in the title (the deepest wear drawn as a quarter of the radius)."""
    steps = p.profiles[joint]
    nominal = p.nominal[joint]
    deepest = max(max(float(np.max(b)), float(np.max(w))) for _, b, w in steps)
    theta = np.append(p.angles, p.angles[:1] + 2 * math.pi)
    with _style():
        fig = Figure(figsize=_SIZE, layout="constrained")
        for column, (part, radius, sign, index) in enumerate(
            (
                ("bearing", nominal["bearing_radius"], 1.0, 1),
                ("journal", nominal["journal_radius"], -1.0, 2),
            )
        ):
            ax = fig.add_subplot(1, 2, column + 1, projection="polar")
            factor = _SHOWN * radius / deepest if deepest > 0 else 1.0
            ax.plot(theta, np.full_like(theta, radius * 1e3), "k--", lw=0.6, label="original")
            colours = np.linspace(0.25, 1.0, len(steps))
            for shade, (_, bearing, journal) in zip(colours, steps, strict=True):
                worn = bearing if index == 1 else journal
                depth = np.append(worn, worn[:1])
                ax.plot(
                    theta,
                    (radius + sign * factor * depth) * 1e3,
                    color=(shade * 0.8, 0.2, 1 - shade),
                    lw=0.7,
                )
            ax.set_title(f"{joint}: {part} [mm], wear x {factor:.3g}", fontsize=9)
            ax.set_ylim(0, radius * 1e3 * (1 + 2 * _SHOWN))
            ax.set_yticklabels([])
        fig.suptitle(
            f"worn profiles after {steps[-1][0]:.4g} cycles (deepest {deepest * 1e6:.3g} um; "
            "blue: early, red: last)"
        )
    return fig


def history_figure(p: WearPrediction) -> Figure:
    """Against the cycles, per joint: the deepest wear of bearing and journal [um], the
    worn volume [mm^3], the largest clearance [mm], the peak contact force [N] and the
    watched channel's peak."""
    h = p.history
    panels = [
        (
            "deepest wear [um]",
            [("max_bearing_depth", "bearing", 1e6), ("max_journal_depth", "journal", 1e6)],
        ),
        (
            "worn volume [mm^3]",
            [("bearing_volume", "bearing", 1e9), ("journal_volume", "journal", 1e9)],
        ),
        ("largest clearance [mm]", [("clearance", "", 1e3)]),
        ("peak contact force [N]", [("peak_contact_force", "", 1.0)]),
    ]
    if p.watch is not None:
        panels.append((f"peak |{p.watch}|", [("peak_watch", "", 1.0)]))
    with _style():
        fig = Figure(
            figsize=(_SIZE[0], 1.6 * math.ceil(len(panels) / 2) + 0.6), layout="constrained"
        )
        axes = fig.subplots(math.ceil(len(panels) / 2), 2, squeeze=False).ravel()
        for ax, (label, series) in zip(axes, panels, strict=False):
            for joint, rows in h.groupby("joint", sort=False):
                for column, part, scale in series:
                    name = f"{joint} {part}".strip()
                    ax.plot(rows["cycles"], rows[column] * scale, marker=".", ms=3, label=name)
            ax.set_ylabel(label)
            ax.set_xlabel("cycles")
            ax.legend()
            if p.cycles_to_limit is not None:
                ax.axvline(p.cycles_to_limit, color="tab:red", ls=":", lw=0.8)
        for ax in axes[len(panels) :]:
            ax.set_visible(False)
        fig.suptitle(f"wear over {p.cycles:.4g} cycles, k = {p.coefficient:.3g} 1/Pa")
    return fig


def wear_figures(
    p: WearPrediction, folder: str | PathLike[str], formats: Sequence[str] = ("png",)
) -> list[Path]:
    """Writes ``wear_history`` and ``wear_profile_<joint>`` into ``folder``."""
    figures = {"wear_history": history_figure(p)}
    figures.update({f"wear_profile_{j}": profile_figure(p, j) for j in p.profiles})
    return save_figures(figures, folder, formats)
