"""The ``jointgap`` command: :func:`main` is its entry point (``jointgap ...`` and
``python -m jointgap``), :func:`build_parser` its argument parser.

Its modules: :mod:`.shared` (exit statuses, run options, error lines: what every command
uses), :mod:`.commands` (the parser, ``check``, ``run``, ``plot``, ``calibrate``,
``converge``), :mod:`.measured` (``synthesize``, ``compare``, ``identify``),
:mod:`.study` (``study``, ``study-plot``), :mod:`.report` (``report``) and
:mod:`.progress` (the progress line of a run).
"""

from .commands import build_parser, main
from .shared import (
    EXIT_INTERRUPTED,
    EXIT_INVALID,
    EXIT_NOT_CONVERGED,
    EXIT_RUN_FAILED,
    EXIT_USAGE,
)

__all__ = [
    "EXIT_INTERRUPTED",
    "EXIT_INVALID",
    "EXIT_NOT_CONVERGED",
    "EXIT_RUN_FAILED",
    "EXIT_USAGE",
    "build_parser",
    "main",
]
