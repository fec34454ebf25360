"""`make bench`, Python part: per-call cost of `Model.simulate` against the engine's own
wall time, then benchmarks/output/results.md with every table (the Rust ones come from
benchmarks/output/bench_ideal.md and diffsol.md, written by the Rust benchmarks).

Run from the repository root after `make install`: `.venv/bin/python benchmarks/run.py`.
"""

from __future__ import annotations

import math
import os
import platform
import statistics
import subprocess
import time
from pathlib import Path

import jointgap
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "output"
MODEL = ROOT / "examples" / "slider_crank_ideal.toml"

# Founding slider-crank: crank 0.08 m, rod 0.32 m, 0 -> 300 rpm in 0.2 s (PHYSICS.md 6).
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


def machine() -> str:
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


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    parts = [
        "# jointgap benchmarks\n",
        machine(),
        "\nFigures are from one run of `make bench` on this machine: read them as ratios "
        "(method against method, stage against stage), not as absolute speeds. The machine "
        "is shared; the dopri5 and auto rows do the same computation, so their difference "
        "shows the noise (10-30 % was seen between runs of the same configuration).\n",
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
    text = "\n".join(parts)
    (OUT / "results.md").write_text(text)
    print(text)
    print(f"wrote {(OUT / 'results.md').relative_to(ROOT)}")


if __name__ == "__main__":
    os.chdir(ROOT)
    main()
