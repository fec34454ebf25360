"""Model files: read a TOML model into a :class:`~jointgap.Model` (written back by
:mod:`jointgap._model_writer`).

The format is described in ``docs/model-file.md``; ``dimension = 3`` in ``[model]``
makes a spatial model, read with the spatial tables of :mod:`jointgap._schema`. Every
error names the file, the line (of the offending key, else of the element's ``name``),
the element and the problem::

    slider.toml:23: joint 'crank_rod': body_j 'rodd' is not a body of the model
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from ._schema import convert_element
from .errors import ModelError
from .model import Model

__all__ = ["load", "loads", "SECTIONS"]

SECTIONS = {
    "model": False,
    "ground": False,
    "body": True,
    "joint": True,
    "driver": True,
    "force": True,
    "marker": True,
}
"""Top-level sections of a model file; True for arrays of tables (``[[body]]``)."""

_HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\-\"' ]+?)\s*\]\]?\s*(#.*)?$")
_TOML_LINE = re.compile(r"\(at line (\d+), column \d+\)")


class SourceMap:
    """Finds the line of an element's key in the raw text of a model file."""

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.lines = [_strip_comment(line) for line in text.splitlines()]
        # (section, is_array, first line index) for every table header
        self.headers: list[tuple[str, bool, int]] = []
        for n, line in enumerate(self.lines):
            m = _HEADER.match(line)
            if m:
                self.headers.append((m.group(2).replace(" ", ""), m.group(1) == "[[", n))

    def span(self, kind: str, index: int | None) -> tuple[int, int] | None:
        """Lines [start, end) of the ``index``-th ``[[kind]]`` table (or of ``[kind]``)."""
        count = -1
        for h, (name, is_array, start) in enumerate(self.headers):
            if name != kind or (is_array and index is None):
                continue
            count += 1
            if is_array and count != index:
                continue
            end = len(self.lines)
            for other, _, line in self.headers[h + 1 :]:
                if not other.startswith(kind + "."):
                    end = line
                    break
            return start, end
        return None

    def line_of(
        self, kind: str | None, index: int | None, name: str | None, key: str | None
    ) -> int | None:
        """1-based line of ``key`` in the element, else of its name, else its header."""
        if kind is None and key:  # a top-level section
            found = self._find(
                rf"^\s*(\[\[?\s*{re.escape(key)}\s*\]|{re.escape(key)}\s*=)", 0, None
            )
            return None if found is None else found + 1
        span = self.span(kind, index) if kind else None
        if span is None and name:
            found = self._find(rf"(?<![\w\-])name\s*=\s*[\"']{re.escape(name)}[\"']", 0, None)
            return None if found is None else found + 1
        if span is None:
            return None
        start, end = span
        parts = key.split(".") if key else []
        if len(parts) > 1:  # an inline table: the line with both keys
            outer, inner = (re.escape(p) for p in (parts[0], parts[-1]))
            found = self._find(rf"(?<![\w\-]){outer}\s*=.*(?<![\w\-]){inner}\s*=", start, end)
            if found is not None:
                return found + 1
        for part in reversed(parts):
            found = self._find(rf"(?<![\w\-])[\"']?{re.escape(part)}[\"']?\s*=", start, end)
            if found is not None:
                return found + 1
        found = self._find(r"(?<![\w\-])name\s*=", start, end)
        return (found if found is not None else start) + 1

    def single_array_header(self) -> tuple[str, int] | None:
        """The first ``[body]``-style header of an array section (``[[body]]``) and its
        1-based line, if any."""
        for name, is_array, line in self.headers:
            if not is_array and SECTIONS.get(name, False):
                return name, line + 1
        return None

    def _find(self, pattern: str, start: int, end: int | None) -> int | None:
        regex = re.compile(pattern)
        for n in range(start, len(self.lines) if end is None else end):
            if regex.search(self.lines[n]):
                return n
        return None

    def locate(self, error: ModelError) -> ModelError:
        """The error with this file and the line of its element and key."""
        if error.file is not None:
            return error
        line = self.line_of(error.kind, error.index, error.name, error.key)
        problem = error.problem
        if error.related is not None:
            other = self.line_of(error.related[0], error.related[1], None, "name")
            if other is not None:
                problem += f" on line {other}"
        return error.located(self.path, line, problem)


def _strip_comment(line: str) -> str:
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:i]
    return line


def load(path: str | PathLike[str]) -> Model:
    """Reads a TOML model file (or a URDF robot, ``*.urdf``: :mod:`jointgap.urdf`) and
    checks it with the engine.

    Raises :class:`~jointgap.ModelError` naming the file, the line, the element and the
    problem; OSError when the file cannot be read.
    """
    if Path(path).suffix.lower() == ".urdf":
        from .urdf import load_urdf

        return _checked(_build(load_urdf(path)))
    data = Path(path).read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise ModelError(
            f"not a UTF-8 text file (byte 0x{data[exc.start]:02x} at offset {exc.start}): "
            "save the model file as UTF-8",
            file=str(path),
            line=line,
        ) from None
    return loads(text, str(path))


def loads(text: str, path: str = "<string>") -> Model:
    """Reads a model from TOML text; ``path`` names it in error messages."""
    source = SourceMap(path, text)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = _TOML_LINE.search(str(exc))
        line = int(m.group(1)) if m else None
        single = source.single_array_header()  # [body] twice is the reader's error
        if single is not None:
            raise _array_hint(single[0]).located(path, single[1]) from None
        raise ModelError(f"invalid TOML: {exc}", file=path, line=line) from None
    if "urdf" in data:  # an overlay naming its robot: a model of its own
        from .urdf import load_robot

        return _checked(_build(load_robot(path)))
    try:
        model = _build(data)
    except ModelError as exc:
        raise source.locate(exc) from None
    model._source = source
    return _checked(model)


def _checked(model: Model) -> Model:
    """The model, checked by the engine."""
    model.check()
    return model


def _array_hint(section: str) -> ModelError:
    return ModelError(
        f"write [[{section}]] (one table per {section}), not [{section}]", key=section
    )


def _dimension(value: Any) -> int:
    """``[model]``'s ``dimension``: 3 for a spatial model, 2 (or left out) for a planar one."""
    if isinstance(value, bool) or value not in (2, 3):
        raise ModelError(
            f"dimension = {value!r}: write 3 for a spatial model (2, or nothing, for a planar one)",
            kind="model",
            key="dimension",
        )
    return int(value)


def _build(data: Mapping[str, Any]) -> Model:
    for section, value in data.items():
        if section not in SECTIONS:
            raise ModelError(
                f"unknown section '{section}' (allowed: {', '.join(SECTIONS)})", key=section
            )
        is_array = SECTIONS[section]
        if is_array and not (isinstance(value, list) and all(isinstance(v, dict) for v in value)):
            raise _array_hint(section)
        if not is_array and not isinstance(value, dict):
            raise ModelError(f"write [{section}] as a table", key=section)
    head = dict(data.get("model", {}))
    dimension = _dimension(head.pop("dimension", 2))
    convert_element("model", head, dimension=dimension)  # unknown keys, units
    model = Model(head.get("name", ""), head.get("gravity"), dimension)
    ground = data.get("ground", {})
    points = convert_element("ground", ground, dimension=dimension)[0]["points"]
    for name in points:
        model.add_ground_point(name, ground["points"][name])
    for kind in ("body", "joint", "driver", "force", "marker"):
        for element in data.get(kind, []):
            model._add(kind, element)
    return model
