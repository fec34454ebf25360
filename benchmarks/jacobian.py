"""Exact Jacobians against the applied forces' part, measured side by side in one run.

The implicit methods (radau5, sdirk4, and ``auto`` when it hands them the steps) take
the acceleration rows of ``df/dy`` either exactly, differentiated from the recorded
evaluation (the default where the compiler covers the model, docs/compiled.md), or as
the applied forces' part by forward differences (``exact_jacobian=False``, the earlier
approximation, which leaves out the constraint forces' geometric stiffness and the
velocity terms). On the founding clearance case (examples/slider_crank_clearance.toml,
0.5 s, slider.ax at 10 kHz) each method and tolerance runs both ways: steps, rejections,
evaluations, Jacobians, Newton iterations, the NRMSE of slider.ax against a radau5 run
at rtol 1e-11, and the wall time (median of runs alternating between the two ways, so
that a load on the machine falls on both).

Writes benchmarks/output/jacobian.md and benchmarks/results/jacobian.json.
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import time
from pathlib import Path
from typing import Any

import jointgap
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "slider_crank_clearance.toml"
REPORT = ROOT / "benchmarks" / "output" / "jacobian.md"
RESULTS = ROOT / "benchmarks" / "results" / "jacobian.json"
RUN: dict[str, Any] = {"t_end": 0.5, "rate": 10_000.0, "channels": ["slider.ax"]}
CASES = [("radau5", 1e-6), ("radau5", 1e-8), ("sdirk4", 1e-6), ("sdirk4", 1e-8), ("auto", 1e-8)]
REPEATS = 7
COUNTERS = (
    "accepted_steps",
    "rejected_steps",
    "rhs_evaluations",
    "jacobian_evaluations",
    "newton_iterations",
)


def nrmse(result: jointgap.Result, reference: jointgap.Result) -> float:
    """RMS of slider.ax's difference from the reference over its range."""
    got, want = np.asarray(result["slider.ax"]), np.asarray(reference["slider.ax"])
    return float(np.sqrt(np.mean((got - want) ** 2)) / (want.max() - want.min()))


def main() -> None:
    model = jointgap.load(MODEL)
    reference = model.simulate(**RUN, method="radau5", rtol=1e-11, atol=1e-14)
    rows: list[dict[str, Any]] = []
    for method, rtol in CASES:
        walls: dict[bool, list[float]] = {True: [], False: []}
        runs: dict[bool, jointgap.Result] = {}
        for _ in range(REPEATS):
            for exact in (True, False):
                started = time.perf_counter()
                runs[exact] = model.simulate(**RUN, method=method, rtol=rtol, exact_jacobian=exact)
                walls[exact].append(time.perf_counter() - started)
        for exact in (True, False):
            stats = runs[exact].stats
            rows.append(
                {
                    "method": method,
                    "rtol": rtol,
                    "jacobian": "exact" if exact else "applied forces",
                    **{k: stats[k] for k in COUNTERS},
                    "nrmse": nrmse(runs[exact], reference),
                    "wall_time": statistics.median(walls[exact]),
                }
            )
    machine = f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps({"machine": machine, "rows": rows}, indent=1) + "\n")
    lines = [
        "# Exact Jacobians against the applied forces' part",
        "",
        f"Founding clearance case, 0.5 s, slider.ax at 10 kHz; {machine}. Wall time: median of",
        f"{REPEATS} runs alternating between the two ways; 'ratio': the applied forces' time",
        "over the exact one's (above 1: exact is faster).",
        "",
        "| method | rtol | Jacobian | steps | rejected | evaluations | Jacobians | Newton "
        "iterations | NRMSE | wall [ms] | ratio |",
        "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for exact, forces in zip(rows[::2], rows[1::2], strict=True):
        for row in (exact, forces):
            ratio = forces["wall_time"] / exact["wall_time"] if row is exact else 1.0
            lines.append(
                f"| {row['method']} | {row['rtol']:.0e} | {row['jacobian']} | "
                + " | ".join(str(row[k]) for k in COUNTERS)
                + f" | {row['nrmse']:.2e} | {1e3 * row['wall_time']:.1f} | {ratio:.2f} |"
            )
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
