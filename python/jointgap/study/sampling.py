"""The parameters of a study and its design: which values each case gets.

A parameter is a list of values or a range (grid parameters: every combination runs),
or a distribution (sampled parameters: ``samples`` draws, by plain Monte Carlo or by
Latin hypercube sampling, seeded). Grid and sampled parameters combine: every grid
point gets the same draws, so the grid points are compared on common random numbers.
Cases are numbered in that order: the first parameter of the file varies slowest, the
draws fastest.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "DISTRIBUTIONS",
    "GRID_KINDS",
    "MODEL",
    "SAMPLINGS",
    "Parameter",
    "design",
]

MODEL = "model"
"""The path of the model-file parameter: its values are file names."""
GRID_KINDS = ("values", "range")
"""Parameter kinds whose every value runs."""
DISTRIBUTIONS = ("uniform", "normal", "truncated_normal")
"""Parameter kinds that are sampled."""
SAMPLINGS = ("grid", "monte_carlo", "latin_hypercube")
"""How a study picks its cases."""


@dataclass(frozen=True)
class Parameter:
    """One parameter of a study.

    Attributes:
        path: what it sets, ``<element>.<quantity>`` (``rod_slider.clearance``,
            ``motor.speed``, ``*.clearance``), ``gravity``, or ``model``.
        kind: ``values`` or ``range`` (grid), or a distribution: ``uniform`` (``low``,
            ``high``), ``normal`` (``mean``, ``std``), ``truncated_normal`` (``mean``,
            ``std`` and ``low``, ``high`` or both).
        values: a grid parameter's values (SI floats, or model file names).
        settings: how it was given, SI: a range's ``from``, ``to`` and ``steps`` or
            ``step``; a distribution's ``low``, ``high``, ``mean``, ``std``.
        unit: the SI unit of its values (``"m"``, ``"rad/s"``, ``""``).
    """

    path: str
    kind: str
    values: tuple[Any, ...] = ()
    settings: Mapping[str, float] = field(default_factory=dict)
    unit: str = ""

    @property
    def sampled(self) -> bool:
        """True for a distribution."""
        return self.kind in DISTRIBUTIONS

    def to_dict(self) -> dict[str, Any]:
        """The entry of ``study.json``: path, kind, unit, settings and (grid) values."""
        out: dict[str, Any] = {"path": self.path, "kind": self.kind, "unit": self.unit}
        out.update(self.settings)
        if not self.sampled:
            out["values"] = list(self.values)
        return out

    def quantile(self, u: np.ndarray) -> np.ndarray:
        """The values at probabilities ``u`` in [0, 1) (the inverse of the distribution
        function): uniform draws ``u`` become draws of this distribution."""
        s = self.settings
        if self.kind == "uniform":
            return s["low"] + u * (s["high"] - s["low"])
        from scipy import stats  # type: ignore[import-untyped]

        if self.kind == "normal":
            return np.asarray(stats.norm.ppf(u, loc=s["mean"], scale=s["std"]), dtype=float)
        low, high = s.get("low", -math.inf), s.get("high", math.inf)
        a, b = (low - s["mean"]) / s["std"], (high - s["mean"]) / s["std"]
        return np.asarray(stats.truncnorm.ppf(u, a, b, loc=s["mean"], scale=s["std"]), dtype=float)


def design(
    parameters: Sequence[Parameter], sampling: str, samples: int | None, seed: int
) -> list[dict[str, Any]]:
    """Every case's parameter values, ``{path: value}`` in the order of ``parameters``.

    The grid points (every combination of the grid parameters, the first varying
    slowest) times the ``samples`` draws of the sampled parameters, drawn with
    ``numpy.random.default_rng(seed)``: independent uniforms (``monte_carlo``) or a
    Latin hypercube (``latin_hypercube``, one draw in each of ``samples`` equal
    strata of every parameter), mapped through each distribution's quantile function.
    """
    grid = [p for p in parameters if not p.sampled]
    drawn = [p for p in parameters if p.sampled]
    draws: list[dict[str, float]] = [{}]
    if drawn and samples is not None:
        rng = np.random.default_rng(seed)
        u = rng.random((samples, len(drawn)))
        if sampling == "latin_hypercube":  # stratum k of n holds [k/n, (k+1)/n)
            strata = np.column_stack([rng.permutation(samples) for _ in drawn])
            u = (strata + u) / samples
        columns = [p.quantile(u[:, k]) for k, p in enumerate(drawn)]
        draws = [
            {p.path: float(col[i]) for p, col in zip(drawn, columns, strict=True)}
            for i in range(samples)
        ]
    cases = []
    for point in itertools.product(*(p.values for p in grid)):
        fixed = dict(zip((p.path for p in grid), point, strict=True))
        for draw in draws:
            values = {**fixed, **draw}
            cases.append({p.path: values[p.path] for p in parameters})
    return cases
