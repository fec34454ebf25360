"""Writing and reading a long run's samples: CSV (``Result.save``) against Parquet (the
streamed format), on the two-clearance slider-crank over 60 s at 10 kHz, every channel.

Writes ``benchmarks/output/output_formats.md``: per format, the file size, the time to
write it, the time to read it back whole (``Result.load`` then every channel) and to read
one channel. The Parquet file is written as a streamed run writes it (``ParquetSink``:
zstd, no dictionary), in blocks of ``CSV_BLOCK`` rows like the CSV writer. CPU time of
this process (``time.process_time``) beside the wall time: on a shared machine the wall
time measures the neighbours too.

    .venv/bin/python benchmarks/output_formats.py [T_END]
"""

from __future__ import annotations

import shutil
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import jointgap
import numpy as np
from jointgap._stream import ParquetSink, StoredChannels
from jointgap.results import CSV_BLOCK, RESULTS_CSV, RESULTS_PARQUET, Result

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "examples" / "slider_crank_two_clearances.toml"


def timed(work: Callable[[], object]) -> tuple[float, float]:
    """(wall, cpu) seconds of ``work()``."""
    wall, cpu = time.perf_counter(), time.process_time()
    work()
    return time.perf_counter() - wall, time.process_time() - cpu


def write_parquet(result: Result, folder: Path) -> None:
    """``result`` as a streamed run leaves it: results.parquet, then summary.json and
    impacts.csv by ``Result.save`` (which keeps a result's own Parquet file)."""
    sink = ParquetSink(folder / RESULTS_PARQUET)
    for start in range(0, len(result.time), CSV_BLOCK):
        block = slice(start, start + CSV_BLOCK)
        sink(result.channels, result.time[block], result.data[:, block])
    sink.close()
    stored = StoredChannels(folder / RESULTS_PARQUET, result.channels, len(result.time))
    replace(result, data=stored).save(folder)


def main() -> None:
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    model = jointgap.load(MODEL)
    start = time.perf_counter()
    result = model.simulate(t_end, rate=10_000)
    run_wall = time.perf_counter() - start
    rows, columns = len(result.time), len(result.channels) + 1
    lines = [
        f"# Output formats: {MODEL.name}, {t_end:g} s at 10 kHz, {rows:,} rows x {columns} "
        f"columns ({8 * rows * columns / 1e6:.0f} MB of doubles); the run took {run_wall:.1f} s",
        "",
        "| format | size [MB] | write wall / cpu [s] | read all wall / cpu [s] | "
        "read one channel wall / cpu [s] |",
        "|---|---:|---:|---:|---:|",
    ]
    scratch = Path(tempfile.mkdtemp(prefix="formats-"))
    try:
        for name, write, file in (
            ("CSV", lambda f: result.save(f), RESULTS_CSV),
            ("Parquet (zstd)", lambda f: write_parquet(result, f), RESULTS_PARQUET),
        ):
            folder = scratch / file
            w = timed(lambda: write(folder))  # noqa: B023
            size = (folder / file).stat().st_size / 1e6
            r = timed(lambda: np.asarray(Result.load(folder).data))  # noqa: B023
            one = timed(lambda: Result.load(folder)["slider.ax"])  # noqa: B023
            back = Result.load(folder)
            assert np.array_equal(back.time, result.time)
            assert np.array_equal(np.asarray(back.data), result.data)  # exact both ways
            lines.append(
                f"| {name} | {size:.0f} | {w[0]:.1f} / {w[1]:.1f} | {r[0]:.1f} / {r[1]:.1f} "
                f"| {one[0]:.2f} / {one[1]:.2f} |"
            )
    finally:
        shutil.rmtree(scratch)
    out = ROOT / "benchmarks" / "output" / "output_formats.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
