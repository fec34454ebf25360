"""The package's layout holds: no two of its modules import each other, directly or
round a circle (imports inside functions and for type checking count too); every
exception and warning lives in ``jointgap.errors`` and is the same class wherever it is
re-exported; a run's ``Result.status`` and ``Result.stats`` are what their types say."""

from __future__ import annotations

import ast
import typing
from pathlib import Path

import jointgap
import jointgap.errors
import pytest

PACKAGE = Path(jointgap.__file__).resolve().parent
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _module_name(path: Path) -> str:
    parts = ["jointgap", *path.relative_to(PACKAGE).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports() -> dict[str, set[str]]:
    """Module -> the package's modules it imports anywhere in its text. ``from . import
    x`` names module ``x`` when there is one, else the package; a module's import of a
    package that contains it (``from .. import __version__``) is left out: that is the
    package's namespace, loaded before the module."""
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    packages = {_module_name(p) for p in PACKAGE.rglob("__init__.py")}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        package = name if name in packages else name.rsplit(".", 1)[0]
        found: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = package.split(".")
                if node.level:
                    base = base[: len(base) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                for alias in node.names:
                    sub = f"{target}.{alias.name}"
                    found.add(sub if sub in modules else target)
            elif isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
        graph[name] = {
            t for t in found if t in modules and t != name and not name.startswith(t + ".")
        }
    return graph


def _circle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import circle of ``graph``, as the modules round it, or None."""
    state: dict[str, int] = {}  # 1 on the current path, 2 done
    path: list[str] = []

    def visit(module: str) -> list[str] | None:
        state[module] = 1
        path.append(module)
        for target in sorted(graph[module]):
            if state.get(target) == 1:
                return path[path.index(target) :] + [target]
            if target not in state and (found := visit(target)) is not None:
                return found
        path.pop()
        state[module] = 2
        return None

    for module in sorted(graph):
        if module not in state and (found := visit(module)) is not None:
            return found
    return None


def test_the_package_imports_no_circle() -> None:
    graph = _imports()
    assert "jointgap.errors" in graph["jointgap.model"]  # the walk sees the imports
    assert _circle(graph) is None, " -> ".join(_circle(graph) or [])


def test_the_circle_finder_finds_one() -> None:
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _circle(graph) == ["a", "b", "c", "a"]


def test_every_error_is_one_class_wherever_it_is_imported_from() -> None:
    from jointgap import _engine, calibration, comparison, convergence, measured, report, study
    from jointgap import units as units_module

    errors = jointgap.errors
    assert set(errors.__all__) <= set(jointgap.__all__)
    for name in errors.__all__:
        cls = getattr(errors, name)
        assert issubclass(cls, BaseException) and getattr(jointgap, name) is cls
    assert units_module.UnitError is errors.UnitError
    assert calibration.CalibrationError is errors.CalibrationError
    assert measured.MeasuredDataError is errors.MeasuredDataError
    assert study.StudyError is errors.StudyError
    assert report.ReportError is errors.ReportError
    assert convergence.RunStopped is errors.RunStopped
    assert comparison.ComparisonWarning is errors.ComparisonWarning
    assert _engine.OutputTooLarge is errors.OutputTooLarge
    assert jointgap.ModelError.__module__ == "jointgap"  # as tracebacks name it


def test_the_grouped_names_all_resolve() -> None:
    assert len(set(jointgap.__all__)) == len(jointgap.__all__)
    for name in jointgap.__all__:
        assert getattr(jointgap, name) is not None, name


def test_a_runs_status_and_stats_are_what_their_types_say(engine: None) -> None:
    model = jointgap.load(EXAMPLES / "slider_crank_ideal.toml")
    result = model.simulate(0.01, rate=1000, profile=True)
    assert typing.get_args(jointgap.RunStatus) == ("finished", "failed", "interrupted")
    assert result.status in typing.get_args(jointgap.RunStatus)
    # The engine writes every counter of RunStats, and nothing else.
    assert set(result.stats) == set(jointgap.RunStats.__annotations__)
    profile = result.stats["profile"]
    assert profile is not None and set(profile) == set(jointgap.StageTimes.__annotations__)
    assert isinstance(result.stats["accepted_steps"], int)
    assert isinstance(result.stats["wall_time"], float)
    with pytest.raises(KeyError):
        _ = result.stats["nothing"]  # type: ignore[typeddict-item]
