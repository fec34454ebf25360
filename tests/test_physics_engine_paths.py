"""The physics tests run on both paths of the evaluation (``tests/conftest.py``): each
path runs as its name says."""

from __future__ import annotations

from pathlib import Path

import jointgap


def test_each_path_runs_as_named(evaluation: str, examples: Path) -> None:
    """A run of the founding case says which path it took."""
    result = jointgap.load(examples / "slider_crank_clearance.toml").simulate(0.01, rate=1000)
    expected = {
        "compiled": "native code",
        "interpreted": "interpreted: turned off by the run's options",
    }[evaluation]
    assert result.stats["compiled"].startswith(expected), result.stats["compiled"]
