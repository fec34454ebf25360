"""Report test helpers: the data a page embeds, and the folders that 'jointgap
compare' and 'jointgap study' write, made small for the tests."""

from __future__ import annotations

import json
import re
from pathlib import Path

from jointgap.cli import main


def embedded(page: str) -> dict:
    """The JSON data a page embeds."""
    match = re.search(r'<script type="application/json" id="jg-data">(.*?)</script>', page, re.S)
    assert match is not None
    return json.loads(match.group(1))


def compare_folder(examples: Path, tmp_path: Path) -> Path:
    """A 'jointgap compare' folder: the founding case against a synthetic record."""
    model = str(examples / "slider_crank_clearance.toml")
    record = tmp_path / "record.csv"
    assert (
        main(
            ["synthesize", model, "--signal", "slider.ax", "--t-end", "0.2", "--out", str(record)]
            + ["--noise", "5", "--lag", "0.004", "--rate", "10000"]
        )
        == 0
    )
    out = tmp_path / "compare"
    assert (
        main(
            ["compare", model, "--measured", str(record), "--signal", "slider.ax"]
            + ["--out", str(out), "--t-end", "0.2", "--format", "png", "--report"]
        )
        == 0
    )
    return out


def study_folder(tmp_path: Path) -> Path:
    """A small study folder as 'jointgap study' writes it (its output contract)."""
    folder = tmp_path / "study"
    (folder / "figures").mkdir(parents=True)
    study = {
        "name": "clearance_sweep",
        "base_model": "examples/slider_crank_clearance.toml",
        "parameters": [
            {"path": "rod_slider.clearance", "kind": "list", "values": [2.5e-4, 5e-4, 1e-3]},
            {"path": "motor.speed", "kind": "list", "values": [20.0, 31.4]},
        ],
        "metrics": ["slider.ax.max_abs", "impacts"],
        "sampling": "grid",
        "n_cases": 6,
    }
    (folder / "study.json").write_text(json.dumps(study))
    rows = [
        "case,rod_slider.clearance,motor.speed,slider.ax.max_abs,impacts,status,reason,run_time_s"
    ]
    k = 0
    for c in (2.5e-4, 5e-4, 1e-3):
        for s in (20.0, 31.4):
            if k == 4:
                rows.append(f"{k},{c},{s},,,failed,step budget spent at t = 0.2 s,0.5")
            else:
                rows.append(f"{k},{c},{s},{1000 * c / 5e-4 + s},{k + 10},finished,,0.2")
            k += 1
    (folder / "cases.csv").write_text("\n".join(rows) + "\n")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(2, 1.5))
    fig.add_subplot().plot([0, 1], [1, 0])
    fig.savefig(folder / "figures" / "slider.ax.max_abs_vs_clearance.png", dpi=50)
    return folder
