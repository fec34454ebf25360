"""Shared fixtures of the front-end tests (units, model files, builder, CLI)."""

from __future__ import annotations

import signal
import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

# A test process started with Ctrl-C ignored (a background job of a non-interactive
# shell) would ignore the SIGINT the interrupt tests send themselves, and their runs would
# go on for hours; the children they start would ignore it too. Take it back.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture
def examples() -> Path:
    """The examples/ folder of the repository."""
    return EXAMPLES


@pytest.fixture
def write_model(tmp_path: Path) -> Callable[[str, str], Path]:
    """Writes TOML text (dedented) to tmp_path/<name> and returns the path."""

    def write(text: str, name: str = "model.toml") -> Path:
        path = tmp_path / name
        path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
        return path

    return write


@pytest.fixture
def engine() -> None:
    """Skips a test when the compiled engine is not built (``make install`` builds it)."""
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
