"""The report page of a wear prediction: one offline HTML file with the run's inputs and
outcome, each joint's final wear, the history table and the figures inlined as images."""

from __future__ import annotations

import base64
import html
from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

from .page import _asset

if TYPE_CHECKING:
    from .._wear_prediction import WearPrediction

__all__ = ["write_wear_report"]

_JOINT_COLUMNS = (
    "joint",
    "clearance [mm]",
    "bearing wear [um]",
    "journal wear [um]",
    "largest clearance [mm]",
)
_HISTORY_COLUMNS = (
    "cycles",
    "joint",
    "bearing wear [um]",
    "journal wear [um]",
    "clearance [mm]",
    "peak contact force [N]",
)


def _table(header: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def write_wear_report(
    p: WearPrediction, path: str | PathLike[str], figures: Sequence[Path]
) -> Path:
    """Writes the page to ``path``, the PNG ``figures`` inlined; returns the path."""
    inputs = [
        ("wear coefficient k", f"{p.coefficient:.4g} 1/Pa ({p.coefficient * 1e9:.4g} mm^3/(N m))"),
        ("pair", p.pair or "given"),
        ("cycles worn", f"{p.cycles:.6g}"),
        ("status", f"{p.status} {p.message}".strip()),
        (
            "cycles to the clearance limit",
            "-" if p.cycles_to_limit is None else f"{p.cycles_to_limit:.6g}",
        ),
        ("simulations", str(p.runs)),
    ]
    finals = []
    for joint, steps in p.profiles.items():
        _, b, w = steps[-1]
        n = p.nominal[joint]
        finals.append(
            (
                joint,
                f"{n['clearance'] * 1e3:.4g}",
                f"{b.max() * 1e6:.4g}",
                f"{w.max() * 1e6:.4g}",
                f"{(n['clearance'] + b.max() + w.max()) * 1e3:.4g}",
            )
        )
    history = [
        [
            f"{r.cycles:.6g}",
            r.joint,
            f"{r.max_bearing_depth * 1e6:.4g}",
            f"{r.max_journal_depth * 1e6:.4g}",
            f"{r.clearance * 1e3:.5g}",
            f"{r.peak_contact_force:.4g}",
            f"{r.peak_watch:.4g}",
        ]
        for r in p.history.itertuples()
    ]
    images = "".join(
        f'<figure><img alt="{html.escape(f.stem)}" src="data:image/png;base64,'
        f'{base64.b64encode(f.read_bytes()).decode()}"><figcaption>{html.escape(f.stem)}</figcaption></figure>'
        for f in figures
        if f.suffix == ".png"
    )
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>jointgap wear prediction</title>
<style>{_asset("report.css")}
figure img {{ max-width: 100%; }}</style></head>
<body data-ready="true"><main>
<h1>Wear over life</h1>
<p>Archard's law on each part's angular grid; each update scales the wear of simulated
steady cycles by a number of cycles chosen by step doubling (docs/wear.md).</p>
<h2>Inputs and outcome</h2>
{_table(("", ""), inputs)}
<h2>Joints</h2>
{_table(_JOINT_COLUMNS, finals)}
<h2>Figures</h2>
{images}
<h2>History</h2>
{_table((*_HISTORY_COLUMNS, f"peak |{p.watch or '-'}|"), history)}
</main></body></html>
"""
    out = Path(path)
    out.write_text(page, encoding="utf-8")
    return out
