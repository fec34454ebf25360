"""Contact laws of clearance joints: normal force laws, friction laws and materials.

Each helper returns a :class:`Law` for :meth:`jointgap.Model.add_clearance_revolute`;
values are SI numbers or strings with units (``"27960 N*s/m"``, ``"0.01 mm"``). Units
are checked when the law is made; the engine checks the values (a restitution in
(0, 1], a positive d_max, ...) and names the joint. A value left out (``None``) takes the
engine's default (:data:`jointgap._schema.ENGINE_DEFAULTS`). Formulas and sources:
``docs/clearance-joints.md``.

>>> from jointgap import laws
>>> laws.adams_impact("27960 N*s/m", "0.01 mm").to_dict()["type"]
'adams_impact'
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ._schema import convert_element

__all__ = [
    "Law",
    "hertz",
    "kelvin_voigt",
    "hunt_crossley",
    "lankarani_nikravesh",
    "gonthier",
    "flores",
    "adams_impact",
    "no_friction",
    "coulomb",
    "modified_coulomb",
    "viscous_coulomb",
    "material",
]

Quantity = float | str


@dataclass(frozen=True)
class Law:
    """A normal (``kind == "normal_law"``) or friction (``"friction"``) law: its ``type``
    and the user's values (numbers or units)."""

    kind: str
    type: str
    params: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        params = {k: v for k, v in self.params.items() if v is not None}
        object.__setattr__(self, "params", MappingProxyType(params))
        self.to_si()  # units and keys

    def to_dict(self) -> dict[str, Any]:
        """The law as a table, as written in a model file (values not converted)."""
        return {"type": self.type, **self.params}

    def to_si(self) -> dict[str, Any]:
        """The law in SI units, defaults filled in, as the engine reads it."""
        label = f"{self.type} {'normal law' if self.kind == 'normal_law' else 'friction'}"
        return convert_element(self.kind, self.to_dict(), label=label)[0]


def _normal(type_: str, **params: Any) -> Law:
    return Law("normal_law", type_, params)


def hertz(exponent: float | None = None) -> Law:
    """Elastic Hertz law ``K delta^n``."""
    return _normal("hertz", exponent=exponent)


def kelvin_voigt(damping: Quantity, exponent: float | None = None, clip: bool | None = None) -> Law:
    """``K delta^n + c delta_dot``; ``damping`` c [N s/m]; ``exponent=1`` for the linear
    spring-dashpot."""
    return _normal("kelvin_voigt", exponent=exponent, damping=damping, clip=clip)


def hunt_crossley(
    restitution: float, exponent: float | None = None, clip: bool | None = None
) -> Law:
    """Hunt and Crossley (1975), hysteresis damping from the restitution r in (0, 1]."""
    return _normal("hunt_crossley", exponent=exponent, restitution=restitution, clip=clip)


def lankarani_nikravesh(
    restitution: float, exponent: float | None = None, clip: bool | None = None
) -> Law:
    """Lankarani and Nikravesh (1990), for restitution close to 1."""
    return _normal("lankarani_nikravesh", exponent=exponent, restitution=restitution, clip=clip)


def gonthier(restitution: float, exponent: float | None = None, clip: bool | None = None) -> Law:
    """Gonthier et al. (2004), valid over the whole range of restitution."""
    return _normal("gonthier", exponent=exponent, restitution=restitution, clip=clip)


def flores(restitution: float, exponent: float | None = None, clip: bool | None = None) -> Law:
    """Flores et al. (2011), for soft contacts (low restitution)."""
    return _normal("flores", exponent=exponent, restitution=restitution, clip=clip)


def adams_impact(
    c_max: Quantity,
    d_max: Quantity | None = None,
    exponent: float | None = None,
    clip: bool | None = None,
) -> Law:
    """MSC ADAMS IMPACT: ``K delta^n + STEP(delta, 0, 0, d_max, c_max) delta_dot``;
    ``c_max`` [N s/m], ``d_max`` [m] (by default the bearing material's, from the
    library)."""
    return _normal("adams_impact", exponent=exponent, c_max=c_max, d_max=d_max, clip=clip)


def no_friction() -> Law:
    """Frictionless contact (the default)."""
    return Law("friction", "none")


def coulomb(mu_s: float, mu_d: float, v_s: Quantity, v_d: Quantity) -> Law:
    """ADAMS Coulomb friction: static ``mu_s`` below the stiction speed ``v_s``, dynamic
    ``mu_d`` above ``v_d`` [m/s], STEP blends between."""
    return Law("friction", "coulomb", {"mu_s": mu_s, "mu_d": mu_d, "v_s": v_s, "v_d": v_d})


def modified_coulomb(mu: float, v_0: Quantity, v_1: Quantity) -> Law:
    """Ambrosio (2003): no friction below slip ``v_0``, full ``mu`` from ``v_1`` [m/s],
    linear between."""
    return Law("friction", "modified_coulomb", {"mu": mu, "v_0": v_0, "v_1": v_1})


def viscous_coulomb(mu: float, v_s: Quantity, viscous: Quantity) -> Law:
    """``mu F_N tanh(v_t / v_s) + viscous v_t``; ``v_s`` [m/s], ``viscous`` [N s/m]."""
    return Law("friction", "viscous_coulomb", {"mu": mu, "v_s": v_s, "viscous": viscous})


def material(youngs_modulus: Quantity, poisson_ratio: float) -> dict[str, Any]:
    """Explicit elastic properties of a contact material (e.g. ``material("207 GPa",
    0.3)``); library materials are given by name (``"steel"``, ``"brass"``, ...)."""
    return {"youngs_modulus": youngs_modulus, "poisson_ratio": poisson_ratio}
