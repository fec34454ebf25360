"""Instructions of one founding-case run, against the engine they were recorded on.

Wall time on a shared machine spreads by several per cent from run to run; the number of
instructions a run executes does not. A change of the engine's layout that moves no
result must keep it: each run below is counted under callgrind (valgrind) and compared
with ``benchmarks/results/instructions.json``.

The runs: the founding clearance slider-crank (examples/slider_crank_clearance.toml),
0.5 s, slider.ax at 10 kHz, with the default ``auto`` method at rtol 1e-8 (the default)
and 1e-7, and radau5 at 3e-9. The counted program is the core's ``one_run`` example: it
reads the model and the options, runs once and prints its counters, so the count is the
run's with a small fixed start-up.

Usage, from the repository root after ``make install``:

    .venv/bin/python benchmarks/instructions.py           # compare (make bench)
    .venv/bin/python benchmarks/instructions.py --record  # record the reference anew

Writes benchmarks/output/instructions.md.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import jointgap

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "benchmarks" / "results" / "instructions.json"
REPORT = ROOT / "benchmarks" / "output" / "instructions.md"
PROGRAM = ROOT / "target" / "release" / "examples" / "one_run"
#: Largest change of a run's count that still reads as the same engine.
TOLERANCE = 0.03

#: The interpreted engine with the applied forces' Jacobian: its layout is what this count
#: watches (benchmarks/compiled.py counts the compiled evaluation against it,
#: benchmarks/jacobian.py the exact Jacobians).
COMMON = {
    "t_end": 0.5,
    "rate": 10_000.0,
    "channels": ["slider.ax"],
    "compiled": False,
    "exact_jacobian": False,
}
RUNS = {
    "auto, rtol 1e-8 (the default)": {**COMMON, "rtol": 1e-8},
    "auto, rtol 1e-7": {**COMMON, "rtol": 1e-7, "atol": 1e-9},
    "radau5, rtol 3e-9": {**COMMON, "rtol": 3e-9, "atol": 3e-11, "method": "radau5"},
}
_COLLECTED = re.compile(r"Collected\s*:\s*(\d+)")


def count(model: Path, options: dict[str, object], folder: Path) -> int:
    """Instructions of one run of ``one_run`` under callgrind."""
    path = folder / "options.json"
    path.write_text(json.dumps(options))
    done = subprocess.run(
        [
            "valgrind",
            "--tool=callgrind",
            f"--callgrind-out-file={folder / 'callgrind.out'}",
            str(PROGRAM),
            str(model),
            str(path),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    found = _COLLECTED.search(done.stderr)
    if found is None:
        raise RuntimeError(f"callgrind printed no count:\n{done.stderr[-2000:]}")
    return int(found.group(1))


def git_commit() -> str:
    done = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return done.stdout.strip() or "unknown"


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--record", action="store_true", help="record the reference anew")
    args = parser.parse_args()
    if shutil.which("valgrind") is None:
        print("instructions: valgrind is not installed (apt-get install valgrind); skipped")
        return 0
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "jointgap-core", "--example", "one_run"],
        check=True,
        cwd=ROOT,
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        model = folder / "model.json"
        model.write_text(jointgap.load(ROOT / "examples" / "slider_crank_clearance.toml").to_json())
        counts = {name: count(model, options, folder) for name, options in RUNS.items()}
    commit = git_commit()
    if args.record:
        REFERENCE.write_text(json.dumps({"commit": commit, "runs": counts}, indent=1) + "\n")
        print(f"recorded in {REFERENCE.relative_to(ROOT)} at {commit}")
        return 0
    reference = json.loads(REFERENCE.read_text())
    lines = [
        f"Instructions (callgrind) of one founding-case run: {commit} against "
        f"{reference['commit']} (the reference)",
        "",
        "| run | reference | now | change |",
        "|---|---:|---:|---:|",
    ]
    worst = 0.0
    for name, now in counts.items():
        was = reference["runs"][name]
        change = now / was - 1.0
        worst = max(worst, abs(change))
        lines.append(f"| {name} | {was / 1e6:.1f} M | {now / 1e6:.1f} M | {100 * change:+.2f} % |")
    verdict = "within" if worst <= TOLERANCE else "BEYOND"
    lines += ["", f"Largest change {100 * worst:.2f} %: {verdict} {100 * TOLERANCE:.0f} %."]
    text = "\n".join(lines) + "\n"
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
