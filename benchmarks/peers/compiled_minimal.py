"""Peer benchmark: the founding clearance case as a special-purpose compiled program.

The speed issue measures jointgap against "a special-purpose C program of the same model
(minimal coordinates, Radau IIA with analytic Jacobian)" that needs about 3 ms for NRMSE
2e-5 and 6 ms for 1e-7 on this machine kind; those two figures are quoted, not measured
here. This benchmark measures a program of that kind on this machine, in the same process
and run as jointgap's ``simulate``: ``crates/jointgap-core/examples/minimal_slider_crank.rs``
writes the rod angle and slider position equations by hand (those of
``scipy_slider_crank.py``, in Rust) and integrates the four states with jointgap's Radau
IIA step, a forward-difference Jacobian of the four states, no event location (the
ADAMS IMPACT law needs no onset speed), the solve split at the end of the crank's ramp.

Both sides record the slider acceleration at 10 kHz; this script scores them against the
converged jointgap run of ``common.py`` and compares the fastest of each side at equal
accuracy (wall time, best of 5 runs for the program and of 3 for jointgap, in Rust).

Run from the repository root after ``make install``:

    .venv/bin/python benchmarks/peers/compiled_minimal.py

Writes benchmarks/output/peers_minimal.md and benchmarks/results/peers_minimal.json.
About 1 minute (the first build of the example adds about a minute).
"""

from __future__ import annotations

import json
import subprocess
import tempfile
import time
from pathlib import Path

import jointgap
import numpy as np
from common import (
    C_PROGRAM_MS,
    MODEL,
    OUTPUT,
    ROOT,
    TARGETS,
    Row,
    fastest,
    fmt,
    load_text,
    machine,
    nrmse,
    reference,
    reference_summary,
    row_dict,
    write_json,
)

OUT = OUTPUT / "peers_minimal.md"
MATCHED = (*TARGETS, 1e-7)
PROGRAM = "compiled minimal"


def run_example(model: jointgap.Model) -> list[dict]:
    """Builds and runs the example on the model; its rows (one per side, method, rtol)."""
    with tempfile.TemporaryDirectory() as tmp:
        model_path, out_path = Path(tmp) / "model.json", Path(tmp) / "runs.json"
        model_path.write_text(model.to_json())
        subprocess.run(
            ["cargo", "run", "--release", "-q", "-p", "jointgap-core", "--example"]
            + ["minimal_slider_crank", "--", str(model_path), str(out_path)],
            cwd=ROOT,
            check=True,
        )
        return json.loads(out_path.read_text())


def main() -> None:
    load_start, begun = load_text(), time.perf_counter()
    model = jointgap.load(MODEL)
    converged = reference(model)
    print(f"reference: {converged.wall:.2f} s; rtol 1e-12 differs by NRMSE {converged.error:.1e}")
    rows = []
    for run in run_example(model):
        peer = PROGRAM if run["side"] == "minimal" else "jointgap"
        row = Row(peer, run["method"], run["rtol"], wall=run["wall"], runs=run["runs"])
        row.error = nrmse(np.asarray(run["ax"]), converged.ax)
        row.nfev, row.steps = run["nfev"], run["steps"] + run["rejected"]
        rows.append(row)
    # The program must be the same mechanism: it converges to the reference.
    tightest = min((r for r in rows if r.peer == PROGRAM), key=lambda r: r.rtol)
    assert tightest.error is not None and tightest.error < 1e-6, tightest
    write(rows, converged.wall, converged.error, load_start, time.perf_counter() - begun)


def write(
    rows: list[Row], ref_wall: float, ref_error: float, load_start: str, total: float
) -> None:
    lines = [
        "## Peer: the founding clearance case as a special-purpose compiled program",
        "",
        f"`benchmarks/peers/compiled_minimal.py`. {machine()} Load average (1, 5, 15 min) "
        f"{load_start} at the start, {load_text()} at the end; the whole run took {total:.0f} s.",
        "",
        "Case: `examples/slider_crank_clearance.toml`, 0 to 0.5 s. Program "
        "(`crates/jointgap-core/examples/minimal_slider_crank.rs`): rod angle and slider "
        "position as unknowns, equations of motion by hand, jointgap's Radau IIA step with a "
        "forward-difference Jacobian, atol = 1e-3 x rtol, no event location, split at "
        "t = 0.2 s, slider acceleration from the equations at quintic-Hermite samples on the "
        "10 kHz grid. jointgap: `simulate` (Rust, model parsed once, `channels = "
        "['slider.ax']`, rate 10 kHz). Wall time: best of 5 runs (program), of 3 (jointgap), "
        "in one process. NRMSE: RMS of the slider.ax difference over the reference's max - min.",
        "",
        f"Reference: jointgap at rtol 1e-11, atol 1e-14 ({ref_wall:.2f} s); jointgap at "
        f"rtol 1e-12 differs from it by NRMSE **{ref_error:.1e}**.",
        "",
        "| side | method | rtol | wall [ms] | NRMSE ax | RHS | steps + rejected |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r.peer} | {r.method} | {r.rtol:.0e} | {fmt(r.wall and r.wall * 1e3, '.2f')} | "
            f"{fmt(r.error, '.1e')} | {fmt(r.nfev, 'd')} | {fmt(r.steps, 'd')} |"
        )
    lines += [
        "",
        "**At matched accuracy**: per NRMSE target, the fastest configuration of each side "
        "meeting it; ratio = jointgap wall / program wall. The last column sets the program "
        "against the issue's quoted C program ("
        + ", ".join(f"{ms:.0f} ms at {nrmse:.0e}" for nrmse, ms in C_PROGRAM_MS.items())
        + ").",
        "",
        "| target NRMSE | program (rtol) | program [ms] | jointgap (method, rtol) | "
        "jointgap [ms] | jointgap / program | program / quoted C |",
        "|---:|---|---:|---|---:|---:|---:|",
    ]
    summary = []
    for target in MATCHED:
        p, j = fastest(rows, PROGRAM, target), fastest(rows, "jointgap", target)
        ratio = j.wall / p.wall if p and j and p.wall and j.wall else None
        quoted = C_PROGRAM_MS.get(target)
        to_c = p.wall * 1e3 / quoted if p and p.wall and quoted else None
        summary.append(
            {
                "target": target,
                "program": None if p is None else row_dict(p),
                "jointgap": None if j is None else row_dict(j),
                "ratio_wall": ratio,
                "program_to_quoted_c": to_c,
            }
        )
        lines.append(
            f"| {target:.0e} | "
            + (f"{p.rtol:.0e} (NRMSE {p.error:.1e})" if p else "not met")
            + f" | {fmt(p.wall * 1e3 if p and p.wall else None, '.2f')} | "
            + (f"{j.method} {j.rtol:.0e} (NRMSE {j.error:.1e})" if j else "not met")
            + f" | {fmt(j.wall * 1e3 if j and j.wall else None, '.2f')} | "
            + f"{fmt(ratio, '.1f')}x | {fmt(to_c, '.1f')} |"
        )
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines[-len(MATCHED) - 2 :]))
    print(f"wrote {OUT.relative_to(ROOT)}")
    path = write_json(
        "peers_minimal.json",
        {
            "case": "examples/slider_crank_clearance.toml, 0 to 0.5 s, slider.ax at 10 kHz",
            "program": "crates/jointgap-core/examples/minimal_slider_crank.rs",
            "quoted_c_program_ms": {f"{k:.0e}": v for k, v in C_PROGRAM_MS.items()},
            "timing": "wall time in one Rust process, best of 5 (program) and 3 (jointgap)",
            "reference": reference_summary(ref_wall, ref_error),
            "runs": [row_dict(r) for r in rows],
            "matched_accuracy": summary,
            "load_average_start": load_start,
            "total_s": total,
        },
    )
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
