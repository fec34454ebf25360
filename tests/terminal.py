"""The ``jointgap`` command in a terminal, as a user runs it: stderr on a pseudo-terminal
(so progress lines show), stdout a pipe, and Ctrl-C sent at a moment the test chooses
by what the command has written, never by a delay (tests/test_*_interrupt*.py,
tests/test_report.py).

Every run here reports progress at every check of the engine (every 16 steps,
``JOINTGAP_PROGRESS_INTERVAL=0``), so a line comes after a fixed amount of work however
fast or loaded the machine is.
"""

from __future__ import annotations

import os
import pty
import re
import signal
import subprocess
import sys
from dataclasses import dataclass

PROGRESS = re.compile(r"t = ([0-9.e+-]+) / [0-9.e+-]+ s")
"""A progress line of a run (:class:`jointgap.cli.progress.ProgressLine`); group 1 is
the simulated time."""


@dataclass(frozen=True)
class Session:
    """What a command did: exit status, what the terminal showed (stderr), stdout."""

    returncode: int
    screen: str
    stdout: str


def in_terminal(*args: str, interrupt_after: re.Pattern[str] | None = None) -> Session:
    """Runs ``jointgap ARGS`` with stderr on a terminal. With ``interrupt_after``, Ctrl-C
    (SIGINT) is sent once the terminal shows that pattern (e.g. :data:`PROGRESS`)."""
    env = {**os.environ, "JOINTGAP_PROGRESS_INTERVAL": "0"}
    master, slave = pty.openpty()
    command = [sys.executable, "-m", "jointgap", *args]
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=slave, env=env) as proc:
        os.close(slave)
        # The terminal is read as fast as the command writes (a command whose runs report
        # progress at every check writes a lot): appends in place, and the pattern looked
        # for in what came since the last look (with a line's overlap), not in the whole
        # screen again, so that a slow reader never blocks the command's writes.
        screen = bytearray()
        looked = 0
        interrupted = interrupt_after is None
        while True:
            try:
                chunk = os.read(master, 4096)
            except OSError:  # EIO: the command has ended and the terminal is drained
                break
            if not chunk:
                break
            screen += chunk
            if not interrupted:
                recent = bytes(screen[max(0, looked - 512) :]).decode(errors="replace")
                looked = len(screen)
                if interrupt_after.search(recent):
                    proc.send_signal(signal.SIGINT)
                    interrupted = True
        os.close(master)
        stdout = proc.stdout.read() if proc.stdout is not None else b""
        returncode = proc.wait()
    assert interrupted, f"never showed {interrupt_after}: {screen.decode(errors='replace')}"
    return Session(returncode, screen.decode(errors="replace"), stdout.decode())


def last_line(screen: str) -> str:
    """The last line the terminal shows (after the last ``\\r`` or newline)."""
    return re.split(r"[\r\n]", screen.rstrip("\r\n"))[-1]
