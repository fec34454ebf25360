"""Physical quantities at the edges: parse ``"300 rpm"``, ``"0.01201 kg*m^2"``, ``"207 GPa"``.

Inside jointgap every number is SI (kg, m, s, N) and angles are radians. Users may
write a quantity as a plain number (taken as SI) or as a string ``"<number> <unit>"``.
The unit expression multiplies and divides unit names and numbers (``*``, ``/``, a
space also multiplies) and raises them to powers (``^``, exponents may be fractional:
``N/m^1.5``, ``m^(3/2)``), so a value may carry its own arithmetic:
``"1/12 kg*m^2"``, ``"2.28*0.05^2/6 kg*m^2"``. SI prefixes (G, M, k, c, m, u or µ,
n) apply to the metric units m, g, s, N, Pa, J, W, Hz and rad.

Dimensions are exponents of mass, length, time and angle. The angle is dimensionless
in SI (1 rad = 1) but tracked here, strictly: a field that expects an angular speed
accepts ``rpm``, ``rad/s`` or ``deg/s`` and rejects ``Hz`` or ``1/s``; a torque
accepts ``N*m`` and rejects ``N*m/rad``. A plain number is always accepted as SI.

``g`` is ambiguous: gram when a mass is expected, standard gravity (9.80665 m/s^2)
when an acceleration is expected.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from itertools import product

from .errors import UnitError

__all__ = [
    "Dimension",
    "UnitError",
    "parse_unit",
    "to_si",
    "to_si_with_dimension",
    "from_si",
    "describe",
    "MASS",
    "LENGTH",
    "TIME",
    "ANGLE",
    "DIMENSIONLESS",
    "SPEED",
    "ANGULAR_SPEED",
    "ACCELERATION",
    "ANGULAR_ACCELERATION",
    "FORCE",
    "TORQUE",
    "INERTIA",
    "STIFFNESS",
    "DAMPING",
    "ROTATIONAL_STIFFNESS",
    "ROTATIONAL_DAMPING",
    "PRESSURE",
    "VISCOSITY",
    "FREQUENCY",
    "ENERGY",
    "HERTZ_STIFFNESS",
]


@dataclass(frozen=True)
class Dimension:
    """Exponents of mass [kg], length [m], time [s] and angle [rad]."""

    mass: Fraction = Fraction(0)
    length: Fraction = Fraction(0)
    time: Fraction = Fraction(0)
    angle: Fraction = Fraction(0)

    def __mul__(self, other: Dimension) -> Dimension:
        return Dimension(
            self.mass + other.mass,
            self.length + other.length,
            self.time + other.time,
            self.angle + other.angle,
        )

    def __truediv__(self, other: Dimension) -> Dimension:
        return self * other**-1

    def __pow__(self, p: int | Fraction) -> Dimension:
        p = Fraction(p)
        return Dimension(self.mass * p, self.length * p, self.time * p, self.angle * p)

    def si_unit(self) -> str:
        """The SI unit of this dimension, e.g. ``kg*m^2`` or ``N/m^1.5`` for known ones."""
        known = _NAMES.get(self)
        if known is not None:
            return known[1]
        return _compose_si(self)

    def noun(self) -> str:
        """A short description, e.g. ``an angular speed [rad/s]``."""
        known = _NAMES.get(self)
        if known is not None:
            return f"{known[0]} [{known[1]}]"
        return f"[{_compose_si(self)}]"


def _compose_si(d: Dimension) -> str:
    parts = []
    for exp, sym in ((d.mass, "kg"), (d.length, "m"), (d.time, "s"), (d.angle, "rad")):
        if exp == 1:
            parts.append(sym)
        elif exp != 0:
            e = str(float(exp)).rstrip("0").rstrip(".") if exp.denominator != 1 else str(exp)
            parts.append(f"{sym}^{e}")
    return "*".join(parts) if parts else "1"


MASS = Dimension(mass=Fraction(1))
LENGTH = Dimension(length=Fraction(1))
TIME = Dimension(time=Fraction(1))
ANGLE = Dimension(angle=Fraction(1))
DIMENSIONLESS = Dimension()
SPEED = LENGTH / TIME
ANGULAR_SPEED = ANGLE / TIME
ACCELERATION = LENGTH / TIME**2
ANGULAR_ACCELERATION = ANGLE / TIME**2
FORCE = MASS * ACCELERATION
TORQUE = FORCE * LENGTH
ENERGY = TORQUE
INERTIA = MASS * LENGTH**2
STIFFNESS = FORCE / LENGTH
DAMPING = FORCE * TIME / LENGTH
ROTATIONAL_STIFFNESS = TORQUE / ANGLE
ROTATIONAL_DAMPING = TORQUE * TIME / ANGLE
PRESSURE = FORCE / LENGTH**2
VISCOSITY = PRESSURE * TIME
FREQUENCY = TIME**-1
HERTZ_STIFFNESS = FORCE / LENGTH ** Fraction(3, 2)

# Names used in messages: dimension -> (article + noun, SI unit).
_NAMES: dict[Dimension, tuple[str, str]] = {
    DIMENSIONLESS: ("a plain number", "1"),
    MASS: ("a mass", "kg"),
    LENGTH: ("a length", "m"),
    TIME: ("a time", "s"),
    ANGLE: ("an angle", "rad"),
    SPEED: ("a speed", "m/s"),
    ANGULAR_SPEED: ("an angular speed", "rad/s"),
    ACCELERATION: ("an acceleration", "m/s^2"),
    ANGULAR_ACCELERATION: ("an angular acceleration", "rad/s^2"),
    FORCE: ("a force", "N"),
    TORQUE: ("a torque", "N*m"),
    INERTIA: ("a moment of inertia", "kg*m^2"),
    STIFFNESS: ("a stiffness", "N/m"),
    DAMPING: ("a damping coefficient", "N*s/m"),
    ROTATIONAL_STIFFNESS: ("a rotational stiffness", "N*m/rad"),
    ROTATIONAL_DAMPING: ("a rotational damping coefficient", "N*m*s/rad"),
    PRESSURE: ("a pressure", "Pa"),
    VISCOSITY: ("a dynamic viscosity", "Pa*s"),
    FREQUENCY: ("a frequency", "Hz"),
    HERTZ_STIFFNESS: ("a contact stiffness", "N/m^1.5"),
}

STANDARD_GRAVITY = 9.80665

# Exact factors stay fractions so that "7.5 mm" gives the float nearest to 0.0075.
Factor = Fraction | float
_F = Fraction

# Unit name -> (factor to SI, dimension). Several entries mean an ambiguous name,
# resolved by the dimension the field expects.
_UNITS: dict[str, list[tuple[Factor, Dimension]]] = {
    # mass
    "g": [(_F("0.001"), MASS), (_F("9.80665"), ACCELERATION)],
    "lb": [(_F("0.45359237"), MASS)],
    # length
    "m": [(_F(1), LENGTH)],
    "in": [(_F("0.0254"), LENGTH)],
    "ft": [(_F("0.3048"), LENGTH)],
    # time
    "s": [(_F(1), TIME)],
    "min": [(_F(60), TIME)],
    "h": [(_F(3600), TIME)],
    # angle
    "rad": [(_F(1), ANGLE)],
    "deg": [(math.pi / 180.0, ANGLE)],
    "°": [(math.pi / 180.0, ANGLE)],
    "rev": [(2.0 * math.pi, ANGLE)],
    "arcmin": [(math.pi / 10800.0, ANGLE)],
    "rpm": [(math.pi / 30.0, ANGULAR_SPEED)],
    # derived
    "Hz": [(_F(1), FREQUENCY)],
    "N": [(_F(1), FORCE)],
    "kgf": [(_F("9.80665"), FORCE)],
    "lbf": [(_F("4.4482216152605"), FORCE)],
    "Pa": [(_F(1), PRESSURE)],
    "bar": [(_F(100000), PRESSURE)],
    "psi": [(_F("6894.757293168361"), PRESSURE)],
    # the poise, for oils' viscosity in cP (1 cP = 1 mPa*s)
    "P": [(_F("0.1"), VISCOSITY)],
    "J": [(_F(1), ENERGY)],
    "W": [(_F(1), ENERGY / TIME)],
}

# Units that take SI prefixes (a prefixed g is always the gram).
_PREFIXABLE = {"m", "g", "s", "N", "Pa", "J", "W", "Hz", "rad", "P"}
_PREFIXES = {
    "G": _F(10) ** 9,
    "M": _F(10) ** 6,
    "k": _F(10) ** 3,
    "c": _F(10) ** -2,
    "m": _F(10) ** -3,
    "u": _F(10) ** -6,
    "µ": _F(10) ** -6,
    "μ": _F(10) ** -6,
    "n": _F(10) ** -9,
}

_NUMBER = re.compile(r"\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)")
_TOKEN = re.compile(
    r"\s*(?:(\*\*|[*/^()·+-])|(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)"
    r"|([A-Za-zµμ°_]+))"
)

_Interpretations = list[tuple[Factor, Dimension]]


def _resolve(name: str) -> _Interpretations | None:
    if name in _UNITS:
        return _UNITS[name]
    for prefix, scale in _PREFIXES.items():
        base = name[len(prefix) :]
        if name.startswith(prefix) and base in _PREFIXABLE:
            # a prefixed g is the gram, never a multiple of standard gravity
            return [(scale * f, d) for f, d in _UNITS[base] if base != "g" or d == MASS]
    return None


def _lookup(name: str) -> _Interpretations:
    found = _resolve(name)
    if found is not None:
        return found
    hint = ""
    if name in ("Nm", "Nms"):
        hint = f" (write {'N*m' if name == 'Nm' else 'N*m*s'})"
    else:
        for guess in dict.fromkeys((name.lower(), name.capitalize(), name[:1] + name[1:].lower())):
            if guess != name and _resolve(guess) is not None:
                hint = f" (did you mean '{guess}'? unit names are case-sensitive)"
                break
    raise UnitError(f"unknown unit '{name}'{hint}")


class _UnitParser:
    """Recursive descent over a unit expression; each term keeps its interpretations.

    expr := term (('*' | '/' | space) term)* ;  term := (name | number | '(' expr ')') ['^' exp]
    exp := ['-' | '+'] (number | '(' number ['/' number] ')')
    Products and quotients associate to the left: ``N*s/m`` is ``(N*s)/m``.
    """

    def __init__(self, text: str) -> None:
        self.text = text.strip()
        self.tokens: list[tuple[str, str]] = []
        pos = 0
        while pos < len(self.text):
            m = _TOKEN.match(self.text, pos)
            if m is None:
                raise self.error(self.text[pos:].strip())
            op, num, name = m.groups()
            if op is not None:
                self.tokens.append(("op", {"**": "^", "·": "*"}.get(op, op)))
            elif name is not None:
                self.tokens.append(("name", name))
            else:
                self.tokens.append(("num", num))
            pos = m.end()
        self.i = 0

    def error(self, at: str) -> UnitError:
        return UnitError(f"cannot read unit '{self.text}' at '{at}'")

    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def take(self) -> tuple[str, str]:
        tok = self.peek()
        if tok is None:
            raise UnitError(f"unit '{self.text}' ends too early")
        self.i += 1
        return tok

    def expect(self, tok: tuple[str, str]) -> None:
        if self.take() != tok:
            raise UnitError(f"unbalanced parentheses in unit '{self.text}'")

    def parse(self) -> _Interpretations:
        result = self.expr()
        tok = self.peek()
        if tok is not None:
            raise self.error(tok[1])
        return result

    def expr(self) -> _Interpretations:
        acc = self.term()
        while True:
            tok = self.peek()
            if tok == ("op", "*"):
                self.take()
                acc = _combine(acc, self.term(), 1)
            elif tok == ("op", "/"):
                self.take()
                acc = _combine(acc, self.term(), -1)
            elif tok is not None and (tok[0] in ("name", "num") or tok == ("op", "(")):
                acc = _combine(acc, self.term(), 1)  # a space multiplies: "N m"
            elif tok in (("op", "+"), ("op", "-")):
                raise UnitError(
                    f"cannot add or subtract in '{self.text}': a quantity is a product of "
                    "numbers and units"
                )
            else:
                return acc

    def term(self) -> _Interpretations:
        kind, value = self.take()
        if kind == "name":
            base = _lookup(value)
        elif (kind, value) == ("op", "("):
            base = self.expr()
            self.expect(("op", ")"))
        elif kind == "num":
            base = [(_F(value), DIMENSIONLESS)]  # as in "1/s" or "1/12 kg*m^2"
        else:
            raise self.error(value)
        if self.peek() == ("op", "^"):
            self.take()
            p = self.exponent()
            base = [(_power(f, p), d**p) for f, d in base]
        return base

    def exponent(self) -> Fraction:
        sign = 1
        if self.peek() in (("op", "-"), ("op", "+")):
            sign = -1 if self.take()[1] == "-" else 1
        kind, value = self.take()
        if (kind, value) == ("op", "("):
            p = self.number()
            if self.peek() == ("op", "/"):
                self.take()
                p = p / self.number()
            self.expect(("op", ")"))
        elif kind == "num":
            p = Fraction(value).limit_denominator(1000)
        else:
            raise UnitError(f"bad exponent in unit '{self.text}' at '{value}'")
        return sign * p

    def number(self) -> Fraction:
        kind, value = self.take()
        if kind != "num":
            raise UnitError(f"bad exponent in unit '{self.text}' at '{value}'")
        return Fraction(value).limit_denominator(1000)


def _power(f: Factor, p: Fraction) -> Factor:
    if isinstance(f, Fraction) and p.denominator == 1:
        return f ** int(p)
    return float(float(f) ** float(p))


def _combine(a: _Interpretations, b: _Interpretations, sign: int) -> _Interpretations:
    return [(fa * fb**sign, da * db**sign) for (fa, da), (fb, db) in product(a, b)]


def parse_unit(expr: str) -> list[tuple[Factor, Dimension]]:
    """Reads a unit expression; returns its (factor to SI, dimension) interpretations.

    There is one interpretation unless the expression contains the ambiguous ``g``.

    >>> parse_unit("N*s/m")[0][1] == DAMPING
    True
    """
    if not expr.strip():
        raise UnitError("empty unit")
    return _UnitParser(expr).parse()


def _split(text: str) -> tuple[Fraction, str]:
    """Splits ``"<number> <unit>"``; the number is kept exact. A number followed by an
    operator (``"1/12 kg*m^2"``, ``"0.05^2 kg"``) leaves only its sign outside: the rest
    is a product of numbers and units for :func:`parse_unit`."""
    m = _NUMBER.match(text)
    if m is None:
        raise UnitError(f"'{text}': malformed number")
    rest = text[m.end() :].strip()
    if rest[:1] in ("/", "*", "^", "·"):
        number = m.group(1)
        sign = Fraction(-1) if number.startswith("-") else Fraction(1)
        return sign, number.lstrip("+-") + rest
    if (rest[:1] in (".", ",") or rest[:1].isdigit()) and not re.match(r"1\s*/", rest):
        raise UnitError(f"'{text}': malformed number")
    return Fraction(m.group(1)), rest


def to_si_with_dimension(
    value: object, expected: Dimension | Sequence[Dimension]
) -> tuple[float, Dimension | None]:
    """Converts ``value`` to SI; returns it with the dimension it was given in.

    ``value`` is a number (SI, the returned dimension is ``None``) or a string
    ``"<number> [unit]"``. ``expected`` is one dimension or several acceptable ones
    (a driver speed may be angular or linear).
    """
    dims = (expected,) if isinstance(expected, Dimension) else tuple(expected)
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, str)):
        raise UnitError(
            f"{value!r}: expected a number or a quantity string like '{_example(dims[0])}'"
        )
    if isinstance(value, numbers.Real):
        x = float(value)
        if not math.isfinite(x):
            raise UnitError(f"{value!r}: must be finite")
        return x, None
    if not value.strip():
        raise UnitError("'': empty value")
    number, unit = _split(value)
    if not unit:
        return float(number), None
    try:
        options = parse_unit(unit)
    except UnitError as exc:
        raise UnitError(f"'{value}': {exc}") from None
    for factor, dim in options:
        if dim in dims:
            try:
                exact = isinstance(factor, Fraction)
                x = float(number * factor) if exact else float(number) * factor
            except OverflowError:
                x = math.inf
            if not math.isfinite(x):
                raise UnitError(f"'{value}': must be finite")
            return x, dim
    wanted = " or ".join(d.noun() for d in dims)
    got = " or ".join(sorted({d.noun() for _, d in options}))
    raise UnitError(f"'{value}': expected {wanted}, got {got}")


def to_si(value: object, expected: Dimension | Sequence[Dimension]) -> float:
    """Converts a number (SI) or a quantity string to SI in the expected dimension.

    >>> to_si("300 rpm", ANGULAR_SPEED)
    31.41592653589793
    >>> to_si("15 mm", LENGTH)
    0.015
    """
    return to_si_with_dimension(value, expected)[0]


def from_si(value: float, unit: str) -> float:
    """Expresses an SI value in ``unit``: ``from_si(0.015, "mm") == 15.0``."""
    options = parse_unit(unit)
    return value / float(options[0][0])


def describe(dim: Dimension) -> str:
    """The text naming a dimension in messages, e.g. ``an angular speed [rad/s]``."""
    return dim.noun()


def _example(dim: Dimension) -> str:
    return f"1 {dim.si_unit()}" if dim != DIMENSIONLESS else "1"


def written_like(value: float, written: object) -> float | str:
    """``value`` (SI) in the form ``written`` had, to write a changed value back into a
    model file: a quantity string keeps its unit (``written_like(0.0175, "15 mm")`` is
    ``"17.5 mm"``), a plain number stays a plain SI number. The number has the fewest
    digits (12 at least) that read back to ``value`` exactly."""
    if not isinstance(written, str):
        return float(value)
    unit = _split(written.strip())[1]
    dimension = parse_unit(unit)[0][1] if unit else DIMENSIONLESS
    number = from_si(value, unit) if unit else value
    for digits in range(12, 18):
        text = f"{number:.{digits}g} {unit}".strip()
        if to_si(text, dimension) == value:
            break
    return text
