"""The size of a run's output, known before it runs: :class:`OutputSize` and the share of
the machine's memory the samples may take (:data:`OUTPUT_MEMORY_FRACTION`). The engine
module computes it (:func:`jointgap._engine.output_size`) and refuses a run too large
for it with :class:`jointgap.errors.OutputTooLarge`, whose message reads it."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["CSV_BYTES_PER_VALUE", "OUTPUT_MEMORY_FRACTION", "OutputSize"]

OUTPUT_MEMORY_FRACTION = 0.25
"""The largest share of the machine's memory (:func:`jointgap._engine.machine_memory`)
that the samples of the runs held in memory at once may take, 8 bytes per value. A run
holds its samples more than once at its peak (the engine's buffers, the NumPy arrays of
the Result, the CSV writer; benchmarks/README.md gives the measured peak), so a quarter
leaves room for the copies and the rest of the machine."""

CSV_BYTES_PER_VALUE = 20
"""About how many characters one value takes in ``results.csv`` (shortest exact floats
with their comma; measured in benchmarks/README.md): the estimate of the file's size."""


@dataclass(frozen=True)
class OutputSize:
    """The expected size of the output of one run, or of a batch of runs with the same
    options, known before they run.

    Attributes:
        samples: output samples of one run (a lower bound when every accepted step is
            recorded besides the sampled output).
        channels: recorded channels of one run (the largest of a batch), the time column
            not counted.
        runs: runs held in memory together.
    """

    samples: int
    channels: int
    runs: int = 1

    @property
    def memory(self) -> int:
        """Bytes of the samples in memory, the time column included: 8 per value."""
        return 8 * self.runs * self.samples * (self.channels + 1)

    @property
    def csv(self) -> int:
        """About the bytes of ``results.csv`` (:data:`CSV_BYTES_PER_VALUE` per value)."""
        return self.memory // 8 * CSV_BYTES_PER_VALUE

    def describe(self) -> str:
        """E.g. ``50,000,001 samples x 48 channels = 19.6 GB in memory (...)``."""
        runs = f"{self.runs} runs x " if self.runs > 1 else ""
        return (
            f"{runs}{self.samples:,} samples x {self.channels} channels = "
            f"{_bytes(self.memory)} in memory (a results.csv of about {_bytes(self.csv)})"
        )


def _bytes(n: float) -> str:
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000:
            return f"{n:.3g} {unit}"
        n /= 1000
    return f"{n:.3g} TB"
