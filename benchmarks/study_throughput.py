"""Throughput of a 1000-case study of the founding case, compiled against interpreted,
measured side by side in one run.

The study: examples/slider_crank_clearance.toml with the rod-slider clearance from 0.1 to
1.0 mm (40 values) crossed with the crank speed from 100 to 600 rpm (25 values), 0.5 s at
10 kHz, keeping the peak contact force and the peak slider acceleration. It runs on the
local cores (``run_study``, two threads), once compiled and once with ``compiled =
false``, in this process, so that a load on the machine falls on both.

Where the time goes, per case: the engine's own run (its ``wall_time``) against the
whole case (the model read from its dictionary, the variant made, the run, the metrics),
for the first 40 cases run one after another in this process.

Writes benchmarks/output/study_throughput.md and benchmarks/results/study_throughput.json.
"""

from __future__ import annotations

import json
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import jointgap
from jointgap.study import load_results, load_study, run_study
from jointgap.study.execute import Case, run_case
from jointgap.variants import with_parameters

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "slider_crank_clearance.toml"
REPORT = ROOT / "benchmarks" / "output" / "study_throughput.md"
RESULTS = ROOT / "benchmarks" / "results" / "study_throughput.json"
WORKERS = 2
PROFILED = 40

STUDY = """
[study]
name = "throughput"
model = "{model}"
t_end = "0.5 s"
rate = "10 kHz"
compiled = {compiled}

[parameters]
"rod_slider.clearance" = {{ from = "0.1 mm", to = "1.0 mm", steps = 40 }}
"motor.speed" = {{ from = "100 rpm", to = "600 rpm", steps = 25 }}

[metrics]
peak_contact_force = "peak_contact_force"
peak_slider_acceleration = {{ stat = "peak", channel = "slider.ax" }}
"""


def study_file(folder: Path, compiled: bool) -> Path:
    """The study file, compiled or not, in ``folder``."""
    path = folder / f"study_{'compiled' if compiled else 'interpreted'}.toml"
    path.write_text(STUDY.format(model=MODEL.as_posix(), compiled=str(compiled).lower()))
    return path


def throughput(folder: Path, compiled: bool) -> dict[str, Any]:
    """Wall time, cases per second and the sum of the cases' run times of the study."""
    out = folder / ("compiled" if compiled else "interpreted")
    start = time.perf_counter()
    run_study(study_file(folder, compiled), out, workers=WORKERS, progress=None)
    wall = time.perf_counter() - start
    table = load_results(out)
    finished = int((table["status"] == "finished").sum())
    return {
        "cases": len(table),
        "finished": finished,
        "wall": wall,
        "cases_per_second": len(table) / wall,
        "case_time_sum": float(table["run_time_s"].sum()),
    }


def per_case(folder: Path, compiled: bool) -> dict[str, float]:
    """The first cases one after another: the engine's own run time against the case's."""
    study = load_study(study_file(folder, compiled))
    engine, whole = 0.0, 0.0
    for k, values in enumerate(study.cases()[:PROFILED]):
        case = Case(k, values, study.model_of(values), study.run, study.metrics)
        start = time.perf_counter()
        outcome = run_case(case)
        whole += time.perf_counter() - start
        model = with_parameters(jointgap.Model.from_dict(case.model), dict(values))
        engine += float(model.simulate(**case.run).stats["wall_time"])
        assert outcome.status == "finished", outcome.reason
    return {"engine": engine / PROFILED, "case": whole / PROFILED}


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        names = ("compiled", "interpreted")
        runs = {name: throughput(folder, name == "compiled") for name in names}
        cases = {name: per_case(folder, name == "compiled") for name in names}
    native, plain = runs["compiled"], runs["interpreted"]
    lines = [
        f"A 1000-case study of the founding case ({platform.machine()}, {WORKERS} threads): "
        "rod_slider.clearance 0.1-1.0 mm x motor.speed 100-600 rpm, 0.5 s at 10 kHz",
        "",
        "| | cases | wall [s] | cases per second | sum of the cases' run times [s] |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, r in runs.items():
        lines.append(
            f"| {name} | {r['finished']} of {r['cases']} | {r['wall']:.1f} | "
            f"{r['cases_per_second']:.1f} | {r['case_time_sum']:.1f} |"
        )
    lines += [
        "",
        f"Throughput compiled against interpreted: "
        f"{native['cases_per_second'] / plain['cases_per_second']:.2f}x.",
        "",
        f"Per case, the first {PROFILED} one after another in this process:",
        "",
        "| | the engine's run [ms] | the whole case [ms] | the rest [ms] |",
        "|---|---:|---:|---:|",
    ]
    for name, c in cases.items():
        lines.append(
            f"| {name} | {1e3 * c['engine']:.1f} | {1e3 * c['case']:.1f} | "
            f"{1e3 * (c['case'] - c['engine']):.1f} |"
        )
    text = "\n".join(lines) + "\n"
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text(text)
    RESULTS.write_text(json.dumps({"runs": runs, "per_case": cases}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
