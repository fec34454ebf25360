"""Compiled against interpreted evaluation, measured side by side in one run.

The founding clearance case (examples/slider_crank_clearance.toml, 0.5 s, slider.ax at
10 kHz, ``auto`` at rtol 1e-8):

1. Instructions (callgrind, when valgrind is installed) of the core's ``one_run``
   example: one run interpreted, one run compiled (its compiling included), and a run
   compiled that takes its code from the process's cache (the count of two runs in one
   process minus that of one). Each count divided by the run's evaluations gives the
   cost per evaluation of everything a run does, the integrator and output included.
2. Wall time: in this process, runs alternating so that a load on the machine falls on
   both, the first compiled run (compiling) and the median of the next ones (from the
   cache) against the median of interpreted runs; and 20 runs in one process of the
   core's ``one_run`` (compiling once), compiled against interpreted, three times each.
3. A batch of variants of the clearance (``simulate_batch``, two threads): the variants'
   constants differ, and as parameters of the code they share it.
4. The spatial four-bar with a spherical clearance joint (examples/
   spatial_four_bar_clearance.toml, 0.5 s, 1 kHz, ``auto`` at rtol 1e-8): instructions
   per evaluation and wall times as for the founding case (compiled and interpreted runs
   are the same bits, so at equal accuracy by construction), and where the time goes
   (the run's own profile): the evaluations against everything else a run does.
5. Where the time goes, for the founding case and the four-bar: the run's own profile
   stage by stage (evaluations, Jacobians and factors, event search, output samples,
   projection, and the integrator's own work), compiled and interpreted.
6. The slider-crank with two clearance joints (examples/slider_crank_two_clearances.toml,
   as the founding case): each joint's contact is a block of its own ways, so one path
   covers every combination of the two joints' branches. Instructions and wall times.
7. Worn parts: the founding case with its bearing worn into an oval (20 um) with a
   pocket (60 um) and its journal worn at two sides (10 um). The contact search over
   the profiles runs interpreted on both paths; instructions, wall times and profile.

Writes benchmarks/output/compiled.md and benchmarks/results/compiled.json.
"""

from __future__ import annotations

import json
import math
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import jointgap
from jointgap import simulate_batch
from jointgap.variants import with_parameters

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "slider_crank_clearance.toml"
SPATIAL = ROOT / "examples" / "spatial_four_bar_clearance.toml"
TWO_JOINTS = ROOT / "examples" / "slider_crank_two_clearances.toml"
PROGRAM = ROOT / "target" / "release" / "examples" / "one_run"
REPORT = ROOT / "benchmarks" / "output" / "compiled.md"
RESULTS = ROOT / "benchmarks" / "results" / "compiled.json"
RUN: dict[str, Any] = {"t_end": 0.5, "rate": 10_000.0, "channels": ["slider.ax"], "rtol": 1e-8}
SPATIAL_RUN: dict[str, Any] = {
    "t_end": 0.5,
    "rate": 1000.0,
    "channels": ["ground_rocker.omega"],
    "rtol": 1e-8,
}
REPEATS = 9
#: The worn founding case's wear tables [um] (item 7), at equally spaced angles.
OVAL_POCKET = [
    20 * (1 + math.cos(2 * t)) + (60 * (1 - ((t - 1) / 0.3) ** 2) if abs(t - 1) < 0.3 else 0)
    for t in (2 * math.pi * k / 72 for k in range(72))
]
TWO_SIDES = [10 * (1 + math.cos(2 * 2 * math.pi * k / 48)) for k in range(48)]
BATCH = 64
_COLLECTED = re.compile(r"Collected\s*:\s*(\d+)")


def instructions(model: Path, options: dict[str, Any], runs: int, folder: Path) -> tuple[int, str]:
    """Instructions of ``runs`` runs in one process under callgrind, and its printout."""
    path = folder / "options.json"
    path.write_text(json.dumps(options))
    done = subprocess.run(
        ["valgrind", "--tool=callgrind", f"--callgrind-out-file={folder / 'cg.out'}",
         str(PROGRAM), str(model), str(path), str(runs)],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    found = _COLLECTED.search(done.stderr)
    if found is None:
        raise RuntimeError(f"callgrind printed no count:\n{done.stderr[-2000:]}")
    return int(found.group(1)), done.stdout


def counts(source: Path, run: dict[str, Any]) -> dict[str, float] | None:
    """The three instruction counts and the evaluations of one run of the model in
    ``source``, or None without valgrind."""
    if shutil.which("valgrind") is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        model = folder / "model.json"
        model.write_text(jointgap.load(source).to_json())
        plain, out = instructions(model, {**run, "compiled": False}, 1, folder)
        evaluations = int(re.search(r"(\d+) evaluations", out).group(1))  # type: ignore[union-attr]
        cold, _ = instructions(model, run, 1, folder)
        twice, _ = instructions(model, run, 2, folder)
    return {
        "interpreted": plain,
        "compiled": cold,
        "cached": twice - cold,
        "evaluations": evaluations,
    }


def timings(source: Path, run: dict[str, Any]) -> dict[str, Any]:
    """Wall times [s] of the model in ``source``, compiled and interpreted, in this
    process."""
    model = jointgap.load(source)
    options = {k: v for k, v in run.items() if k != "t_end"}
    first = model.simulate(run["t_end"], **options)
    native: list[float] = []
    plain: list[float] = []
    for _ in range(REPEATS):
        for compiled, into in ((True, native), (False, plain)):
            start = time.perf_counter()
            model.simulate(run["t_end"], compiled=compiled, **options)
            into.append(time.perf_counter() - start)
    return {
        "first_compiled": first.stats["wall_time"],
        "compile_time": first.stats["compile_time"],
        "account": first.stats["compiled"],
        "compiled": statistics.median(native),
        "interpreted": statistics.median(plain),
    }


def where_the_time_goes(source: Path, run: dict[str, Any]) -> dict[str, dict[str, float]]:
    """The run's own profile [s], compiled (code from the cache) and interpreted: the
    evaluations (the compiled one in ``forces``; the interpreted one in ``forces`` and
    ``linear_solves``) against the rest of the run."""
    model = jointgap.load(source)
    options = {k: v for k, v in run.items() if k != "t_end"}
    model.simulate(run["t_end"], **options)
    out: dict[str, dict[str, float]] = {}
    for compiled in (True, False):
        profiles = [
            model.simulate(run["t_end"], compiled=compiled, profile=True, **options).stats[
                "profile"
            ]
            for _ in range(3)
        ]
        fastest = min(profiles, key=lambda p: p["total"])
        out["compiled" if compiled else "interpreted"] = dict(fastest)
    return out


def program_runs() -> dict[str, float]:
    """Wall time [s] of 20 runs in one process of ``one_run``, compiled and interpreted
    (the fastest of three each)."""
    times: dict[str, list[float]] = {"compiled": [], "interpreted": []}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        model = folder / "model.json"
        model.write_text(jointgap.load(MODEL).to_json())
        for _ in range(3):
            for name, compiled in (("compiled", True), ("interpreted", False)):
                path = folder / f"{name}.json"
                path.write_text(json.dumps({**RUN, "compiled": compiled}))
                start = time.perf_counter()
                subprocess.run([str(PROGRAM), str(model), str(path), "20"], check=True,
                               capture_output=True)  # fmt: skip
                times[name].append(time.perf_counter() - start)
    return {name: min(t) for name, t in times.items()}


def batch() -> dict[str, float]:
    """Wall time [s] of a batch of clearance variants, compiled and interpreted."""
    base = jointgap.load(MODEL)
    variants = [
        with_parameters(base, {"rod_slider.clearance": f"{0.2 + 0.6 * k / (BATCH - 1):.4f} mm"})
        for k in range(BATCH)
    ]
    out: dict[str, float] = {}
    for compiled in (True, False):
        start = time.perf_counter()
        results = simulate_batch(variants, 0.2, rate=2000, threads=2, compiled=compiled)
        out["compiled" if compiled else "interpreted"] = time.perf_counter() - start
        if compiled:
            out["compile_time"] = sum(r.stats["compile_time"] for r in results)
    return out


def count_table(counted: dict[str, float] | None) -> list[str]:
    """The callgrind counts as a table (none without valgrind)."""
    if counted is None:
        return []
    n = counted["evaluations"]
    lines = [
        "| run (callgrind) | instructions | per evaluation | against interpreted |",
        "|---|---:|---:|---:|",
    ]
    labels = {
        "interpreted": "interpreted",
        "compiled": "compiled, compiling included",
        "cached": "compiled, code from the cache",
    }
    for name, label in labels.items():
        c = counted[name]
        lines.append(
            f"| {label} | {c / 1e6:.1f} M | {c / n:.0f} | {counted['interpreted'] / c:.2f}x |"
        )
    return [*lines, ""]


def wall_rows(timed: dict[str, Any]) -> list[str]:
    """The account of a model's first run and its wall times, the head of a table."""
    return [
        f"Account of the first run: {timed['account']}",
        "",
        "| wall time (this process) | seconds | ratio |",
        "|---|---:|---:|",
        f"| first compiled run | {timed['first_compiled']:.4f} | "
        f"compile {timed['compile_time']:.4f} s |",
        f"| compiled, median of {REPEATS} | {timed['compiled']:.4f} | "
        f"{timed['interpreted'] / timed['compiled']:.2f}x |",
        f"| interpreted, median of {REPEATS} | {timed['interpreted']:.4f} | 1 |",
    ]


#: The profile's stages besides the evaluations, as the tables name them.
STAGES = {
    "jacobians": "Jacobians and LU factors",
    "events": "event search",
    "output": "output samples",
    "projection": "projection",
}


def profile_lines(profile: dict[str, dict[str, float]]) -> list[str]:
    """Where the time goes, stage by stage, compiled and interpreted (the run's own
    profile, which reads the clock at each stage: its total is a few per cent above an
    unmeasured run's), and the most that cheaper evaluations can give."""
    native, plain = profile["compiled"], profile["interpreted"]
    evaluation = {
        "compiled": native["forces"] + native["linear_solves"],
        "interpreted": plain["forces"] + plain["linear_solves"],
    }
    rows = []
    for name, p in (("compiled", native), ("interpreted", plain)):
        own = p["total"] - evaluation[name] - sum(p[stage] for stage in STAGES)
        cells = " | ".join(f"{p[stage]:.4f}" for stage in STAGES)
        rows.append(f"| {name} | {evaluation[name]:.4f} | {cells} | {own:.4f} | {p['total']:.4f} |")
    # Both runs take the same steps: the compiled run's rest is the work that is not
    # evaluation.
    rest = native["total"] - evaluation["compiled"]
    return [
        "Where the time goes (the run's profile, fastest of 3; each stage without the "
        "evaluations it makes; the integrator's own work is what the stages leave: its "
        "stage sums, error norms, Newton iterations' solves, step control, contact "
        "updates and the switching rule):",
        "",
        "| | evaluations [s] | " + " [s] | ".join(STAGES.values()) + " [s] | "
        "integrator's own [s] | total [s] |",
        "|---|" + "---:|" * (len(STAGES) + 3),
        *rows,
        "",
        f"With evaluations that cost nothing, a run would take the rest alone: "
        f"{plain['total'] / rest:.2f}x the interpreted run at most.",
    ]


def spatial_lines(spatial: dict[str, Any]) -> list[str]:
    """The spatial four-bar's counts, wall times and profile."""
    return [
        "The spatial four-bar with a spherical clearance joint "
        "(examples/spatial_four_bar_clearance.toml), 0.5 s, 1 kHz, auto at rtol 1e-8",
        "",
        *count_table(spatial["counts"]),
        *wall_rows(spatial["timings"]),
        "",
        *profile_lines(spatial["profile"]),
    ]


def worn_model(folder: Path) -> Path:
    """The founding case with worn parts (item 7), written into ``folder``."""
    text = MODEL.read_text()

    def table(key: str, depths: list[float]) -> str:
        return f"{key} = [" + ", ".join(f'"{w:.4f} um"' for w in depths) + "]\n"

    tables = table("bearing_wear", OVAL_POCKET) + table("journal_wear", TWO_SIDES)
    marker = 'clearance = "0.5 mm"\n'
    path = folder / "slider_crank_worn.toml"
    path.write_text(text.replace(marker, marker + tables, 1))
    return path


def main() -> int:
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "jointgap-core", "--example", "one_run"],
        check=True, cwd=ROOT,
    )  # fmt: skip
    counted = counts(MODEL, RUN)
    timed = timings(MODEL, RUN)
    founding_profile = where_the_time_goes(MODEL, RUN)
    program = program_runs()
    batched = batch()
    spatial = {
        "counts": counts(SPATIAL, SPATIAL_RUN),
        "timings": timings(SPATIAL, SPATIAL_RUN),
        "profile": where_the_time_goes(SPATIAL, SPATIAL_RUN),
    }
    two = {"counts": counts(TWO_JOINTS, RUN), "timings": timings(TWO_JOINTS, RUN)}
    with tempfile.TemporaryDirectory() as tmp:
        worn_source = worn_model(Path(tmp))
        worn = {
            "counts": counts(worn_source, RUN),
            "timings": timings(worn_source, RUN),
            "profile": where_the_time_goes(worn_source, RUN),
        }
    lines = [
        f"Compiled against interpreted evaluation ({platform.machine()}, "
        f"{platform.processor() or 'cpu'}), the founding clearance case, 0.5 s, auto at rtol 1e-8",
        "",
    ]
    lines += count_table(counted)
    lines += [
        *wall_rows(timed),
        f"| batch of {BATCH} clearance variants (0.2 s each, 2 threads), compiled | "
        f"{batched['compiled']:.3f} | {batched['interpreted'] / batched['compiled']:.2f}x "
        f"(compiling {batched['compile_time']:.3f} s of thread time) |",
        f"| the same batch interpreted | {batched['interpreted']:.3f} | 1 |",
        f"| 20 runs in one process (one_run), compiled | {program['compiled']:.3f} | "
        f"{program['interpreted'] / program['compiled']:.2f}x |",
        f"| 20 runs in one process (one_run), interpreted | {program['interpreted']:.3f} | 1 |",
    ]
    lines += ["", *profile_lines(founding_profile)]
    lines += ["", *spatial_lines(spatial)]
    lines += [
        "",
        "Two clearance joints (examples/slider_crank_two_clearances.toml), 0.5 s, 10 kHz, "
        "auto at rtol 1e-8",
        "",
        *count_table(two["counts"]),
        *wall_rows(two["timings"]),
        "",
        "Worn parts: the founding case, its bearing worn into an oval (20 um) with a pocket "
        "(60 um), its journal worn at two sides (10 um); 0.5 s, 10 kHz, auto at rtol 1e-8",
        "",
        *count_table(worn["counts"]),
        *wall_rows(worn["timings"]),
        "",
        *profile_lines(worn["profile"]),
    ]
    text = "\n".join(lines) + "\n"
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text(text)
    figures = {
        "counts": counted,
        "timings": timed,
        "profile": founding_profile,
        "program": program,
        "batch": batched,
        "spatial": spatial,
        "two_joints": two,
        "worn": worn,
    }
    RESULTS.write_text(json.dumps(figures, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
