"""`make bench`, Python part: per-call cost of `Model.simulate` against the engine's own
wall time; speed against accuracy per integrator on the founding clearance case
(benchmarks/output/clearance.md); then benchmarks/output/results.md with every table (the
Rust ones come from benchmarks/output/bench_ideal.md and diffsol.md, written by the Rust
benchmarks).

Run from the repository root after `make install`: `.venv/bin/python benchmarks/run.py`;
`.venv/bin/python benchmarks/run.py clearance` runs the clearance part alone (about 1-2
min) and writes clearance.md only.
"""

from __future__ import annotations

import math
import os
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import jointgap
import numpy as np
from jointgap.results import Impact
from recording import machine, write_results

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "output"


MODEL = ROOT / "examples" / "slider_crank_ideal.toml"

# Founding slider-crank (docs/physics.md section 5): crank 0.08 m, rod 0.32 m, 0 -> 300 rpm
# in 0.2 s.
R, L, W, T_RAMP = 0.08, 0.32, 300 * 2 * math.pi / 60, 0.2


def slider_ax(t: np.ndarray) -> np.ndarray:
    """Closed-form slider acceleration [m/s^2] at times t."""
    ramp = t < T_RAMP
    th = np.where(ramp, 0.5 * W * t**2 / T_RAMP, 0.5 * W * T_RAMP + W * (t - T_RAMP))
    w = np.where(ramp, W * t / T_RAMP, W)
    al = np.where(ramp, W / T_RAMP, 0.0)
    s, c = np.sin(th), np.cos(th)
    root = np.sqrt(L**2 - R**2 * s**2)
    dx = -R * s - R**2 * s * c / root
    d2x = -R * c - R**2 * (c**2 - s**2) / root - R**4 * s**2 * c**2 / root**3
    return d2x * w**2 + dx * al


def timed(call, budget: float = 1.0) -> tuple[float, float, object]:
    """Median Python wall time and median engine wall_time [s] over >= 7 calls."""
    result = call()  # warm-up
    py, engine = [], []
    start = time.perf_counter()
    while len(py) < 7 or (len(py) < 51 and time.perf_counter() - start < budget):
        t0 = time.perf_counter()
        result = call()
        py.append(time.perf_counter() - t0)
        engine.append(result.stats["wall_time"])
    return statistics.median(py), statistics.median(engine), result


def python_table() -> str:
    t0 = time.perf_counter()
    model = jointgap.load(MODEL)
    load_ms = (time.perf_counter() - t0) * 1e3
    lines = [
        "## Python: `jointgap.load(...).simulate(1.0, rate=10000, ...)`\n",
        f"`jointgap.load('examples/slider_crank_ideal.toml')`: {load_ms:.1f} ms (first call). "
        "atol = rtol x 1e-2. 'Python' is the median time of the `simulate` call, 'engine' the "
        "median `result.stats['wall_time']` (compile, assembly, integration, recording in "
        "Rust); the difference is the per-call cost of the Python layer (options, model to "
        "JSON, arrays, Result). Error: max |slider.ax - closed form| over the samples.\n",
        "| method | rtol | channels | Python [ms] | engine [ms] | overhead [ms] | overhead | "
        "samples | max err ax [m/s^2] |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for method in ("dopri5", "sdirk4", "auto"):
        for rtol in (1e-6, 1e-9):
            for channels in (None, ["slider.*"]):

                def call(method=method, rtol=rtol, channels=channels):
                    return model.simulate(
                        1.0,
                        rate=10_000,
                        rtol=rtol,
                        atol=rtol * 1e-2,
                        method=method,
                        channels=channels,
                    )

                py, engine, res = timed(call)
                err = np.max(np.abs(np.asarray(res["slider.ax"]) - slider_ax(np.asarray(res.time))))
                lines.append(
                    f"| {res.stats['method']} | {rtol:.0e} | {'slider.*' if channels else 'all'} "
                    f"| {py * 1e3:.2f} | {engine * 1e3:.2f} | {(py - engine) * 1e3:.2f} "
                    f"| {(py - engine) / py:.0%} | {len(res.time)} | {err:.2e} |"
                )
    return "\n".join(lines) + "\n"


# --- The founding clearance case: speed against accuracy per integrator -------------------

CLEARANCE = ROOT / "examples" / "slider_crank_clearance.toml"
CL_T_END = 0.5  # simulated time [s]
CL_RATE = 10_000  # output grid of the accuracy measure [Hz]
CL_METHODS = ("dopri5", "sdirk4", "auto", "radau5")
# The issue asks for 1e-4 to 1e-9; 1e-10 is there to reach its NRMSE 1e-7 figure. The
# half decades between 1e-7 and 1e-9 match the two NRMSE targets more closely than a
# decade apart would (the cheapest run that meets a target is compared).
CL_RTOLS = (1e-4, 1e-5, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 1e-10)
CL_REPEATS = 3  # timings are the best of up to this many passes over all configurations
CL_REPEAT_BUDGET = 2.0  # [s]: a configuration that has used this much CPU is not repeated
CL_MAX_STEPS = 200_000  # step budget: the slowest configuration would stop within ~15 s
# Reference and its check: two tight runs by different methods.
CL_REFERENCE = ("dopri5", 1e-12)
CL_CHECK = ("sdirk4", 1e-11)
# The issue's figures for scale (same machine kind): a hand-written C program of the same
# model (minimal coordinates, Radau IIA), NRMSE target -> ms; SciPy's fastest method.
C_PROGRAM_MS = {2e-5: 3.0, 1e-7: 6.0}
SCIPY_S = 0.3


def cl_atol(rtol: float) -> float:
    """atol = 1e-3 x rtol, bounded below by 1e-15 (the reference's), rounded to the
    decimal a user would type (1e-3 * 1e-4 is 1.0000000000000001e-07, and a change of
    atol in its last bit changes this case's trajectory measurably: see the last table)."""
    return float(f"{max(1e-3 * rtol, 1e-15):.0e}")


@dataclass
class ClRun:
    """One configuration: the first run's figures and the best timings over the passes."""

    method: str
    rtol: float
    atol: float
    max_steps: int = CL_MAX_STEPS
    compiled: bool = True  # the evaluation compiled to native code (the default)
    status: str = "not run"
    message: str = ""
    stats: dict[str, Any] = field(default_factory=dict)
    ax: np.ndarray | None = None
    impacts: dict[str, list[Impact]] = field(default_factory=dict)
    nrmse: float = math.nan
    wall: list[float] = field(default_factory=list)  # result.stats["wall_time"], 10 kHz
    cpu: list[float] = field(default_factory=list)  # process time of simulate, 10 kHz
    cpu_int: list[float] = field(default_factory=list)  # the same with two samples

    @property
    def ok(self) -> bool:
        return self.status == "finished"

    def best(self, what: str) -> float:
        values = getattr(self, what)
        return min(values) if values else math.nan


def nrmse(ax: np.ndarray | None, ref: np.ndarray) -> float:
    """RMS(ax - ref) / (max - min of ref); NaN when ax is missing or shorter."""
    if ax is None or len(ax) != len(ref):
        return math.nan
    return float(np.sqrt(np.mean((ax - ref) ** 2)) / (ref.max() - ref.min()))


def cl_pass(model: jointgap.Model, run: ClRun) -> None:
    """One timed run at 10 kHz output and one with two samples (t = 0 and t_end:
    integration, event location and projection alone). The first pass keeps the
    figures; a failed run keeps its status and message, a raising one becomes 'error'."""

    def call(rate: float) -> tuple[float, jointgap.Result]:
        c0 = time.process_time()
        res = model.simulate(
            CL_T_END,
            rate=rate,
            rtol=run.rtol,
            atol=run.atol,
            method=run.method,
            channels=["slider.ax"],
            max_steps=run.max_steps,
            compiled=run.compiled,
        )
        return time.process_time() - c0, res

    first = not run.cpu
    try:
        cpu, res = call(CL_RATE)
        cpu_int, _ = call(2)
    except Exception as exc:  # a benchmark row, not a crash
        run.status, run.message = "error", f"{type(exc).__name__}: {exc}"
        return
    run.wall.append(res.stats["wall_time"])
    run.cpu.append(cpu)
    run.cpu_int.append(cpu_int)
    if first:
        run.status, run.message, run.stats = res.status, res.message, dict(res.stats)
        run.ax = np.asarray(res["slider.ax"], dtype=float)
        run.impacts = res.impacts
    print(
        f"  clearance {run.method:6} rtol {run.rtol:.0e} atol {run.atol:.0e}: {run.status}, "
        f"CPU {cpu * 1e3:.1f} ms, integrate {cpu_int * 1e3:.1f} ms",
        file=sys.stderr,
        flush=True,
    )


def cl_sweep(model: jointgap.Model, runs: list[ClRun], repeats: int) -> None:
    """Round-robin passes, so that a burst of load on the shared machine does not hit all
    repeats of one configuration; failed or costly configurations run once."""
    for p in range(repeats):
        for run in runs:
            spent = sum(run.cpu) + sum(run.cpu_int)
            if p == 0 or (run.ok and spent < CL_REPEAT_BUDGET):
                cl_pass(model, run)


def n_impacts(run: ClRun) -> int:
    return sum(len(v) for v in run.impacts.values())


def fmt(x: float, spec: str) -> str:
    return "-" if not math.isfinite(x) else format(x, spec)


def work_precision_figure(runs: list[ClRun], interpreted: list[ClRun], path: Path) -> None:
    """Integrate CPU time against NRMSE of slider.ax, one line per method (log-log), the
    evaluation compiled (the default), and auto's line interpreted (dashed), with the
    hand-written C program's two figures quoted by the speed issue for scale."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0, 3.6), layout="constrained")
    ax = fig.subplots()
    lines = [(m, marker, runs, "-", m) for m, marker in zip(CL_METHODS, "os^D", strict=True)]
    lines.append(("auto", "^", interpreted, "--", "auto, interpreted"))
    colours = {m: f"C{k}" for k, m in enumerate(CL_METHODS)}
    for method, marker, group, style, label in lines:
        pts = sorted(
            (r.nrmse, 1e3 * r.best("cpu_int"))
            for r in group
            if r.method == method and r.ok and math.isfinite(r.nrmse)
        )
        if pts:
            ax.loglog(
                *zip(*pts, strict=True),
                marker=marker,
                linestyle=style,
                linewidth=1.0,
                label=label,
                color=colours[method],
                fillstyle="none" if style == "--" else "full",
            )
    ax.loglog(
        *zip(*C_PROGRAM_MS.items(), strict=True), "k*", markersize=9, label="C program (quoted)"
    )
    ax.set_xlabel("NRMSE of slider acceleration")
    ax.set_ylabel("integrate CPU time [ms]")
    ax.invert_xaxis()
    ax.grid(True, which="both", linewidth=0.3)
    ax.legend(fontsize="small")
    ax.set_title("founding clearance case, 0.5 s", fontsize="medium")
    fig.savefig(path, dpi=150)


def step_history_figure(path: Path) -> str:
    """The founding case at default settings, every accepted step recorded: step size
    against time, the contact mode shaded, impact onsets marked; so a reader sees where
    impacts and sticking friction cost steps. Returns a one-line summary."""
    from matplotlib.figure import Figure

    run = jointgap.load(CLEARANCE).simulate(CL_T_END, channels=["rod_slider.mode"])
    t, mode = run.time, run["rod_slider.mode"]
    h = np.diff(t)
    fig = Figure(figsize=(7.0, 3.0), layout="constrained")
    ax = fig.subplots()
    ax.semilogy(t[1:], h, linewidth=0.6, color="C0", label="step size")
    for value, colour, label in ((2, "tab:green", "continuous contact"), (1, "tab:red", "impact")):
        ax.fill_between(
            t[1:],
            1e-9,
            1e-2,
            where=mode[1:] == value,
            color=colour,
            alpha=0.15,
            linewidth=0,
            label=label,
        )
    onsets = [i.onset_time for i in run.impacts["rod_slider"]]
    ax.plot(
        onsets, np.full(len(onsets), 2e-3), "v", color="tab:red", markersize=4, label="impact onset"
    )
    ax.set_ylim(h.min() / 2, 5e-3)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("accepted step [s]")
    ax.legend(fontsize="small", ncols=4, loc="lower center")
    ax.set_title(f"founding case, {run.stats['method']}", fontsize="small")
    fig.savefig(path, dpi=150)
    contact = mode[1:] > 0
    return (
        f"Step history ({path.name}): {len(h)} steps; median step "
        f"{np.median(h[~contact]) * 1e6:.1f} us in free flight, "
        f"{np.median(h[contact]) * 1e6:.1f} us in contact; "
        f"{int(contact.sum())} of the steps ({contact.mean():.0%}) are taken in contact."
    )


def clearance_table() -> str:
    model = jointgap.load(CLEARANCE)
    ref = ClRun(CL_REFERENCE[0], CL_REFERENCE[1], cl_atol(CL_REFERENCE[1]))
    check = ClRun(CL_CHECK[0], CL_CHECK[1], cl_atol(CL_CHECK[1]))
    cl_sweep(model, [ref, check], 1)
    if not (ref.ok and check.ok) or ref.ax is None:
        raise RuntimeError(f"reference runs failed: {ref.message} / {check.message}")
    ref_ax = ref.ax
    floor = nrmse(check.ax, ref_ax)
    runs = [ClRun(m, r, cl_atol(r)) for m in CL_METHODS for r in CL_RTOLS]
    # auto interpreted too, in the same round-robin passes as the compiled runs.
    interpreted = [ClRun("auto", r, cl_atol(r), compiled=False) for r in CL_RTOLS]
    cl_sweep(model, runs + interpreted, CL_REPEATS)
    for run in runs + interpreted:
        run.nrmse = nrmse(run.ax, ref_ax)
    work_precision_figure(runs, interpreted, OUT / "work_precision.png")
    base = next(r for r in runs if r.method == "dopri5" and r.rtol == 1e-6)
    span = float(ref_ax.max() - ref_ax.min())
    spread = [max(r.cpu) / min(r.cpu) - 1 for r in runs if len(r.cpu) > 1]
    median_spread = statistics.median(spread) if spread else math.nan

    lines = [
        "## Founding clearance case: speed against accuracy per integrator\n",
        f"`examples/slider_crank_clearance.toml`, {CL_T_END} s simulated (crank ramp to "
        "300 rpm in 0.2 s, then steady), `simulate(0.5, rate=10000, rtol, atol=1e-3 x rtol, "
        f"method, channels=['slider.ax'], max_steps={CL_MAX_STEPS})`. The issue asks for "
        "rtol 1e-4 to 1e-9; 1e-10 is added to reach its NRMSE 1e-7 figure.\n",
        f"Times are the best of up to {CL_REPEATS} round-robin passes (a configuration that "
        f"has used {CL_REPEAT_BUDGET:.0f} s of CPU is not repeated): 'wall' is "
        "`result.stats['wall_time']` at 10 kHz output (5001 samples, each costing about "
        "one RHS evaluation or more whatever the channels); 'CPU' is the process time of "
        "the `simulate` call at 10 kHz (engine single-threaded; it includes about 1 ms of "
        "Python layer and, unlike wall, not the time other processes took from the shared "
        "cores); 'integrate' the CPU time of the same run with two samples (integration, "
        "event location, projection: the figure to set against a program that does not "
        "record). 'x d5 1e-6': CPU over that of dopri5 at rtol 1e-6. Steps: accepted + "
        "rejected. Events: contact onsets and separations located. Impacts: onsets in "
        "`result.impacts`. NRMSE: RMS of the difference of slider.ax from the reference on "
        f"the 10 kHz grid, over the reference's max - min ({span:.1f} m/s^2).\n",
        f"Reference: {ref.method} at rtol {ref.rtol:.0e}, atol {ref.atol:.0e} "
        f"({ref.stats['accepted_steps']} steps, {ref.best('cpu'):.2f} s). Check: "
        f"{check.method} at rtol {check.rtol:.0e}, atol {check.atol:.0e} "
        f"({check.stats['accepted_steps']} steps, {check.best('cpu'):.2f} s) differs from "
        f"it by NRMSE **{floor:.1e}**: NRMSE values near or below that are not resolved. "
        f"Reference: peak |slider.ax| {np.abs(ref_ax).max():.1f} m/s^2, "
        f"{n_impacts(ref)} impacts. Noise: over the {len(spread)} configurations timed more "
        f"than once, the slowest CPU time exceeded the best by {fmt(median_spread, '.0%')} "
        f"(median) and {fmt(max(spread, default=math.nan), '.0%')} (largest).\n",
        "| method | rtol | status | wall [ms] | CPU [ms] | integrate [ms] | x d5 1e-6 | "
        "steps | RHS | Jacobians | projections | events | impacts | "
        "peak \\|ax\\| [m/s^2] | NRMSE ax |",
        "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for run in runs:
        st = run.stats
        steps = (
            f"{st['accepted_steps']} + {st['rejected_steps']}" if "accepted_steps" in st else "-"
        )
        status = run.status if run.ok else f"**{run.status}**: {run.message}"
        peak = float(np.abs(run.ax).max()) if run.ax is not None and len(run.ax) else math.nan
        lines.append(
            f"| {st.get('method', run.method)} | {run.rtol:.0e} | {status} "
            f"| {fmt(run.best('wall') * 1e3, '.1f')} | {fmt(run.best('cpu') * 1e3, '.1f')} "
            f"| {fmt(run.best('cpu_int') * 1e3, '.1f')} "
            f"| {fmt(run.best('cpu') / base.best('cpu'), '.2f')} | {steps} "
            f"| {st.get('rhs_evaluations', '-')} | {st.get('jacobian_evaluations', '-')} "
            f"| {st.get('projections', '-')} | {st.get('events', '-')} | {n_impacts(run)} "
            f"| {fmt(peak, '.1f')} | {fmt(run.nrmse, '.1e')} |"
        )

    # At equal accuracy: the cheapest run of each method that meets the issue's targets.
    lines += [
        "\n**At equal accuracy.** Per method, the cheapest finished run (by 'integrate') "
        "whose NRMSE meets the target, against the issue's figures for scale on this "
        "machine kind: a hand-written C program of the same model (minimal coordinates, "
        "Radau IIA) takes about 3 ms at NRMSE 2e-5 and 6 ms at 1e-7; SciPy's fastest "
        f"method about {SCIPY_S} s (figures quoted from the issue, not measured here).\n",
        "| target NRMSE | method | rtol | NRMSE | integrate [ms] | CPU at 10 kHz [ms] | "
        "x C program | x SciPy |",
        "|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    matched: list[dict[str, Any]] = []
    for target, c_ms in C_PROGRAM_MS.items():
        for method in CL_METHODS:
            met = [r for r in runs if r.method == method and r.ok and r.nrmse <= target]
            if not met:
                lines.append(f"| {target:.0e} | {method} | not met | | | | | |")
                continue
            r = min(met, key=lambda r: r.best("cpu_int"))
            matched.append(
                {
                    "target_nrmse": target,
                    "method": method,
                    "rtol": r.rtol,
                    "nrmse": r.nrmse,
                    "integrate_s": r.best("cpu_int"),
                    "simulate_10khz_s": r.best("cpu"),
                    "c_program_s": c_ms * 1e-3,
                    "ratio_to_c": r.best("cpu") * 1e3 / c_ms,
                    "target_ratio": 5.0,
                }
            )
            lines.append(
                f"| {target:.0e} | {method} | {r.rtol:.0e} | {r.nrmse:.1e} "
                f"| {r.best('cpu_int') * 1e3:.1f} | {r.best('cpu') * 1e3:.1f} "
                f"| {r.best('cpu_int') * 1e3 / c_ms:.0f} | {r.best('cpu_int') / SCIPY_S:.2f} |"
            )

    write_results(
        "founding",
        {
            "case": "examples/slider_crank_clearance.toml, 0.5 s, slider.ax at 10 kHz",
            "runs": [
                {
                    "method": r.method,
                    "rtol": r.rtol,
                    "status": r.status,
                    "nrmse": r.nrmse,
                    "simulate_10khz_s": r.best("cpu"),
                    "integrate_s": r.best("cpu_int"),
                    "rhs_evaluations": r.stats.get("rhs_evaluations"),
                    "steps": r.stats.get("accepted_steps"),
                }
                for r in runs
            ],
            "matched_accuracy": matched,
        },
    )

    # Where the error is: NRMSE per 50 ms window at rtol 1e-8, and the reference's contacts.
    t = np.arange(len(ref_ax)) / CL_RATE
    edges = np.arange(0.0, CL_T_END - 1e-9, 0.05)
    lines += [
        "\n**Where the error is.** RMS of the slider.ax difference per 50 ms window "
        "(window start [s]), over the reference's max - min, at rtol 1e-8:\n",
        "| method | " + " | ".join(f"{lo:.2f}" for lo in edges) + " |",
        "|---|" + "---:|" * len(edges),
    ]
    for run in runs:
        if run.rtol != 1e-8 or run.ax is None or len(run.ax) != len(ref_ax):
            continue
        d = run.ax - ref_ax
        cells = [
            fmt(float(np.sqrt(np.mean(d[(t >= lo) & (t < lo + 0.05)] ** 2)) / span), ".0e")
            for lo in edges
        ]
        lines.append(f"| {run.method} | {' | '.join(cells)} |")
    contacts = [i for impacts in ref.impacts.values() for i in impacts]
    long = [
        f"{i.onset_time:.3f} s ("
        + ("to the end" if math.isnan(i.duration) else f"{i.duration * 1e3:.0f} ms")
        + ")"
        for i in contacts
        if math.isnan(i.duration) or i.duration > 0.01
    ]
    lines.append(
        "\nContacts longer than 10 ms in the reference (onset, duration): "
        + ", ".join(long)
        + f". Largest penetration {max(i.max_penetration for i in contacts):.2e} m.\n"
    )

    # What atol does: the same rtol with other atol (single runs).
    lines += [
        "**What atol does.** The error test scales component i by atol + rtol |y_i|: "
        "positions are 0.1-0.4 m and speeds up to a few m/s, so for most components rtol "
        "dominates and atol only matters for components near zero (the slider's y and "
        "angle, the crank angle as it passes 0, speeds at rest). It also sets the "
        "projection trigger (constraint drift > 1e-2 atol). The penetration (about 1e-5 "
        "m) is a difference of positions of about 0.4 m, so the rtol term (0.4 rtol m), "
        "not atol, bounds its local error. atol = 1e-1, 1e-3 (the table above) and 1e-5 x "
        "rtol, single runs; the engine's default atol is 1e-9:\n",
        "| method | rtol | atol | steps | RHS | projections | NRMSE ax |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for method in ("dopri5", "sdirk4"):
        for rtol in (1e-4, 1e-6, 1e-8):
            atols = sorted(
                {float(f"{a:.0e}") for a in (rtol * 1e-1, rtol * 1e-3, rtol * 1e-5)}, reverse=True
            )
            for atol in atols:
                if math.isclose(atol, cl_atol(rtol)):
                    r = next(x for x in runs if x.method == method and x.rtol == rtol)
                else:
                    r = ClRun(method, rtol, atol)
                    cl_sweep(model, [r], 1)
                    r.nrmse = nrmse(r.ax, ref_ax)
                st = r.stats
                chosen = " (table above)" if math.isclose(atol, cl_atol(rtol)) else ""
                lines.append(
                    f"| {method} | {rtol:.0e} | {atol:.0e}{chosen} "
                    f"| {st.get('accepted_steps', '-')} + {st.get('rejected_steps', '-')} "
                    f"| {st.get('rhs_evaluations', '-')} | {st.get('projections', '-')} "
                    f"| {fmt(r.nrmse, '.1e')} |"
                )

    # How reproducible one NRMSE figure is: atol changed in its 12th digit.
    lines += [
        "\n**How much one NRMSE figure means.** The same runs with atol x (1 + k 1e-12), "
        "k = 0..3 (k = 0: the main table): a change far below any tolerance moves the "
        "step sequence, and through the impacts the error:\n",
        "| method | rtol | steps (min-max) | NRMSE ax (min-max) |",
        "|---|---:|---:|---:|",
    ]
    for method in ("dopri5", "sdirk4", "radau5"):
        for rtol in (1e-6, 1e-8):
            base_run = next(x for x in runs if x.method == method and x.rtol == rtol)
            group = [base_run]
            for k in (1, 2, 3):
                r = ClRun(method, rtol, cl_atol(rtol) * (1 + k * 1e-12))
                cl_sweep(model, [r], 1)
                r.nrmse = nrmse(r.ax, ref_ax)
                group.append(r)
            steps = [g.stats["accepted_steps"] for g in group if "accepted_steps" in g.stats]
            errs = [g.nrmse for g in group if math.isfinite(g.nrmse)]
            lines.append(
                f"| {method} | {rtol:.0e} | {min(steps, default=0)}-{max(steps, default=0)} "
                f"| {fmt(min(errs, default=math.nan), '.1e')}-"
                f"{fmt(max(errs, default=math.nan), '.1e')} |"
            )
    return "\n".join(lines) + "\n"


BATCH_PASSES = 6  # pairs of batch passes (1 thread, 2 threads)


def batch_table() -> str:
    """Batch throughput (jointgap.simulate_batch): eight clearance variants of the founding
    case on 1 and 2 engine threads, and the per-run Python overhead of a batch."""
    from jointgap.variants import with_parameters

    base = jointgap.load(ROOT / "examples" / "slider_crank_clearance.toml")
    variants = [
        with_parameters(base, {"rod_slider.clearance": f"{c} mm"})
        for c in (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)
    ]
    # Passes alternate 1 and 2 threads; each pair gives a ratio, and the median of the
    # pairs' ratios is the figure. On this shared machine the speed of one core moves by
    # 10-30 % within seconds: the best 1-thread pass against the best 2-thread pass
    # compares one lucky core with two, and read 1.55-1.99 for the same engine.
    pairs = []
    for _ in range(BATCH_PASSES):
        wall = {}
        for threads in (1, 2):
            start = time.perf_counter()
            jointgap.simulate_batch(variants, 0.5, threads=threads, rate=10_000)
            wall[threads] = time.perf_counter() - start
        pairs.append(wall)
    ratios = sorted(p[1] / p[2] for p in pairs)
    ratio = statistics.median(ratios)
    walls = {k: statistics.median(p[k] for p in pairs) for k in (1, 2)}
    tiny = [base] * 500
    start = time.perf_counter()
    runs = jointgap.simulate_batch(tiny, 1e-4, threads=1, rate=10_000)
    total = time.perf_counter() - start
    engine = sum(r.stats["wall_time"] for r in runs if isinstance(r, jointgap.Result))
    write_results(
        "batch",
        {
            "wall_1_thread_s": walls[1],
            "wall_2_threads_s": walls[2],
            "throughput_ratio": ratio,
            "pair_ratios": ratios,
            "target_ratio": 1.8,
            "overhead_per_run_s": (total - engine) / len(tiny),
            "target_overhead_s": 1e-3,
        },
    )
    return "\n".join(
        [
            "## Batch runs (jointgap.simulate_batch)\n",
            "Eight variants of the founding clearance case (clearance 0.2 to 0.9 mm), 0.5 s "
            f"at 10 kHz each; {BATCH_PASSES} passes alternating 1 and 2 threads, medians (the "
            "throughput is the median of the passes' ratios). Overhead: 500 runs of 0.1 ms "
            "simulated, the batch's wall time less the engine's, per run.\n",
            "| threads | wall [s] | throughput vs 1 thread |",
            "|---:|---:|---:|",
            f"| 1 | {walls[1]:.3f} | 1.00 |",
            f"| 2 | {walls[2]:.3f} | {ratio:.2f} |",
            "",
            "Ratio of each pass: " + ", ".join(f"{r:.2f}" for r in ratios) + ".",
            "",
            f"Python overhead per run in a batch: {1e3 * (total - engine) / len(tiny):.3f} ms.",
            "",
        ]
    )


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    parts = [
        "# jointgap benchmarks\n",
        machine(),
        "\nFigures are from one run of `make bench` on this machine: read them as ratios "
        "(method against method, stage against stage), not as absolute speeds. The machine "
        "is shared; in the ideal-case tables the dopri5 and auto rows do the same computation, "
        "so their difference shows the noise (10-30 % was seen between runs of the same "
        "configuration).\n",
    ]
    for name, how in (
        ("bench_ideal.md", "cargo run --release -p jointgap-core --example bench_ideal"),
        ("diffsol.md", "cargo run --release -p jointgap-bench-diffsol"),
    ):
        path = OUT / name
        if path.exists():
            parts.append(path.read_text())
        else:
            parts.append(f"_{name} missing: run `{how}` first._\n")
    parts.append(python_table())
    clearance = clearance_table()
    (OUT / "clearance.md").write_text(clearance)
    parts.append(clearance)
    parts.append(batch_table())
    parts.append(step_history_figure(OUT / "step_history.png"))
    from targets import targets_table

    parts.append(targets_table())
    text = "\n".join(parts)
    (OUT / "results.md").write_text(text)
    print(text)
    print(f"wrote {(OUT / 'results.md').relative_to(ROOT)}")


if __name__ == "__main__":
    os.chdir(ROOT)
    if sys.argv[1:] == ["batch"]:
        print(batch_table())
    elif sys.argv[1:] == ["steps"]:
        OUT.mkdir(parents=True, exist_ok=True)
        print(step_history_figure(OUT / "step_history.png"))
    elif sys.argv[1:] == ["clearance"]:
        OUT.mkdir(parents=True, exist_ok=True)
        table = clearance_table()
        (OUT / "clearance.md").write_text(table)
        print(table)
        print(f"wrote {(OUT / 'clearance.md').relative_to(ROOT)}")
    else:
        main()
