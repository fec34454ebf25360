"""A changed model written back into the user's own model file.

``jointgap calibrate --write`` and ``jointgap identify --write`` change a few contact
parameters of a model read from a file. :func:`write_back` writes that file again as the
user wrote it (comments, order, layout), with only the changed values replaced, each in
the unit the user gave it: ``c_max = "27960 N*s/m"`` becomes ``c_max = "17155.65 N*s/m"``
and a plain number stays a plain (SI) number. A value the file does not give (a
stiffness that came from the materials, say) is added to its table as an SI number.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from os import PathLike
from pathlib import Path
from typing import Any

import tomlkit

from ._model_reader import loads
from .model import Model
from .units import written_like

__all__ = ["write_back"]


def write_back(source: str | PathLike[str], model: Model, path: str | PathLike[str]) -> list[str]:
    """Writes ``model`` to ``path`` as the model file ``source`` with the clearance-joint
    values in which ``model`` differs from it; returns those values as
    ``joint.key = value`` lines.

    Raises ValueError when ``model`` differs from ``source`` in anything but the contact
    data of its clearance joints (write such a model with :meth:`Model.save`).
    """
    text = Path(source).read_text(encoding="utf-8")
    before, after = loads(text, str(source)).to_dict(), model.to_dict()
    changes = list(_changes(before, after, str(source)))
    document = tomlkit.parse(text)
    written = []
    for joint, keys, value in changes:
        table = _joint_table(document, joint, str(source))
        # the contact data sit flat in the joint, or in a nested `clearance` table
        nested = table.get("clearance")
        container: Any = nested if isinstance(nested, Mapping) else table
        for key in keys[:-1]:
            container = container[key]
        old = container.get(keys[-1])
        container[keys[-1]] = written_like(value, old)
        written.append(f"{joint}.{'.'.join(keys)} = {container[keys[-1]]}")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(tomlkit.dumps(document), encoding="utf-8")
    return written


def _changes(
    before: Mapping[str, Any], after: Mapping[str, Any], source: str
) -> Iterator[tuple[str, tuple[str, ...], float]]:
    """``(joint, keys, value)`` of every contact value that differs; anything else that
    differs is an error."""
    joints_before = {j["name"]: j for j in before["joints"]}
    for key in before:
        if key != "joints" and before[key] != after.get(key):
            raise ValueError(f"{source}: cannot write back a model whose {key} changed")
    if [j["name"] for j in after["joints"]] != list(joints_before):
        raise ValueError(f"{source}: cannot write back a model whose joints changed")
    for joint in after["joints"]:
        old = joints_before[joint["name"]]
        rest = {k: v for k, v in joint.items() if k != "clearance"}
        if rest != {k: v for k, v in old.items() if k != "clearance"}:
            raise ValueError(f"{source}: cannot write back joint '{joint['name']}': it changed")
        for keys, value in _leaves(joint.get("clearance") or {}, ()):
            if value != _at(old.get("clearance") or {}, keys):
                if not isinstance(value, (int, float)):
                    raise ValueError(
                        f"{source}: cannot write back {joint['name']}.{'.'.join(keys)}"
                    )
                yield joint["name"], keys, float(value)


def _leaves(
    data: Mapping[str, Any], prefix: tuple[str, ...]
) -> Iterator[tuple[tuple[str, ...], Any]]:
    for key, value in data.items():
        if isinstance(value, Mapping):
            yield from _leaves(value, (*prefix, key))
        else:
            yield (*prefix, key), value


def _at(data: Any, keys: tuple[str, ...]) -> Any:
    for key in keys:
        if not isinstance(data, Mapping):
            return None
        data = data.get(key)
    return data


def _joint_table(document: Any, joint: str, source: str) -> Any:
    for table in document.get("joint", []):
        if table.get("name") == joint:
            return table
    raise ValueError(f"{source}: no [[joint]] named '{joint}'")
