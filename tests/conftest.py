"""Shared fixtures of the front-end tests (units, model files, builder, CLI)."""

from __future__ import annotations

import json
import signal
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

#: The modules of the physics tests (by the start of their names), which run on both
#: paths of the evaluation: compiled to native code (the engine's default) and
#: interpreted (docs/compiled.md). The planar fingerprints (``test_bit_for_bit``) hold
#: on both to the bit. The wear predictions over a life (``test_wear_life``) repeat the
#: cycles that ``test_wear_core`` checks, and run on the default path only.
PHYSICS = (
    "test_physics_",
    "test_energy_accounts",
    "test_wear_core",
    "test_wear_spatial",
    "test_joint_kind_examples",
    "test_singular_positions",
    "test_bit_for_bit",
)

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


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """Runs each physics test on both paths of the evaluation (:func:`evaluation`)."""
    if metafunc.module.__name__.rsplit(".", 1)[-1].startswith(PHYSICS):
        metafunc.parametrize("evaluation", ["compiled", "interpreted"], indirect=True)


@pytest.fixture(autouse=True)
def evaluation(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """The path of the evaluation a test's runs take: compiled (the engine's default)
    or, for the physics tests also, interpreted: every run of the engine's ``simulate``
    and ``simulate_batch`` then with ``compiled = false``."""
    path: str = getattr(request, "param", "compiled")
    if path == "interpreted":
        from jointgap import _jointgap

        def interpreted(options_json: str) -> str:
            return json.dumps({**json.loads(options_json), "compiled": False})

        simulate, batch = _jointgap.simulate, _jointgap.simulate_batch

        def simulate_interpreted(model: str, options: str, *args: Any, **kwargs: Any) -> Any:
            return simulate(model, interpreted(options), *args, **kwargs)

        def batch_interpreted(models: list[str], options: str, *args: Any, **kwargs: Any) -> Any:
            return batch(models, interpreted(options), *args, **kwargs)

        monkeypatch.setattr(_jointgap, "simulate", simulate_interpreted)
        monkeypatch.setattr(_jointgap, "simulate_batch", batch_interpreted)
    return path
