"""A model written as a TOML model file (SI numbers, radians) that :func:`jointgap.load`
reads back to the same model: :meth:`jointgap.Model.save`. It reads the model's plain
dictionary, so the builder imports it and not the other way round."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

__all__ = ["save", "dumps"]


def save(model: Mapping[str, Any], path: str | PathLike[str]) -> None:
    """Writes ``model`` (:meth:`jointgap.Model.to_dict`) as a TOML model file in SI
    numbers."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(dumps(model), encoding="utf-8")


def dumps(model: Mapping[str, Any]) -> str:
    """The TOML text of a model file for ``model`` (:meth:`jointgap.Model.to_dict`: SI
    numbers, radians)."""
    d = model
    out = ["# jointgap model file; plain numbers are SI (kg, m, s, N, rad)", "", "[model]"]
    if d.get("dimension") == 3:  # spatial; gravity may be left to the engine
        out.append("dimension = 3")
    out.append(f"name = {_value(d['name'])}")
    if "gravity" in d:
        out.append(f"gravity = {_value(d['gravity'])}")
    out.append("")
    if d["ground_points"]:
        out += ["[ground]", f"points = {_value(d['ground_points'])}", ""]
    for kind, key in (
        ("body", "bodies"),
        ("joint", "joints"),
        ("driver", "drivers"),
        ("force", "forces"),
        ("marker", "markers"),
    ):
        for element in d[key]:
            out.append(f"[[{kind}]]")
            out += [f"{_key(k)} = {_value(v)}" for k, v in element.items() if v is not None]
            out.append("")
    return "\n".join(out)


def _key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_\-]+", key) else _value(key)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, Mapping):
        if not value:
            return "{}"
        return "{ " + ", ".join(f"{_key(str(k))} = {_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} to TOML")
