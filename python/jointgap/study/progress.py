"""The progress bar of a running study: cases done, failed, rate, time left.

On a terminal one line is redrawn in place; into a file or a pipe (a log, a CI job) a
line is written at every tenth of the cases and at the end.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]

_WIDTH = 24  # characters of the bar


class Progress:
    """Counts the cases of one run of a study and shows how far it is.

    Args:
        total: cases of the study.
        skipped: cases already stored by an earlier run (they count as done).
        stream: where to write (default stderr); None writes nothing.
    """

    def __init__(self, total: int, skipped: int, stream: TextIO | None = sys.stderr) -> None:
        self.total = total
        self.skipped = skipped
        self.ran = 0
        self.failed = 0
        self.stream = stream
        self.start = time.monotonic()
        self.tty = stream is not None and stream.isatty()
        self._shown_tenth = -1
        self.show()

    def add(self, failed: bool) -> None:
        """One more case ended (``failed``: as a failure)."""
        self.ran += 1
        self.failed += failed
        self.show()

    def line(self) -> str:
        """``[#######.........]  12/48 cases, 1 failed, 2.3 cases/s, 0:16 left``."""
        done = self.skipped + self.ran
        filled = round(_WIDTH * done / self.total) if self.total else _WIDTH
        elapsed = time.monotonic() - self.start
        rate = self.ran / elapsed if elapsed > 0 and self.ran else 0.0
        text = f"[{'#' * filled}{'.' * (_WIDTH - filled)}] {done}/{self.total} cases"
        if self.skipped:
            text += f" ({self.skipped} stored before)"
        text += f", {self.failed} failed"
        if rate > 0:
            left = (self.total - done) / rate
            text += f", {rate:.3g} cases/s, {_clock(left)} left"
        return text

    def show(self) -> None:
        if self.stream is None:
            return
        done = self.skipped + self.ran
        if self.tty:
            self.stream.write("\r" + self.line() + "\x1b[K")
        else:
            tenth = 10 * done // self.total if self.total else 10
            if tenth == self._shown_tenth or tenth == 10:  # the end: close() says it
                return
            self._shown_tenth = tenth
            self.stream.write(self.line() + "\n")
        self.stream.flush()

    def close(self) -> None:
        """Ends the bar's line, with the elapsed time."""
        if self.stream is None:
            return
        elapsed = _clock(time.monotonic() - self.start)
        end = f"{self.line()}, {elapsed} elapsed"
        self.stream.write(("\r" + end + "\x1b[K\n") if self.tty else end + "\n")
        self.stream.flush()


def _clock(seconds: float) -> str:
    """``m:ss`` (or ``h:mm:ss``)."""
    s = round(seconds)
    h, rest = divmod(s, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"
