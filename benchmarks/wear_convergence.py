"""Wear over life on the founding slider-crank: the deepest bearing and journal wear
after a number of cycles as the update's tolerance tightens and the grid is refined,
against wearing the profiles cycle by cycle (docs/wear.md, "Convergence"). Writes
benchmarks/output/wear_convergence.md.

    .venv/bin/python benchmarks/wear_convergence.py [CYCLES]
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import jointgap
from jointgap.wear import predict_wear

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "slider_crank_clearance.toml"
OUT = Path(__file__).resolve().parent / "output" / "wear_convergence.md"


def main(cycles: float = 300.0) -> str:
    model = jointgap.load(EXAMPLE)
    rows = []
    cases = [
        (36, 0.2, False),
        (36, 0.1, False),
        (36, 0.05, False),
        (36, 0.025, False),
        (36, None, True),
        (18, 0.05, False),
        (72, 0.05, False),
    ]
    for cells, tolerance, every in cases:
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            p = predict_wear(
                model,
                cycles,
                length="10 mm",
                cells=cells,
                tolerance=tolerance or 0.05,
                every_cycle=every,
            )
        _, bearing, journal = p.profiles["rod_slider"][-1]
        rows.append(
            f"| {cells} | {'every cycle' if every else tolerance} | {p.cycles:.4g} | "
            f"{bearing.max() * 1e6:.3f} | {journal.max() * 1e6:.3f} | {p.runs} | "
            f"{time.perf_counter() - start:.1f} | {p.status} |"
        )
    table = "\n".join(
        [
            f"Founding case, steel in brass dry (k = 6.44e-13 1/Pa), bearing length 10 mm, "
            f"{cycles:g} cycles:",
            "",
            "| cells | tolerance | cycles | bearing [um] | journal [um] | runs | wall [s] "
            "| status |",
            "|---:|---:|---:|---:|---:|---:|---:|---|",
            *rows,
        ]
    )
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(table + "\n", encoding="utf-8")
    return table


if __name__ == "__main__":
    print(main(float(sys.argv[1]) if len(sys.argv) > 1 else 300.0))
