"""The progress line of long commands: simulated time, steps and impacts so far,
rewritten in place on stderr (``\\r``) while the engine runs, and only when stderr is a
terminal (never in a pipe, a file or CI logs)::

    with progress_line(args.t_end) as progress:
        result = model.simulate(args.t_end, progress=progress)

The engine calls ``progress(t, steps, impacts)`` about every 0.2 s of wall time
(:meth:`jointgap.Model.simulate`; ``JOINTGAP_PROGRESS_INTERVAL`` sets another interval,
:data:`jointgap._engine.PROGRESS_INTERVAL_VARIABLE`); the line is erased when the block
ends, so the summary printed after it stands alone. A command of many runs says where
it stands in :attr:`ProgressLine.label` (``"run 3: "``, ``"trials: 12 done, best nrmse
0.0412; "``); runs on several threads may report to one line.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TextIO

__all__ = ["ProgressLine", "progress_line", "writing_line"]


class ProgressLine:
    """``progress(t, steps, impacts)`` that writes one line, updated in place.

    Args:
        t_end: the run's end time [s] (a number or text with a unit, ``"0.5 s"``), for the
            percentage; None or unreadable: no percentage.
        stream: where to write (default stderr).
        label: text before the numbers, e.g. ``"ideal run: "``.
    """

    def __init__(
        self, t_end: float | str | None, stream: TextIO | None = None, label: str = ""
    ) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.t_end = _seconds(t_end)
        self.label = label
        self.width = 0
        self.calls = 0
        self._lock = threading.Lock()

    def __call__(self, t: float, steps: int, impacts: int) -> None:
        self.calls += 1
        done = ""
        if self.t_end:
            done = f" ({min(100.0, 100.0 * t / self.t_end):5.1f} %)"
        end = f" / {self.t_end:g}" if self.t_end else ""
        self.show(
            f"{self.label}t = {t:.6g}{end} s{done}, {steps} steps, "
            f"{impacts} impact{'' if impacts == 1 else 's'}"
        )

    def show(self, text: str) -> None:
        """Writes ``text`` in place of the line."""
        with self._lock:
            pad = max(0, self.width - len(text))
            self.width = len(text)  # first: a Ctrl-C while writing leaves it erasable
            self.stream.write("\r" + text + " " * pad)
            self.stream.flush()

    def clear(self) -> None:
        """Erases the line (if one was written)."""
        with self._lock:
            if self.width:
                self.stream.write("\r" + " " * self.width + "\r")
                self.stream.flush()
                self.width = 0


def _seconds(t_end: float | str | None) -> float | None:
    if t_end is None:
        return None
    from .. import units

    try:
        value = units.to_si(t_end, units.TIME)
    except ValueError:
        return None
    return value if value > 0 else None


@contextmanager
def progress_line(
    t_end: float | str | None, label: str = "", stream: TextIO | None = None
) -> Iterator[ProgressLine | None]:
    """A :class:`ProgressLine` while the block runs, erased after it; None (no
    progress, no cost) when ``stream`` (default stderr) is not a terminal."""
    out = stream if stream is not None else sys.stderr
    isatty = getattr(out, "isatty", None)
    if not (callable(isatty) and isatty()):
        yield None
        return
    line = ProgressLine(t_end, out, label)
    try:
        yield line
    finally:
        line.clear()


@contextmanager
def writing_line(
    label: str, stream: TextIO | None = None
) -> Iterator[Callable[[int, int], None] | None]:
    """``progress(rows_written, rows)`` for :meth:`jointgap.Result.save` that shows
    ``writing LABEL: 45 %`` in place while a long result is written, erased after it;
    None when ``stream`` (default stderr) is not a terminal."""
    out = stream if stream is not None else sys.stderr
    isatty = getattr(out, "isatty", None)
    if not (callable(isatty) and isatty()):
        yield None
        return
    width = 0

    def progress(done: int, rows: int) -> None:
        nonlocal width
        text = f"writing {label}: {100.0 * done / max(rows, 1):5.1f} % of {rows} rows"
        out.write("\r" + text + " " * max(0, width - len(text)))
        out.flush()
        width = len(text)

    try:
        yield progress
    finally:
        if width:
            out.write("\r" + " " * width + "\r")
            out.flush()
