"""Scale with size (issue 6): cost per step against the size of the mechanism.

Two mechanisms from ``benchmarks/benchmark_models.py``, for N in the geometric series
N = 2 x 10^(k/5) (2, 3, 5, 8, 13, 20, 32, 50, 80, 126, 200):

- ``four_bar_chain(N)``: the chain of N four-bar loops (IFToMM benchmark A02, 2N + 1
  bars of 1 m and 1 kg, B_0 at 1 m/s), 6N + 3 coordinates, 6N + 2 constraint rows;
- ``n_link_chain(N)``: N bars of 1 m and 1 kg pinned end to end, released from
  horizontal, 3N coordinates, 2N rows.

**The run.** ``method="dopri5"``, rtol 1e-8, atol 1e-10, one channel, three samples,
and ``max_step`` = 0.2 ms, far below the steps the error control would take (30 ms for
the four-bar chain, 4 ms for the 126-link chain): every step is then a step of 0.2 ms
doing the same work at every N (6 RHS evaluations, no rejection; projections rare), and
the motion is the first K steps of the benchmark's, K from 20 to 3000 (0.6 s, before the
four-bar chain's singular position at 0.708 s). K is chosen per N so that the steps take
about 1 s (from the cost predicted by the previous N), so that they, not the one-time
assembly, dominate the run.

**The time.** Cost per step is timed inside the integration, from the run's progress
reports (``progress=``, about every 0.2 s of wall time): the wall time between the first
and the last report over the steps between them. Compiling and assembling the model
(Newton on the positions, redundant-row detection, velocities: dense SVDs) are done
before the first report and do not enter it, however long they take. A run too short
for two reports is timed as (engine wall time of the run - of a one-step run) / (K - 1),
the two runs repeated (medians) while under 1 s in all, at most 5 times. Cost per RHS is
cost per step x steps / RHS evaluations. The one-time cost ('assembly') is timed on its
own: ``Model.check()``, which reads, compiles and assembles the model as a run does.

**The fit.** The exponent p of cost per step ~ N^p is fitted by least squares on log-log
over N >= 20 (the larger N, where fixed per-step overheads no longer dominate); the
target of issue 6 is linear growth, read as p <= 1.1. The series stops when the next N's
predicted time (extrapolated from the last two) would overrun the chain's share of the
time budget (``--budget``, 120 s for both chains by default): what was capped is printed
and written.

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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from benchmark_models import four_bar_chain, n_link_chain  # noqa: E402
from recording import machine  # noqa: E402  (one description of the machine for every table)

OUT = ROOT / "benchmarks" / "output"
RESULTS = ROOT / "benchmarks" / "results"
DOC_IMAGE = ROOT / "docs" / "images" / "bench_scaling.png"
# The dense engine's figures (commit 90b3374, before the structured solve of 24b34fb),
# drawn faded behind the new ones for comparison.
BASELINE = RESULTS / "scaling_dense.json"

SERIES = sorted({round(2 * 10 ** (k / 5)) for k in range(11)})  # 2 ... 200
STEP = 2e-4  # [s], max_step: every step this long
K_MIN, K_MAX = 20, 3000  # steps per run; K_MAX * STEP = 0.6 s < 0.708 s (singular position)
STEPS_TIME = 1.0  # [s], wall time the steps of one run should take
RTOL, ATOL = 1e-8, 1e-10
FIT_FROM = 20  # fit the exponent over N >= FIT_FROM
TARGET = 1.1  # issue 6: cost per step grows linearly with N
REPEAT_TIME = 1.0  # [s] of runs per point when timed by difference
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
    steps: int  # accepted + rejected
    rejected: int
    rhs: int
    projections: int
    run_s: float  # engine wall time of the run (median when repeated)
    assembly_s: float  # median time of Model.check(): compile + assemble
    per_step_s: float
    per_rhs_s: float
    timed_by: str  # "progress" (inside the run) or "difference" (of two runs)
    timed_steps: int  # steps the per-step time is taken over
    repeats: int


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


def _run(
    model: jointgap.Model,
    steps: int,
    channel: str,
    progress: Callable[[float, int, int], object] | None = None,
) -> jointgap.Result:
    # Half a step off the grid: before commit 24b34fb, with t_end a whole number of steps,
    # rounding left a last step of about 1e-16 s that the engine refused (below its
    # smallest resolvable step) for some step counts (e.g. 259-323 at rtol 1e-8).
    t_end = (steps - 0.5) * STEP
    result = model.simulate(
        t_end,
        rate=2.0 / t_end,
        method="dopri5",
        rtol=RTOL,
        atol=ATOL,
        max_step=STEP,
        channels=[channel],
        progress=progress,
    )
    if result.status != "finished":
        raise RuntimeError(f"{model.name}: {result.message}")
    return result


def measure(chain: Chain, n: int, k: int) -> Point:
    """Times ``Model.check`` (compile + assemble) and a run of ``k`` steps of
    ``chain`` with ``n``, inside the run from its progress reports, or by difference
    with a one-step run when it is too short for two reports."""
    model = chain.build(n)
    reports: list[tuple[float, int]] = []

    def progress(_t: float, steps: int, _impacts: int) -> None:
        reports.append((time.perf_counter(), steps))

    started = time.perf_counter()
    warnings = model.check()
    checks = [time.perf_counter() - started]
    full = _run(model, k, chain.channel, progress)
    runs = [float(full.stats["wall_time"])]
    s = full.stats
    steps = s["accepted_steps"] + s["rejected_steps"]
    timed_by, repeats = "progress", 1
    if len(reports) >= 2 and reports[-1][1] - reports[0][1] >= 32:
        timed_steps = reports[-1][1] - reports[0][1]
        per_step = (reports[-1][0] - reports[0][0]) / timed_steps
    else:
        timed_by, timed_steps = "difference", steps - 1
        ones: list[float] = []
        spent = checks[0] + runs[0]
        while True:
            ones.append(float(_run(model, 1, chain.channel).stats["wall_time"]))
            spent += ones[-1]
            if len(runs) >= MAX_REPEATS or spent >= REPEAT_TIME:
                break
            started = time.perf_counter()
            model.check()
            checks.append(time.perf_counter() - started)
            runs.append(float(_run(model, k, chain.channel).stats["wall_time"]))
            spent += checks[-1] + runs[-1]
        repeats = len(runs)
        per_step = (statistics.median(runs) - statistics.median(ones)) / timed_steps
    redundant = sum("redundant" in w for w in warnings)
    return Point(
        n=n,
        coordinates=3 * len(model.bodies),
        rows=3 * len(model.bodies) - model.degrees_of_freedom() - redundant,
        redundant=redundant,
        steps=steps,
        rejected=s["rejected_steps"],
        rhs=s["rhs_evaluations"],
        projections=s["projections"],
        run_s=statistics.median(runs),
        assembly_s=statistics.median(checks),
        per_step_s=per_step,
        per_rhs_s=per_step * steps / s["rhs_evaluations"],
        timed_by=timed_by,
        timed_steps=timed_steps,
        repeats=repeats,
    )


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


def _extrapolate(
    points: list[Point], cost: Callable[[Point], float], n: int
) -> tuple[float, float]:
    """Cost at ``n`` from the last two points, with their slope (at least 1) on log-log;
    the slope too."""
    a, b = points[-2], points[-1]
    slope = 1.0
    if cost(a) > 0 and cost(b) > 0:
        slope = max(math.log(cost(b) / cost(a)) / math.log(b.n / a.n), 1.0)
    return max(cost(b), 0.0) * (n / b.n) ** slope, slope


def run_chain(chain: Chain, budget: float, max_n: int) -> ChainResult:
    """Measures the series up to ``max_n`` while the predicted time fits in ``budget``."""
    result = ChainResult(chain.name, chain.label)
    series = [n for n in SERIES if n <= max_n]
    started = time.perf_counter()
    for i, n in enumerate(series):
        pts = result.points
        k = K_MAX
        if len(pts) >= 2:
            step, slope = _extrapolate(pts, lambda p: p.per_step_s, n)
            assembly, _ = _extrapolate(pts, lambda p: p.assembly_s, n)
            k = min(max(round(STEPS_TIME / max(step, 1e-12)), K_MIN), K_MAX)
            predicted = 2 * assembly + k * step
            left = budget - (time.perf_counter() - started)
            if predicted > left:
                result.capped = (
                    f"stopped after N = {pts[-1].n}: N = {n} would take about "
                    f"{predicted:.0f} s ({k} steps of about {step:.2g} s, cost per step "
                    f"extrapolated with exponent {slope:.1f}, and assembly), "
                    f"{max(left, 0):.0f} s of the {budget:.0f} s budget left; not measured: "
                    "N = " + ", ".join(str(m) for m in series[i:])
                )
                break
        point = measure(chain, n, k)
        pts.append(point)
        print(
            f"  {chain.name} N = {n}: {point.per_step_s * 1e3:.4g} ms/step over "
            f"{point.timed_steps} steps ({point.timed_by}), assembly "
            f"{point.assembly_s * 1e3:.4g} ms",
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
        f"Each run: dopri5, rtol {RTOL:.0e}, atol {ATOL:.0e}, max_step {STEP * 1e3:g} ms "
        f"(every step that long: 6 RHS, no rejection), 'steps' steps from the benchmark's "
        "initial state, one channel, three samples. 'per step' is timed inside the run "
        "between its first and last progress report ('progress', over 'timed' steps) or, "
        "for runs too short for two reports, as (run - one-step run) / (steps - 1) from the "
        "engine's wall time ('difference', medians of 'runs' runs); 'per RHS' is per step x "
        "steps / RHS. 'assembly' is the time of `Model.check()` (read, compile and "
        "assemble, once per run). 'local p' is the slope of cost per step from the "
        "previous N.\n",
        "| mechanism | N | coordinates | rows | steps | RHS | projections | timed | runs "
        "| assembly [ms] | per step [ms] | per RHS [us] | local p |",
        "|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|",
    ]
    for res in results:
        prev: Point | None = None
        for p in res.points:
            local = "-"
            if prev is not None and prev.per_step_s > 0 and p.per_step_s > 0:
                local = f"{math.log(p.per_step_s / prev.per_step_s) / math.log(p.n / prev.n):.2f}"
            lines.append(
                f"| {res.name} | {p.n} | {p.coordinates} | {p.rows} | {p.steps} | {p.rhs} "
                f"| {p.projections} | {p.timed_by} ({p.timed_steps}) | {p.repeats} "
                f"| {p.assembly_s * 1e3:.4g} | {p.per_step_s * 1e3:.4g} "
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


def figure(results: list[ChainResult], path: Path, baseline: Path | None = None) -> None:
    """Cost per step (with the fits and slope 1) and assembly against N; the points of
    an earlier scaling.json ``baseline`` hollow and faded."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = {"four_bar_chain": "tab:blue", "n_link_chain": "tab:orange"}
    if baseline is not None and baseline.exists():
        old = json.loads(baseline.read_text())
        for chain in old["chains"]:
            c = colours.get(chain["name"], "k")
            ns = [p["n"] for p in chain["points"]]
            fit_ = chain.get("per_step_fit") or {}
            label = f"{chain['name']} at {old['commit']}" + (
                f", p = {fit_['exponent']:.2f}" if "exponent" in fit_ else ""
            )
            style = {"color": c, "mfc": "none", "alpha": 0.45}
            ax.loglog(
                ns, [p["per_step_s"] * 1e3 for p in chain["points"]], "s--", **style, label=label
            )
            bx.loglog(
                ns, [p["assembly_s"] * 1e3 for p in chain["points"]], "s--", **style, label=label
            )
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
    ax.set_title(f"dopri5 step of {STEP * 1e3:g} ms (fit over N >= {FIT_FROM})")
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
    parser.add_argument(
        "--baseline",
        type=Path,
        default=BASELINE,
        help="an earlier scaling.json drawn faded for comparison (default: the dense engine's)",
    )
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    header = machine() + f" Engine built {engine_build()}."
    four_bar_chain(2).simulate(STEP)  # warm-up: load the extension
    results: list[ChainResult] = []
    started = time.perf_counter()
    for k, chain in enumerate(CHAINS):
        # Each chain gets an equal share of what is left.
        share = (args.budget - (time.perf_counter() - started)) / (len(CHAINS) - k)
        results.append(run_chain(chain, share, args.max_n))
    text = table(results, header)
    (OUT / "scaling.md").write_text(text)
    figure(results, OUT / "scaling.png", args.baseline)
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
            "method": "dopri5",
            "rtol": RTOL,
            "atol": ATOL,
            "max_step_s": STEP,
            "steps_min_max": [K_MIN, K_MAX],
            "steps_wall_time_s": STEPS_TIME,
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
