"""Fingerprints of planar runs, to prove a change of the engine's layout moves no result.

Every shipped example and every benchmark mechanism is run with options that exercise
the whole engine (every step recorded beside a fixed rate, step peaks, energy
accounts, each integration method on the founding case). A run's fingerprint holds a
SHA-256 of the bytes of every recorded channel, of the sample times, of the impact list
and of the contact-mode times, with the run counters and a few plain figures to read
when a fingerprint differs. ``tests/records/planar.json`` holds the fingerprints of the
engine before a change; ``tests/test_bit_for_bit.py`` compares against it. The sums of
the sparse factorisation take the widest vector instructions the processor has, so the
fingerprints hold for the instruction set they were recorded on, which the file names.

Record anew (only when a change of results is intended and explained in its commit):

    .venv/bin/python tests/planar_records.py
"""

from __future__ import annotations

import hashlib
import json
import platform
import sys
import tomllib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import jointgap
import numpy as np
from benchmark_models import four_bar_chain, n_link_chain

ROOT = Path(__file__).resolve().parents[1]
RECORDS = Path(__file__).resolve().parent / "records" / "planar.json"

#: Options every example runs with: 0.3 s (several impacts of each clearance example),
#: a fixed rate and every step, the step peaks and the energy accounts.
EXAMPLE_RUN: dict[str, Any] = {
    "t_end": 0.3,
    "rate": 2000.0,
    "every_step": True,
    "step_peaks": True,
    "energy": True,
}


def _example(name: str, **options: Any) -> Callable[[], jointgap.Result]:
    def run() -> jointgap.Result:
        return jointgap.load(ROOT / "examples" / f"{name}.toml").simulate(
            **{**EXAMPLE_RUN, **options}
        )

    return run


def _benchmark(
    model: Callable[[], jointgap.Model], **options: Any
) -> Callable[[], jointgap.Result]:
    def run() -> jointgap.Result:
        return model().simulate(**options)

    return run


def _spatial(path: Path) -> bool:
    """A spatial model file (``dimension = 3``): not a planar record."""
    return tomllib.loads(path.read_text()).get("model", {}).get("dimension", 2) == 3


def cases() -> Iterator[tuple[str, Callable[[], jointgap.Result]]]:
    """Every case by name: the examples (study files aside), the founding case with each
    integration method, and the benchmark mechanisms (the two-loop chain through its
    singular position at tight tolerance, a chain large enough for the sparse solve)."""
    for path in sorted((ROOT / "examples").glob("*.toml")):
        if not path.stem.startswith("study_") and not _spatial(path):
            yield path.stem, _example(path.stem)
    for method in ("dopri5", "sdirk4", "radau5"):
        yield f"founding_{method}", _example("slider_crank_clearance", t_end=0.1, method=method)
    yield (
        "four_bar_chain_2",
        _benchmark(
            lambda: four_bar_chain(2), t_end=1.0, rate=1000.0, rtol=1e-10, atol=1e-12, energy=True
        ),
    )
    yield "four_bar_chain_40", _benchmark(lambda: four_bar_chain(40), t_end=0.1, rate=1000.0)
    yield "n_link_chain_5", _benchmark(lambda: n_link_chain(5), t_end=0.5, every_step=True)
    yield "n_link_chain_60", _benchmark(lambda: n_link_chain(60), t_end=0.02, rate=1000.0)


def _digest(*arrays: Any) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(np.asarray(a, dtype=np.float64)).tobytes())
    return h.hexdigest()[:32]


def _finite_max(values: np.ndarray) -> float | None:
    finite = np.abs(values[np.isfinite(values)])
    return float(finite.max()) if finite.size else None


def fingerprint(result: jointgap.Result) -> dict[str, Any]:
    """What a run must reproduce bit for bit (wall time and machine memory aside, and the
    account of its compiled code, whose compile time is a wall time)."""
    impacts = {
        joint: _digest(
            [
                [i.onset_time, i.onset_speed, i.peak_force, i.max_penetration, i.duration]
                for i in log
            ]
        )
        for joint, log in result.impacts.items()
    }
    return {
        "status": result.status,
        "message": result.message,
        "warnings": list(result.warnings),
        "stats": {
            k: v
            for k, v in result.stats.items()
            if k not in ("wall_time", "compile_time", "compiled")
        },
        "samples": len(result.time),
        "time": _digest(result.time),
        "marks": None if result.samples is None else _digest(result.samples),
        "channels": {name: _digest(result[name]) for name in result.channels},
        "largest": {name: _finite_max(result[name]) for name in result.channels},
        "impacts": impacts,
        "impact_count": {joint: len(log) for joint, log in result.impacts.items()},
        "mode_time": {joint: _digest(t) for joint, t in result.mode_time.items()},
        "peaks": _digest([result.peaks[name] for name in result.channels]),
        "clearances": result.clearances,
    }


def differences(expected: dict[str, Any], got: dict[str, Any]) -> list[str]:
    """Each way `got` differs from `expected`, in words with the figures to compare."""
    out: list[str] = []
    for key in ("status", "message", "warnings", "stats", "samples", "time", "marks", "clearances"):
        if expected[key] != got[key]:
            out.append(f"{key}: {expected[key]!r} -> {got[key]!r}")
    for group in ("channels", "impacts", "mode_time"):
        for name in sorted(set(expected[group]) | set(got[group])):
            if expected[group].get(name) != got[group].get(name):
                if group == "channels":
                    was, now = expected["largest"].get(name), got["largest"].get(name)
                    out.append(f"channel {name}: largest |value| {was!r} -> {now!r}")
                elif group == "impacts":
                    was, now = expected["impact_count"].get(name), got["impact_count"].get(name)
                    out.append(f"impacts of {name}: {was} -> {now} impacts, values differ")
                else:
                    out.append(f"{group} of {name} differ")
    if expected["peaks"] != got["peaks"]:
        out.append("step peaks differ")
    return out


#: Vector instruction sets that change how the linear algebra's sums are grouped. AVX-512
#: is not one: every case gave the same bits on a machine with it as on the one they were
#: recorded on, without it.
VECTOR_FLAGS = ("sse4_2", "avx", "avx2", "fma")


def instruction_set() -> list[str]:
    """The machine's architecture and the vector flags of :data:`VECTOR_FLAGS` it has."""
    flags: set[str] = set()
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.exists():
        for line in cpuinfo.read_text().splitlines():
            if line.startswith("flags"):
                flags = set(line.split(":", 1)[1].split())
                break
    return [platform.machine(), *(f for f in VECTOR_FLAGS if f in flags)]


def record() -> None:
    """Writes the fingerprints of every case to :data:`RECORDS`."""
    records = {name: fingerprint(run()) for name, run in cases()}
    RECORDS.parent.mkdir(parents=True, exist_ok=True)
    body = {"instruction_set": instruction_set(), "cases": records}
    RECORDS.write_text(json.dumps(body, indent=1, sort_keys=True) + "\n")
    print(f"{len(records)} cases recorded in {RECORDS.relative_to(ROOT)}")


if __name__ == "__main__":
    sys.exit(record())
