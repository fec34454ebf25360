"""Issue 6's speed targets side by side: each figure measured by `make bench` (and the
peers by `make bench-peers`), its target and whether it is met; plus the memory of a
long streamed run and a profile per benchmark (where the time goes, stage by stage).

Reads benchmarks/results/{founding,batch,scaling,peers_scipy,peers_exudyn}.json, measures
memory and profiles itself, prints a markdown table and writes
benchmarks/results/targets.json. Run standalone after `make bench`:
`.venv/bin/python benchmarks/targets.py`."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import jointgap
from benchmark_models import four_bar_chain, n_link_chain
from recording import write_results

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
CLEARANCE = ROOT / "examples" / "slider_crank_clearance.toml"

# Peak RSS from /proc/self/status (VmHWM, this process's own memory since its exec), not
# ru_maxrss: Linux carries ru_maxrss over from the parent at fork, so a child of a large
# process (make bench's) would report the parent's size.
MEMORY_RUN = """
import sys, tempfile, time, jointgap
def peak():
    line = next(l for l in open("/proc/self/status") if l.startswith("VmHWM:"))
    return int(line.split()[1]) * 1024
baseline = peak()
model = jointgap.load(sys.argv[1])
with tempfile.TemporaryDirectory() as folder:
    start = time.perf_counter()
    result = model.simulate(60.0, rate=10_000, stream=folder + "/run.parquet")
    wall = time.perf_counter() - start
    largest = max(abs(result["slider.ax"]))
print(peak(), wall, len(result.time), baseline)
"""


def _load(name: str) -> dict[str, Any] | None:
    path = RESULTS / f"{name}.json"
    return json.loads(path.read_text()) if path.exists() else None


def memory_of_long_run() -> dict[str, Any]:
    """Peak resident memory of a fresh process that simulates the founding case for 60 s
    at 10 kHz (600 001 samples of 48 channels, 230 MB if held) streamed to Parquet, then
    reads one channel back; and the same process's peak after ``import jointgap`` alone
    (VmHWM both), so that the figure says what the run adds."""
    out = subprocess.run(
        [sys.executable, "-c", MEMORY_RUN, str(CLEARANCE)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.split()
    rss, wall, samples, baseline = int(out[0]), float(out[1]), int(out[2]), int(out[3])
    return {
        "peak_rss_bytes": rss,
        "import_rss_bytes": baseline,
        "wall_s": wall,
        "samples": samples,
        "target_bytes": 200e6,
    }


PROFILED = {
    "founding case, auto, default tolerances, 0.5 s at 10 kHz": (
        lambda: jointgap.load(CLEARANCE),
        {"t_end": 0.5, "rate": 10_000},
    ),
    "four-bar chain N = 50, dopri5, 0.2 s": (
        lambda: four_bar_chain(50),
        {"t_end": 0.2, "rate": 1000, "method": "dopri5", "channels": ["system.*"]},
    ),
    "N-link chain N = 50, dopri5, 0.2 s": (
        lambda: n_link_chain(50),
        {"t_end": 0.2, "rate": 1000, "method": "dopri5", "channels": ["system.*"]},
    ),
}
STAGES = ("forces", "linear_solves", "jacobians", "output", "events", "projection")


def profiles() -> dict[str, dict[str, float]]:
    """Seconds per stage of each profiled benchmark (the best of three by total)."""
    out: dict[str, dict[str, float]] = {}
    for name, (build, options) in PROFILED.items():
        model = build()
        runs = [model.simulate(**options, profile=True) for _ in range(3)]
        best = min(runs, key=lambda r: r.stats["profile"]["total"])
        out[name] = {**best.stats["profile"], "rhs_evaluations": best.stats["rhs_evaluations"]}
    return out


def _peer_ratio(matched: dict[str, Any]) -> tuple[float, str]:
    """A peer's CPU-time ratio at one matched accuracy: the median of the paired rounds
    (both sides timed in alternation, ``peers/common.py``) where the run has them, else
    the ratio of the two sweeps' best times."""
    paired = matched.get("paired")
    if paired:
        ratios = [r["ratio"] for r in paired["rounds"]]
        return paired["ratio_median"], (
            f"median of {len(ratios)} paired rounds, {min(ratios):.1f}-{max(ratios):.1f}; "
            f"the sweeps' best times: {matched['ratio_cpu']:.1f}x"
        )
    return matched["ratio_cpu"], "the sweeps' best times"


def _row(figure: str, value: str, target: str, met: bool | None) -> str:
    verdict = "n/a" if met is None else ("met" if met else "**not met**")
    return f"| {figure} | {value} | {target} | {verdict} |"


def targets_table() -> str:
    rows: list[dict[str, Any]] = []

    def add(
        figure: str, value: float | None, target: str, met: bool | None, unit: str = ""
    ) -> None:
        rows.append({"figure": figure, "value": value, "target": target, "met": met, "unit": unit})

    founding = _load("founding")
    for c_target in (2e-5, 1e-7):
        best = None
        if founding:
            candidates = [m for m in founding["matched_accuracy"] if m["target_nrmse"] == c_target]
            best = min(candidates, key=lambda m: m["ratio_to_c"], default=None)
        add(
            f"founding case at NRMSE {c_target:.0e}: simulate time / C program's"
            + (f" ({best['method']}, rtol {best['rtol']:.0e})" if best else ""),
            best["ratio_to_c"] if best else None,
            "<= 5",
            best["ratio_to_c"] <= 5 if best else None,
            "x",
        )
    minimal = _load("peers_minimal")
    for m in minimal["matched_accuracy"] if minimal else []:
        # The targets with a quoted C figure (2e-5, 1e-7).
        if m["program_to_quoted_c"] is not None and m["ratio_wall"] is not None:
            add(
                f"founding case at NRMSE {m['target']:.0e}: simulate time / a compiled "
                "minimal-coordinate program's, measured in one run (jointgap's Radau IIA on 4 "
                f"states: {m['program']['wall'] * 1e3:.1f} ms, "
                f"{m['program_to_quoted_c']:.1f}x the quoted C figure)",
                m["ratio_wall"],
                "for scale",
                None,
                "x",
            )
    scipy = _load("peers_scipy")
    if scipy:
        tight = min(scipy["matched_accuracy"], key=lambda m: m["target"])
        ratio, how = _peer_ratio(tight)
        add(
            f"fastest SciPy method / jointgap at NRMSE {tight['target']:.0e} "
            f"({tight['scipy']['method']}; {how})",
            ratio,
            ">= 30",
            ratio >= 30,
            "x",
        )
    else:
        add("fastest SciPy method / jointgap", None, ">= 30", None)
    exudyn = _load("peers_exudyn")
    if exudyn:
        overall = [m for m in exudyn["matched_accuracy"] if m.get("which") == "overall"]
        tight = min(overall, key=lambda m: m["target"])
        ratio, how = _peer_ratio(tight)
        add(
            f"fastest Exudyn solver / jointgap at NRMSE {tight['target']:.0e} "
            f"({tight['exudyn']['method']}; {how})",
            ratio,
            ">= 100",
            ratio >= 100,
            "x",
        )
    else:
        add("fastest Exudyn solver / jointgap", None, ">= 100", None)
    batch = _load("batch")
    if batch:
        add(
            "batch throughput, 2 threads / 1",
            batch["throughput_ratio"],
            ">= 1.8",
            batch["throughput_ratio"] >= 1.8,
            "x",
        )
        add(
            "Python overhead per run in a batch",
            batch["overhead_per_run_s"] * 1e3,
            "< 1 ms",
            batch["overhead_per_run_s"] < 1e-3,
            "ms",
        )
    scaling = _load("scaling")
    if scaling:
        for chain in scaling["chains"]:
            fit = chain["per_step_fit"]
            add(
                f"{chain['label']}: cost per step ~ N^p, N {fit['n_from']}-{fit['n_to']}",
                fit["exponent"],
                "p <= 1.1",
                fit["exponent"] <= 1.1,
            )
    memory = memory_of_long_run()
    add(
        f"peak memory, 60 s at 10 kHz streamed ({memory['samples']} samples, "
        f"{memory['wall_s']:.0f} s; {memory['import_rss_bytes'] / 1e6:.0f} MB after "
        "`import jointgap`)",
        memory["peak_rss_bytes"] / 1e6,
        "< 200 MB",
        memory["peak_rss_bytes"] < memory["target_bytes"],
        "MB",
    )
    profile = profiles()

    write_results("targets", {"targets": rows, "memory": memory, "profiles": profile})
    lines = [
        "## Issue 6 targets\n",
        "Each figure from this `make bench` run (peers from the last `make bench-peers`, "
        "read from benchmarks/results/); ratios taken within one run.\n",
        "| figure | measured | target | |",
        "|---|---:|---|---|",
    ]
    for r in rows:
        value = "not measured" if r["value"] is None else f"{r['value']:.3g} {r['unit']}".strip()
        lines.append(_row(r["figure"], value, r["target"], r["met"]))
    lines += [
        "\n**Where the time goes.** Share of the integration time per stage "
        "(`simulate(..., profile=True)`; each stage excludes the ones it calls; 'rest' is "
        "the integrators' own arithmetic):\n",
        "| benchmark | total [ms] | RHS | " + " | ".join(STAGES) + " | rest |",
        "|---|---:|---:|" + "---:|" * (len(STAGES) + 1),
    ]
    for name, p in profile.items():
        total = p["total"]
        rest = total - sum(p[s] for s in STAGES)
        shares = [f"{100 * p[s] / total:.0f} %" for s in STAGES]
        lines.append(
            f"| {name} | {1e3 * total:.1f} | {p['rhs_evaluations']} | {' | '.join(shares)} "
            f"| {100 * rest / total:.0f} % |"
        )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    print(targets_table())
