"""Scale with size (issue 6): cost per step against the size of the mechanism.

Two mechanisms from :mod:`jointgap.benchmark_models`, for N in the geometric series
N = 2 x 10^(k/5) (2, 3, 5, 8, 13, 20, 32, 50, 80, 126, 200):

- ``four_bar_chain(N)``: the chain of N four-bar loops (IFToMM benchmark A02, 2N + 1
  bars of 1 m and 1 kg, B_0 at 1 m/s), 6N + 3 coordinates, 6N + 2 constraint rows;
- ``n_link_chain(N)``: N bars of 1 m and 1 kg pinned end to end, released from
  horizontal, 3N coordinates, 2N rows.

Each runs the same short simulation: 0 to 0.3 s (the four-bar chain's rockers reach the
singular horizontal position only at 0.72 s), ``method="dopri5"``, rtol 1e-8, atol
1e-10, one channel recorded at 10 Hz (3 samples, so the output costs nothing next to the
steps). The engine's own ``stats["wall_time"]`` is the time; cost per step is

    (wall time of the run - wall time of a run to t = 1e-9 s)
        / (steps of the run - steps of that run)

(steps = accepted + rejected), so compiling the model, assembling it (Newton on the
positions, redundant-row detection, velocities) and setting up the recorder, paid once
per run, do not enter it; cost per RHS evaluation is the same with the RHS counts. The
one-time cost ('assembly') is timed on its own: ``Model.check()``, which compiles and
assembles the model as a run does (and reads it from JSON, as a run does). Small N are
repeated (medians) until 1 s of runs is spent, at most 5 times; large N run once.

The exponent p of cost per step ~ N^p is fitted by least squares on log-log over
N >= 20 (the larger N, where fixed per-step overheads no longer dominate); the target of
issue 6 is linear growth, read as p <= 1.1. The series stops when the next N's predicted
time (extrapolated from the last two) would overrun the chain's share of the time budget
(``--budget``, 120 s for both chains by default): what was capped is printed and written.

Writes benchmarks/output/scaling.md, benchmarks/output/scaling.png (copied to
docs/images/bench_scaling.png) and benchmarks/results/scaling.json. Run from the
repository root after ``make install``:

    .venv/bin/python benchmarks/scaling.py [--budget SECONDS] [--max-n N]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import jointgap
import numpy as np
from jointgap.benchmark_models import four_bar_chain, n_link_chain

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from run import machine  # noqa: E402  (one description of the machine for every table)

OUT = ROOT / "benchmarks" / "output"
RESULTS = ROOT / "benchmarks" / "results"
DOC_IMAGE = ROOT / "docs" / "images" / "bench_scaling.png"

SERIES = sorted({round(2 * 10 ** (k / 5)) for k in range(11)})  # 2 ... 200
T_END = 0.3  # [s], before the four-bar chain's singular position (0.72 s)
T_SETUP = 1e-9  # [s], a run that assembles and takes one step
RTOL, ATOL = 1e-8, 1e-10
RATE = 10.0  # [Hz]: samples at 0, 0.1, 0.2, 0.3 s
FIT_FROM = 20  # fit the exponent over N >= FIT_FROM
TARGET = 1.1  # issue 6: cost per step grows linearly with N
REPEAT_TIME = 1.0  # [s] of runs per point for small N
MAX_REPEATS = 5


@dataclass
class Chain:
    """One family of mechanisms: its builder and the channel it records."""

    name: str
    label: str
    build: Callable[[int], jointgap.Model]
    channel: str


CHAINS = (
    Chain("four_bar_chain", "chain of N four-bar loops (A02)", four_bar_chain, "rocker_0.angle"),
    Chain("n_link_chain", "N-link chain", n_link_chain, "link_1.angle"),
)


@dataclass
class Point:
    """The measurement at one N."""

    n: int
    coordinates: int
    rows: int  # active constraint rows (redundant ones removed)
    redundant: int
    steps: int  # accepted + rejected, run to T_END
    rejected: int
    rhs: int
    projections: int
    setup_steps: int  # of the T_SETUP run
    setup_rhs: int
    run_s: float  # median engine wall time, run to T_END
    setup_s: float  # median engine wall time, run to T_SETUP
    assembly_s: float  # median time of Model.check(): compile + assemble
    repeats: int
    per_step_s: float = math.nan
    per_rhs_s: float = math.nan


@dataclass
class Fit:
    """Least-squares line through log(cost) against log(N)."""

    n_from: int
    n_to: int
    points: int
    exponent: float
    prefactor: float  # cost = prefactor * N^exponent [s]


@dataclass
class ChainResult:
    name: str
    label: str
    points: list[Point] = field(default_factory=list)
    capped: str = ""  # why the series stopped before its last N, if it did
    per_step_fit: Fit | None = None
    per_rhs_fit: Fit | None = None
    assembly_fit: Fit | None = None


def _run(model: jointgap.Model, t_end: float, channel: str) -> jointgap.Result:
    result = model.simulate(
        t_end, rate=RATE, method="dopri5", rtol=RTOL, atol=ATOL, channels=[channel]
    )
    if result.status != "finished":
        raise RuntimeError(f"{model.name}: {result.message}")
    return result


def measure(chain: Chain, n: int) -> Point:
    """Times ``Model.check`` (compile + assemble), a run to T_SETUP and one to T_END,
    repeated while cheap."""
    model = chain.build(n)
    runs: list[float] = []
    setups: list[float] = []
    checks: list[float] = []
    spent = 0.0
    full = setup = None
    warnings: list[str] = []
    while len(runs) < MAX_REPEATS and (not runs or spent < REPEAT_TIME):
        started = time.perf_counter()
        warnings = model.check()
        checks.append(time.perf_counter() - started)
        setup = _run(model, T_SETUP, chain.channel)
        full = _run(model, T_END, chain.channel)
        setups.append(setup.stats["wall_time"])
        runs.append(full.stats["wall_time"])
        spent += checks[-1] + setups[-1] + runs[-1]
    assert full is not None and setup is not None
    s, s0 = full.stats, setup.stats
    redundant = sum("redundant" in w for w in warnings)
    point = Point(
        n=n,
        coordinates=3 * len(model.bodies),
        rows=3 * len(model.bodies) - model.degrees_of_freedom() - redundant,
        redundant=redundant,
        steps=s["accepted_steps"] + s["rejected_steps"],
        rejected=s["rejected_steps"],
        rhs=s["rhs_evaluations"],
        projections=s["projections"],
        setup_steps=s0["accepted_steps"] + s0["rejected_steps"],
        setup_rhs=s0["rhs_evaluations"],
        run_s=statistics.median(runs),
        setup_s=statistics.median(setups),
        assembly_s=statistics.median(checks),
        repeats=len(runs),
    )
    extra = point.run_s - point.setup_s
    point.per_step_s = extra / (point.steps - point.setup_steps)
    point.per_rhs_s = extra / (point.rhs - point.setup_rhs)
    return point


def fit(points: list[Point], cost: Callable[[Point], float]) -> Fit | None:
    """Exponent over N >= FIT_FROM (the last three points if fewer than two there)."""
    chosen = [p for p in points if p.n >= FIT_FROM and cost(p) > 0]
    if len(chosen) < 2:
        chosen = [p for p in points if cost(p) > 0][-3:]
    if len(chosen) < 2:
        return None
    x = np.log([p.n for p in chosen])
    y = np.log([cost(p) for p in chosen])
    slope, intercept = np.polyfit(x, y, 1)
    return Fit(chosen[0].n, chosen[-1].n, len(chosen), float(slope), float(math.exp(intercept)))


def run_chain(chain: Chain, budget: float, max_n: int) -> ChainResult:
    """Measures the series up to ``max_n`` while the predicted time fits in ``budget``."""
    result = ChainResult(chain.name, chain.label)
    series = [n for n in SERIES if n <= max_n]
    started = time.perf_counter()
    for k, n in enumerate(series):
        pts = result.points
        if len(pts) >= 2:
            a, b = pts[-2], pts[-1]
            cost_a = a.run_s + a.setup_s + a.assembly_s
            cost_b = b.run_s + b.setup_s + b.assembly_s
            slope = max(math.log(cost_b / cost_a) / math.log(b.n / a.n), 1.0)
            predicted = cost_b * (n / b.n) ** slope
            left = budget - (time.perf_counter() - started)
            if predicted > left:
                result.capped = (
                    f"stopped after N = {b.n}: N = {n} would take about {predicted:.0f} s "
                    f"(extrapolated with exponent {slope:.1f}), {max(left, 0):.0f} s of the "
                    f"{budget:.0f} s budget left; not measured: N = "
                    + ", ".join(str(m) for m in series[k:])
                )
                break
        point = measure(chain, n)
        pts.append(point)
        print(
            f"  {chain.name} N = {n}: {point.per_step_s * 1e3:.4g} ms/step, "
            f"assembly {point.assembly_s * 1e3:.4g} ms ({point.repeats} runs)",
            flush=True,
        )
    result.per_step_fit = fit(result.points, lambda p: p.per_step_s)
    result.per_rhs_fit = fit(result.points, lambda p: p.per_rhs_s)
    result.assembly_fit = fit(result.points, lambda p: p.assembly_s)
    return result


def _exp(f: Fit | None) -> str:
    return "-" if f is None else f"{f.exponent:.2f} (N = {f.n_from}-{f.n_to}, {f.points} points)"


def table(results: list[ChainResult], header: str) -> str:
    lines = [
        "## Scale with size: cost per step against N\n",
        header,
        "",
        f"Each run: 0 to {T_END} s, dopri5, rtol {RTOL:.0e}, atol {ATOL:.0e}, one channel at "
        f"{RATE:.0f} Hz. 'per step' and 'per RHS' are (run - setup run) / (steps or RHS "
        f"of the run - of the setup run), the setup run ending at t = {T_SETUP:.0e} s, from "
        "the engine's wall time (`stats['wall_time']`); 'assembly' is the time of "
        "`Model.check()` (compile and assemble, once per run). Medians of 'runs' runs. "
        "'local p' is the slope of cost per step from the previous N.\n",
        "| mechanism | N | coordinates | rows | steps | RHS | runs | assembly [ms] "
        "| per step [ms] | per RHS [us] | local p |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for res in results:
        prev: Point | None = None
        for p in res.points:
            local = "-"
            if prev is not None and prev.per_step_s > 0 and p.per_step_s > 0:
                local = f"{math.log(p.per_step_s / prev.per_step_s) / math.log(p.n / prev.n):.2f}"
            lines.append(
                f"| {res.name} | {p.n} | {p.coordinates} | {p.rows} | {p.steps} | {p.rhs} "
                f"| {p.repeats} | {p.assembly_s * 1e3:.4g} | {p.per_step_s * 1e3:.4g} "
                f"| {p.per_rhs_s * 1e6:.4g} | {local} |"
            )
            prev = p
    lines += [
        "",
        "| figure | value | target | met |",
        "|---|---|---|---|",
    ]
    for res in results:
        f = res.per_step_fit
        met = "-" if f is None else ("yes" if f.exponent <= TARGET else "no")
        lines.append(f"| {res.name}: exponent of cost per step | {_exp(f)} | <= {TARGET} | {met} |")
        lines.append(f"| {res.name}: exponent of cost per RHS | {_exp(res.per_rhs_fit)} | - | - |")
        lines.append(f"| {res.name}: exponent of assembly | {_exp(res.assembly_fit)} | - | - |")
    lines.append("")
    for res in results:
        largest = res.points[-1].n if res.points else 0
        lines.append(
            f"- {res.name}: N = {', '.join(str(p.n) for p in res.points)} measured "
            f"(largest {largest}). " + (res.capped or "Whole series measured.")
        )
    return "\n".join(lines) + "\n"


def figure(results: list[ChainResult], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = {"four_bar_chain": "tab:blue", "n_link_chain": "tab:orange"}
    for res in results:
        c = colours.get(res.name, "k")
        n = np.array([p.n for p in res.points], dtype=float)
        ax.loglog(n, [p.per_step_s * 1e3 for p in res.points], "o", color=c, label=res.label)
        bx.loglog(n, [p.assembly_s * 1e3 for p in res.points], "o-", color=c, label=res.label)
        f = res.per_step_fit
        if f is not None:
            x = np.array([f.n_from, f.n_to], dtype=float)
            label = f"fit p = {f.exponent:.2f}"
            ax.loglog(x, f.prefactor * x**f.exponent * 1e3, "-", color=c, label=label)
            # Reference slope 1 through the first fitted point.
            x1 = np.array([f.n_from, max(SERIES)], dtype=float)
            ax.loglog(x1, f.prefactor * f.n_from**f.exponent * (x1 / f.n_from) * 1e3, ":", color=c)
    ax.plot([], [], ":", color="grey", label="slope 1 (target)")
    for a in (ax, bx):
        a.set_xlim(1.5, 1.3 * max(SERIES))
    ax.set_xlabel("N (loops or links)")
    ax.set_ylabel("cost per step [ms]")
    ax.set_title(f"dopri5 step, rtol {RTOL:.0e} (fit over N >= {FIT_FROM})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    bx.set_xlabel("N (loops or links)")
    bx.set_ylabel("assembly (once per run) [ms]")
    bx.set_title("compile + assemble")
    bx.grid(True, which="both", alpha=0.3)
    bx.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def engine_build() -> str:
    """When the compiled engine in use was built (its file's modification time, UTC)."""
    so = next(Path(jointgap.__file__).parent.glob("_jointgap*.so"), None)
    if so is None:
        return "unknown"
    return time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime(so.stat().st_mtime))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--budget", type=float, default=120.0, help="seconds for both chains")
    parser.add_argument("--max-n", type=int, default=max(SERIES), help="largest N")
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    header = machine() + f" Engine built {engine_build()}."
    four_bar_chain(2).simulate(T_SETUP)  # warm-up: load the extension
    results: list[ChainResult] = []
    started = time.perf_counter()
    for k, chain in enumerate(CHAINS):
        # Each chain gets an equal share of what is left.
        share = (args.budget - (time.perf_counter() - started)) / (len(CHAINS) - k)
        results.append(run_chain(chain, share, args.max_n))
    text = table(results, header)
    (OUT / "scaling.md").write_text(text)
    figure(results, OUT / "scaling.png")
    shutil.copyfile(OUT / "scaling.png", DOC_IMAGE)
    figures = []
    for res in results:
        f = res.per_step_fit
        figures.append(
            {
                "name": f"{res.name}: exponent p of cost per step ~ N^p",
                "value": None if f is None else round(f.exponent, 3),
                "target": f"<= {TARGET}",
                "met": None if f is None else f.exponent <= TARGET,
            }
        )
    data = {
        "benchmark": "scaling",
        "issue": 6,
        "what": "cost per dopri5 step against the size N of the mechanism",
        "machine": machine(),
        "commit": commit,
        "engine_build": engine_build(),
        "settings": {
            "t_end_s": T_END,
            "setup_t_end_s": T_SETUP,
            "method": "dopri5",
            "rtol": RTOL,
            "atol": ATOL,
            "rate_hz": RATE,
            "fit_from_n": FIT_FROM,
            "series": SERIES,
            "budget_s": args.budget,
            "max_n": args.max_n,
        },
        "figures": figures,
        "chains": [asdict(r) for r in results],
    }
    (RESULTS / "scaling.json").write_text(json.dumps(data, indent=1) + "\n")
    print(text)
    for path in (OUT / "scaling.md", OUT / "scaling.png", DOC_IMAGE, RESULTS / "scaling.json"):
        print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    os.chdir(ROOT)
    main()
