"""Where the benchmarks' figures go and on what they were measured: :func:`machine`, the
one description of the machine for every table, and :func:`write_results`, which writes
``benchmarks/results/<name>.json`` with it. Every benchmark script imports these from
here (and none from another script's module), so the scripts import no circle."""

from __future__ import annotations

import json
import os
import platform
import subprocess
from pathlib import Path
from typing import Any

import jointgap

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


def machine() -> str:
    """The machine, its load, Python, jointgap and the commit, in one sentence."""
    cpu = "unknown"
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    return (
        f"Machine: {cpu}, nproc = {nproc}, load average {load} (1, 5, 15 min) when the "
        f"Python part ran; Python {platform.python_version()}, jointgap "
        f"{jointgap.__version__}, commit {commit or 'unknown'}."
    )


def write_results(name: str, figures: dict[str, Any]) -> Path:
    """Writes ``benchmarks/results/<name>.json`` with the machine and commit."""
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"{name}.json"
    path.write_text(json.dumps({"machine": machine(), **figures}, indent=1) + "\n")
    return path
