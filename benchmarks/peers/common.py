"""What the peer benchmarks share: the case, the converged reference, the accuracy measure,
jointgap's timed runs, the matched-accuracy choice and the JSON results.

The peers (``scipy_slider_crank.py``, ``exudyn_slider_crank.py``) run the founding
clearance slider-crank (``examples/slider_crank_clearance.toml``, docs/physics.md section 5)
from 0 to 0.5 s and score the slider acceleration on a 10 kHz grid against one converged
jointgap run. Runs in the main ``.venv`` (numpy, jointgap); the machine description is
``benchmarks/recording.machine``.
"""

from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import jointgap
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "examples" / "slider_crank_clearance.toml"
OUTPUT = ROOT / "benchmarks" / "output"  # markdown tables (git-ignored)
RESULTS = ROOT / "benchmarks" / "results"  # JSON figures (committed)
T_END = 0.5  # [s]
RATE = 10_000  # output samples per second [Hz]
TARGETS = (1e-3, 1e-4, 2e-5)  # NRMSE targets of the matched-accuracy tables

sys.path.insert(0, str(ROOT / "benchmarks"))
# One description of the machine for every table; the speed issue's quoted C program times.
from recording import machine  # noqa: E402
from run import C_PROGRAM_MS  # noqa: E402

__all__ = [
    "C_PROGRAM_MS",
    "MODEL",
    "OUTPUT",
    "RATE",
    "RESULTS",
    "ROOT",
    "T_END",
    "TARGETS",
    "Reference",
    "Row",
    "commit",
    "fastest",
    "fmt",
    "grid",
    "load_text",
    "machine",
    "nrmse",
    "PAIRED_ROUNDS",
    "paired_ratio",
    "paired_text",
    "reference",
    "reference_summary",
    "row_dict",
    "run_jointgap",
    "write_json",
]


def grid() -> np.ndarray:
    """The output grid, 0 to T_END at RATE."""
    return np.arange(int(round(T_END * RATE)) + 1) / RATE


def nrmse(actual: np.ndarray, reference: np.ndarray) -> float:
    """RMS of the difference over the reference's max - min."""
    return float(np.sqrt(np.mean((actual - reference) ** 2)) / np.ptp(reference))


def load_text() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def commit() -> str:
    return subprocess.run(
        ["git", "log", "-1", "--format=%h"], capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()


def fmt(x: float | None, spec: str) -> str:
    return "" if x is None else format(x, spec)


@dataclass
class Reference:
    """jointgap at rtol 1e-11, atol 1e-14; ``error``: a run at rtol 1e-12, atol 1e-15
    differs from it by this NRMSE (the floor of what can be resolved)."""

    time: np.ndarray
    ax: np.ndarray  # slider.ax on the grid [m/s^2]
    wall: float  # [s]
    error: float
    impacts: int  # contact onsets of the clearance joint


def reference_summary(wall: float, error: float, **extra: Any) -> dict[str, Any]:
    """The reference's settings and figures as the peers' JSON records them."""
    return {"rtol": 1e-11, "atol": 1e-14, "wall": wall, **extra, "nrmse_vs_rtol_1e-12": error}


def reference(model: jointgap.Model) -> Reference:
    start = time.perf_counter()
    run = model.simulate(T_END, rate=RATE, rtol=1e-11, atol=1e-14)
    wall = time.perf_counter() - start
    assert run.status == "finished", run.message
    assert np.allclose(run.time, grid(), rtol=0.0, atol=1e-12)
    check = model.simulate(T_END, rate=RATE, rtol=1e-12, atol=1e-15, channels=["slider.ax"])
    assert check.status == "finished", check.message
    ax = run["slider.ax"]
    impacts = sum(len(v) for v in run.impacts.values())
    return Reference(run.time, ax, wall, nrmse(check["slider.ax"], ax), impacts)


@dataclass
class Row:
    """One configuration of a peer or of jointgap."""

    peer: str  # "SciPy", "Exudyn" or "jointgap"
    method: str
    rtol: float  # or the step size, for fixed-step methods (see ``setting``)
    wall: float | None = None  # best of the repetitions [s], solve + 10 kHz output
    solve: float | None = None  # of which the solve alone (SciPy) [s]
    runs: int = 0
    error: float | None = None
    nfev: int | None = None
    njev: int | None = None
    steps: int | None = None
    note: str = ""
    cpu: float | None = None  # process CPU time, best of the repetitions [s]
    setting: str = "rtol"  # what ``rtol`` holds: "rtol" or "h" (fixed step [s])


JOINTGAP_METHODS = ("auto", "radau5")
"""jointgap's methods set against the peers; the fastest at each accuracy is compared, as
the peers' fastest is."""


def timed_jointgap(model: jointgap.Model, rtol: float, method: str) -> tuple[float, float, Any]:
    """One ``simulate`` (``method``, atol = 1e-3 x rtol, slider.ax at 10 kHz): its wall
    and process CPU time [s] and its result."""
    start, cpu_start = time.perf_counter(), time.process_time()
    result = model.simulate(
        T_END, rate=RATE, rtol=rtol, atol=1e-3 * rtol, method=method, channels=["slider.ax"]
    )
    return time.perf_counter() - start, time.process_time() - cpu_start, result


def run_jointgap(
    model: jointgap.Model, rtol: float, ref: np.ndarray, repeats: int = 2, method: str = "auto"
) -> Row:
    """jointgap's ``simulate`` (``method``, atol = 1e-3 x rtol, slider.ax at 10 kHz), the
    model loaded once: wall and process CPU time of the Python call, best of ``repeats``."""
    row = Row("jointgap", method, rtol)
    for _ in range(repeats):
        wall, cpu, result = timed_jointgap(model, rtol, method)
        row.runs += 1
        if result.status != "finished":
            row.note = f"{result.status}: {result.message}"
            return row
        row.wall = wall if row.wall is None else min(row.wall, wall)
        row.cpu = cpu if row.cpu is None else min(row.cpu, cpu)
        row.error = nrmse(result["slider.ax"], ref)
        stats = result.stats
        row.nfev, row.njev = stats["rhs_evaluations"], stats["jacobian_evaluations"]
        row.steps = stats["accepted_steps"] + stats["rejected_steps"]
    return row


PAIRED_ROUNDS = 5
"""Rounds of a paired timing (see ``paired_ratio``)."""


def paired_ratio(
    peer_cpu: Callable[[], float], model: jointgap.Model, rtol: float, method: str
) -> dict[str, Any]:
    """One matched pair timed in alternation: each round one peer run (``peer_cpu``
    returns its process CPU time [s]) and jointgap's best of 3, and the ratio of the
    round; the figure is the median of the rounds' ratios. On this shared machine a core's
    speed moves by 10-30 % within seconds, so two sides timed minutes apart differ by that
    much from the machine alone (the same pair read 18x and 22x in two runs); alternating
    puts both sides of each ratio in the same stretch."""
    rounds = []
    for _ in range(PAIRED_ROUNDS):
        peer = peer_cpu()
        ours = min(timed_jointgap(model, rtol, method)[1] for _ in range(3))
        rounds.append({"peer_cpu": peer, "jointgap_cpu": ours, "ratio": peer / ours})
    return {
        "rounds": rounds,
        "ratio_median": statistics.median(r["ratio"] for r in rounds),
    }


def paired_text(paired: dict[str, Any] | None) -> str:
    """A paired timing for a table: median ratio, and the rounds' range."""
    if not paired:
        return ""
    ratios = [r["ratio"] for r in paired["rounds"]]
    return f"{paired['ratio_median']:.1f}x ({min(ratios):.1f}-{max(ratios):.1f})"


def fastest(rows: list[Row], peer: str, target: float, key: str = "wall") -> Row | None:
    """The cheapest row of ``peer`` (by ``key``: "wall" or "cpu") whose NRMSE meets target."""
    ok = [
        r
        for r in rows
        if r.peer == peer and r.error is not None and r.error <= target and getattr(r, key)
    ]
    return min(ok, key=lambda r: getattr(r, key) or math.inf, default=None)


def write_json(name: str, payload: dict[str, Any]) -> Path:
    """benchmarks/results/<name>, with the machine, the commit and the load added."""
    payload = {
        "machine": machine(),
        "commit": commit(),
        "load_average_end": load_text(),
        "python": sys.version.split()[0],
        "numpy": np.__version__,
        "jointgap": jointgap.__version__,
        **payload,
    }
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / name
    path.write_text(json.dumps(payload, indent=1, default=_plain) + "\n")
    return path


def row_dict(row: Row) -> dict[str, Any]:
    return asdict(row)


def _plain(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(f"not JSON: {type(x)}")
