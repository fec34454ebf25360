"""Study files: a base model, parameters addressed by path, metrics, run options.

::

    [study]
    name = "clearance_speed"
    model = "slider_crank_clearance.toml"     # relative to this file
    t_end = "0.4 s"
    rate = "2 kHz"

    [parameters]
    "rod_slider.clearance" = { from = "0.1 mm", to = "1.0 mm", steps = 4 }
    "motor.speed" = ["100 rpm", "300 rpm", "600 rpm"]

    [metrics]
    peak_contact_force = "peak_contact_force"
    peak_slider_acceleration = { stat = "peak", channel = "slider.ax" }

The format is described in ``docs/studies.md``. Everything is checked before any case
runs (the models, every parameter against every model, every metric's channel and joint,
the run options); an error names the file, the line, the key and its value::

    study.toml:9: [parameters] rod_slider.clearnce = ["0.1 mm"]: unknown quantity ...
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from .. import units as u
from .._engine import run_options
from .._model_reader import load
from ..errors import StudyError
from ..model import Model
from ..variants import parameter_value, with_parameters
from .metrics import Metric, ideal_counterpart, parse_metric
from .sampling import DISTRIBUTIONS, MODEL, SAMPLINGS, Parameter, design

__all__ = ["RUN_KEYS", "Study", "StudyError", "load_study", "loads_study"]

RUN_KEYS = ("t_end", "rate", "rtol", "atol", "method", "max_step", "max_steps", "compiled")
"""Run options a study file may give in ``[study]`` (as ``jointgap run``)."""
_STUDY_KEYS = {"name", "model", "sampling", "samples", "seed", "time_series", *RUN_KEYS}
_SECTIONS = ("study", "parameters", "metrics")
_RESERVED = ("case", "status", "reason", "run_time_s")
_DISTRIBUTION_KEYS = {
    "uniform": ({"low", "high"}, set()),
    "normal": ({"mean", "std"}, set()),
    "truncated_normal": ({"mean", "std"}, {"low", "high"}),
}
"""Per distribution: the keys it needs and the optional ones."""
_SPEC_KEYS = {"from", "to", "steps", "step", "distribution", "low", "high", "mean", "std"}
_UNITS = {
    "clearance": "m",
    "d_max": "m",
    "c_max": "N*s/m",
    "damping": "N*s/m",
    "viscous": "N*s/m",
    "stiffness": "N/m^n",
    "ramp_time": "s",
    "gravity": "m/s^2",
    "speed": "rad/s",
}
"""SI unit of a parameter's values, by quantity (a prismatic driver's speed is m/s)."""


@dataclass(frozen=True)
class Study:
    """A resolved study: what every case runs and what it keeps.

    Attributes:
        name: the study's name (default: the file's stem).
        base_model: the base model file as the study file names it.
        models: model dictionaries (SI) by file name: the base model, or each value of
            the ``model`` parameter.
        parameters: in file order; the first varies slowest.
        metrics: in file order.
        sampling: ``grid``, ``monte_carlo`` or ``latin_hypercube``.
        samples: draws of the sampled parameters (None for a grid).
        seed: seed of the draws.
        run: keyword arguments of :meth:`jointgap.Model.simulate`, SI.
        time_series: keep every channel (True), these channels, or none (False).
    """

    name: str
    base_model: str
    models: Mapping[str, Mapping[str, Any]]
    parameters: tuple[Parameter, ...]
    metrics: tuple[Metric, ...]
    sampling: str
    samples: int | None
    seed: int
    run: Mapping[str, Any]
    time_series: bool | tuple[str, ...]

    def cases(self) -> list[dict[str, Any]]:
        """Every case's parameter values in case order (:func:`sampling.design`)."""
        return design(self.parameters, self.sampling, self.samples, self.seed)

    def model_of(self, values: Mapping[str, Any]) -> Mapping[str, Any]:
        """The model dictionary a case starts from, before its parameters are set."""
        return self.models[values.get(MODEL, Path(self.base_model).name)]

    def to_dict(self) -> dict[str, Any]:
        """The content of ``study.json``: the resolved study (SI), its case count, the
        unit of every column, and a digest of every model, so that a rerun into the
        same folder can tell whether it is the same study."""
        metrics = [m.name for m in self.metrics]
        units = {p.path: p.unit for p in self.parameters} | {m.name: m.unit for m in self.metrics}
        return {
            "name": self.name,
            "base_model": self.base_model,
            "parameters": [p.to_dict() for p in self.parameters],
            "metrics": metrics,
            "sampling": self.sampling,
            "n_cases": len(self.cases()),
            "samples": self.samples,
            "seed": self.seed,
            "metric_definitions": [m.to_dict() for m in self.metrics],
            "units": units | {"run_time_s": "s"},
            "run": dict(self.run),
            "time_series": self.time_series
            if isinstance(self.time_series, bool)
            else list(self.time_series),
            "models": {
                name: hashlib.sha256(json.dumps(m, sort_keys=True).encode()).hexdigest()
                for name, m in self.models.items()
            },
        }


def load_study(path: str | PathLike[str]) -> Study:
    """Reads and checks a study file (model files relative to it). Raises
    :class:`StudyError` (or the model file's :class:`~jointgap.ModelError`)."""
    text = Path(path).read_text(encoding="utf-8")
    return loads_study(text, str(path))


def loads_study(text: str, path: str = "<string>") -> Study:
    """A study from TOML text; ``path`` names it in errors and locates its model files."""
    return _Reader(text, path).study()


class _Reader:
    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.folder = Path(path).parent
        self.lines = text.splitlines()
        try:
            self.data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise StudyError(f"{path}: invalid TOML: {exc}") from None

    # ------------------------------------------------------------ errors

    def error(self, section: str, key: str, value: Any, problem: str) -> StudyError:
        line = self._line(section, key)
        where = f"{self.path}:{line}" if line else self.path
        shown = "" if value is None else f" = {_toml(value)}"
        return StudyError(f"{where}: [{section}] {key}{shown}: {problem}")

    def _line(self, section: str, key: str) -> int | None:
        """The line of ``key`` in ``[section]`` (bare, quoted or dotted), if found."""
        pattern = re.compile(r'^\s*"?' + re.escape(key) + r'"?\s*=')
        inside = False
        for n, line in enumerate(self.lines, 1):
            header = re.match(r"^\s*\[+\s*([^\]]+?)\s*\]", line)
            if header:
                inside = header.group(1) == section
            elif inside and pattern.match(line):
                return n
        return None

    # ------------------------------------------------------------ sections

    def study(self) -> Study:
        for section in self.data:
            if section not in _SECTIONS:
                raise StudyError(
                    f"{self.path}: unknown section [{section}] (allowed: "
                    f"{', '.join(f'[{s}]' for s in _SECTIONS)})"
                )
        for section in ("study", "metrics"):
            if not isinstance(self.data.get(section), dict) or not self.data[section]:
                raise StudyError(f"{self.path}: no [{section}] table")
        head = self.data["study"]
        for key, value in head.items():
            if key not in _STUDY_KEYS:
                known = ", ".join(sorted(_STUDY_KEYS))
                raise self.error("study", key, value, f"unknown key (known: {known})")
        raw_parameters = self.data.get("parameters", {})
        base, models = self.models(head, raw_parameters.get(MODEL))
        run = self.options(head)
        parameters = tuple(
            self.parameter(path, raw, models) for path, raw in _flatten(raw_parameters).items()
        )
        sampling, samples, seed = self.sampling(head, parameters)
        metrics = tuple(self.metric(name, raw, run["t_end"]) for name, raw in self.metrics())
        for m in metrics:
            if m.name in {p.path for p in parameters}:
                raw = self.data["metrics"][m.name]
                raise self.error("metrics", m.name, raw, "a parameter has this name")
        study = Study(
            name=str(head.get("name", Path(self.path).stem)),
            base_model=base,
            models=models,
            parameters=parameters,
            metrics=metrics,
            sampling=sampling,
            samples=samples,
            seed=seed,
            run=run,
            time_series=self.time_series(head),
        )
        self.check_against_models(study)
        return study

    def models(
        self, head: Mapping[str, Any], listed: Any
    ) -> tuple[str, dict[str, Mapping[str, Any]]]:
        """The base model file and the model dictionaries by file name."""
        given = head.get("model")
        if listed is not None:
            if given is not None:
                raise self.error(
                    "study", "model", given, "the models are a parameter: give them there only"
                )
            if not (
                isinstance(listed, list) and listed and all(isinstance(f, str) for f in listed)
            ):
                raise self.error("parameters", MODEL, listed, "write a list of model files")
            files = list(listed)
            section = "parameters"
        elif isinstance(given, str):
            files, section = [given], "study"
        else:
            raise self.error("study", "model", given, 'write model = "<model file>.toml"')
        models: dict[str, Mapping[str, Any]] = {}
        for file in files:
            name = Path(file).name
            if name in models:
                raise self.error(section, MODEL, file, f"two model files named {name}")
            path = self.folder / file
            if not path.is_file():
                raise self.error(section, MODEL, file, f"no such file ({path})")
            models[name] = load(path).to_dict()
        return files[0], models

    def options(self, head: Mapping[str, Any]) -> dict[str, Any]:
        """The run options given, SI; each checked alone, so that an error names its key."""
        if "t_end" not in head:
            raise self.error("study", "t_end", None, 'missing: the simulated time, e.g. "0.5 s"')
        given = {k: head[k] for k in RUN_KEYS if k in head}
        if not isinstance(given.get("compiled", True), bool):
            raise self.error(
                "study", "compiled", given["compiled"], "must be true or false (false: interpreted)"
            )
        for key, value in given.items():
            try:
                run_options(value) if key == "t_end" else run_options(1.0, **{key: value})
            except (ValueError, TypeError) as exc:
                raise self.error("study", key, value, str(exc)) from None
        options = run_options(**given)
        return {k: options[k] for k in given}

    def sampling(
        self, head: Mapping[str, Any], parameters: tuple[Parameter, ...]
    ) -> tuple[str, int | None, int]:
        drawn = [p for p in parameters if p.sampled]
        sampling = head.get("sampling", "monte_carlo" if drawn else "grid")
        if sampling not in SAMPLINGS:
            raise self.error(
                "study", "sampling", sampling, f"must be one of {', '.join(SAMPLINGS)}"
            )
        seed = head.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise self.error("study", "seed", seed, "must be an integer >= 0")
        if sampling == "grid":
            if drawn:
                raise self.error(
                    "parameters",
                    drawn[0].path,
                    None,
                    f"a {drawn[0].kind} distribution needs sampling = "
                    '"monte_carlo" or "latin_hypercube" in [study]',
                )
            if "samples" in head:
                raise self.error("study", "samples", head["samples"], "a grid takes no samples")
            return sampling, None, seed
        if not drawn:
            raise self.error(
                "study", "sampling", sampling, "no parameter is a distribution to sample"
            )
        samples = head.get("samples")
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise self.error("study", "samples", samples, "the number of draws: an integer >= 1")
        return sampling, samples, seed

    def time_series(self, head: Mapping[str, Any]) -> bool | tuple[str, ...]:
        value = head.get("time_series", False)
        if isinstance(value, bool):
            return value
        if isinstance(value, list) and value and all(isinstance(c, str) for c in value):
            return tuple(value)
        raise self.error(
            "study", "time_series", value, "true (every channel), false, or a list of channels"
        )

    def metrics(self) -> list[tuple[str, Any]]:
        out = []
        for name, raw in self.data["metrics"].items():
            if name in _RESERVED:
                raise self.error("metrics", name, raw, f"{name} is a column of every study")
            out.append((name, raw))
        return out

    def metric(self, name: str, raw: Any, t_end: float) -> Metric:
        try:
            metric = parse_metric(name, raw, lambda v: u.to_si(v, u.TIME))
        except (ValueError, TypeError) as exc:
            raise self.error("metrics", name, raw, str(exc)) from None
        if metric.window is not None:
            start, end = metric.window
            if start >= t_end:
                raise self.error(
                    "metrics",
                    name,
                    raw,
                    f"the window starts at {start:g} s, not before the run ends (t_end = "
                    f"{t_end:g} s): it holds no sample",
                )
            if end is not None and end > t_end:
                raise self.error("metrics", name, raw, f"the window ends after t_end = {t_end:g} s")
        return metric

    # ------------------------------------------------------------ parameters

    def parameter(self, path: str, raw: Any, models: Mapping[str, Mapping[str, Any]]) -> Parameter:
        if path == MODEL:
            return Parameter(MODEL, "values", tuple(models))
        unit = self.unit(path, models)
        try:
            if isinstance(raw, Mapping):
                if "distribution" in raw:
                    return self.distribution(path, raw, unit)
                return self.range(path, raw, unit)
            values = raw if isinstance(raw, list) else [raw]
            if not values:
                raise ValueError("no values")
            return Parameter(
                path, "values", tuple(parameter_value(path, v) for v in values), unit=unit
            )
        except ValueError as exc:
            raise self.error("parameters", path, raw, _strip_path(str(exc), path)) from None

    def unit(self, path: str, models: Mapping[str, Mapping[str, Any]]) -> str:
        element, _, quantity = path.rpartition(".")
        if quantity == "speed":
            for model in models.values():
                joints = {j["name"]: j["type"] for j in model["joints"]}
                for d in model["drivers"]:
                    if d["name"] == element and joints.get(d["joint"]) == "prismatic":
                        return "m/s"
        return _UNITS.get(quantity, "")

    def range(self, path: str, raw: Mapping[str, Any], unit: str) -> Parameter:
        unknown = sorted(set(raw) - {"from", "to", "steps", "step"})
        if unknown or "from" not in raw or "to" not in raw:
            raise ValueError(
                "write a list, a range { from = .., to = .., steps = N } (or step = ..), or "
                '{ distribution = "uniform" | "normal" | "truncated_normal", .. }'
            )
        start, stop = parameter_value(path, raw["from"]), parameter_value(path, raw["to"])
        if ("steps" in raw) == ("step" in raw):
            raise ValueError("give steps (the number of values) or step, one of them")
        settings: dict[str, float] = {"from": start, "to": stop}
        if "steps" in raw:
            steps = raw["steps"]
            if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
                raise ValueError("empty range: steps must be an integer >= 1")
            if steps == 1 and start != stop:
                raise ValueError("steps = 1 gives from alone: use steps >= 2, or a list")
            values = np.linspace(start, stop, steps, dtype=float)
            settings["steps"] = steps
        else:
            step = parameter_value(path, raw["step"])
            if not step > 0.0 or stop < start:
                raise ValueError("empty range: it needs from <= to and step > 0")
            count = math.floor((stop - start) / step * (1 + 1e-9)) + 1
            values = np.asarray(start + step * np.arange(count), dtype=float)
            settings["step"] = step
        rounded = tuple(float(f"{v:.12g}") for v in values)  # 0.1 + 2 * 0.1 is 0.3
        return Parameter(path, "range", rounded, settings, unit)

    def distribution(self, path: str, raw: Mapping[str, Any], unit: str) -> Parameter:
        kind = raw["distribution"]
        if kind not in DISTRIBUTIONS:
            raise ValueError(f"distribution {kind!r}: must be one of {', '.join(DISTRIBUTIONS)}")
        needed, optional = _DISTRIBUTION_KEYS[kind]
        keys = set(raw) - {"distribution"}
        if not needed <= keys or not keys <= needed | optional:
            wanted = ", ".join(sorted(needed) + [f"{k} (optional)" for k in sorted(optional)])
            raise ValueError(f"a {kind} distribution takes {wanted}")
        s = {k: parameter_value(path, raw[k]) for k in sorted(keys)}
        if kind == "truncated_normal" and not optional & keys:
            raise ValueError("a truncated normal needs low, high or both")
        if "std" in s and not s["std"] > 0.0:
            raise ValueError(f"bad std {s['std']:g}: must be > 0")
        if "low" in s and "high" in s and not s["low"] < s["high"]:
            raise ValueError(f"bad bounds: low {s['low']:g} must be below high {s['high']:g}")
        return Parameter(path, kind, settings=s, unit=unit)

    # ------------------------------------------------------------ against the models

    def check_against_models(self, study: Study) -> None:
        """Every parameter sets something in every model (tried with its values, or a
        distribution's mean and bounds), every metric finds its channel and joint."""
        for name, data in study.models.items():
            base = Model.from_dict(data)
            for p in study.parameters:
                if p.path == MODEL:
                    continue
                trial = p.values or [
                    p.settings[k] for k in ("mean", "low", "high") if k in p.settings
                ]
                for value in trial:
                    try:
                        with_parameters(base, {p.path: value})
                    except ValueError as exc:
                        problem = f"{_strip_path(str(exc), p.path)} (model {name}, value {value:g})"
                        raw = _flatten(self.data.get("parameters", {}))[p.path]
                        raise self.error("parameters", p.path, raw, problem) from None
            channels = base.simulate(1e-9).channels
            clearance = [j["name"] for j in data["joints"] if j["type"] == "clearance_revolute"]
            ideal: list[str] = []
            if any(m.needs_ideal for m in study.metrics):
                ideal = Model.from_dict(ideal_counterpart(data)).simulate(1e-9).channels
            for m in study.metrics:
                try:
                    m.check(channels, clearance, ideal)
                except ValueError as exc:
                    raw = self.data["metrics"][m.name]
                    raise self.error("metrics", m.name, raw, f"{exc} (model {name})") from None
            if not isinstance(study.time_series, bool):
                for c in study.time_series:
                    if c not in channels:
                        raise self.error(
                            "study",
                            "time_series",
                            list(study.time_series),
                            f"model {name} has no channel '{c}'",
                        )


def _flatten(table: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """``[parameters]`` as ``{path: spec}``: a bare dotted key (``rod_slider.clearance =``)
    reads as nested tables in TOML; a table is a spec when it has a spec's keys."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping) and not set(value) & _SPEC_KEYS:
            out.update(_flatten(value, f"{path}."))
        else:
            out[path] = value
    return out


def _strip_path(message: str, path: str) -> str:
    """A variants message without its leading ``parameter <path>:`` (the error names
    the key already)."""
    return message.removeprefix(f"parameter {path}: ")


def _toml(value: Any) -> str:
    """A value as TOML writes it, for messages."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return str(value)
