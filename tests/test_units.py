"""Quantities with units: each unit, prefixes, exponents, dimensions and errors."""

from __future__ import annotations

import math
from fractions import Fraction

import pytest
from jointgap import units as u
from jointgap.units import UnitError, to_si


@pytest.mark.parametrize(
    ("text", "dim", "expected"),
    [
        ("300 rpm", u.ANGULAR_SPEED, 10 * math.pi),
        ("0.08 m", u.LENGTH, 0.08),
        ("2.37 kg", u.MASS, 2.37),
        ("0.01201 kg*m^2", u.INERTIA, 0.01201),
        ("207 GPa", u.PRESSURE, 207e9),
        ("15 mm", u.LENGTH, 0.015),
        ("7.5 mm", u.LENGTH, 0.0075),
        ("0.2 s", u.TIME, 0.2),
        ("90 deg", u.ANGLE, math.pi / 2),
        ("9.81 m/s^2", u.ACCELERATION, 9.81),
        ("27960 N*s/m", u.DAMPING, 27960.0),
        ("3.136e10 N/m^1.5", u.HERTZ_STIFFNESS, 3.136e10),
        ("1e4 N/m", u.STIFFNESS, 1e4),
        ("5 N*m", u.TORQUE, 5.0),
        ("10 rad/s", u.ANGULAR_SPEED, 10.0),
        ("1 rev", u.ANGLE, 2 * math.pi),
        ("2 Hz", u.FREQUENCY, 2.0),
        ("10 kHz", u.FREQUENCY, 1e4),
        ("1 lbf", u.FORCE, 4.4482216152605),
        ("2 in", u.LENGTH, 0.0508),
        ("3 kN", u.FORCE, 3000.0),
        ("97 MPa", u.PRESSURE, 97e6),
        ("4 ms", u.TIME, 0.004),
        ("1.5 cm", u.LENGTH, 0.015),
        ("2 km", u.LENGTH, 2000.0),
        ("500 g", u.MASS, 0.5),
        ("250 mg", u.MASS, 2.5e-4),
        ("3 µm", u.LENGTH, 3e-6),
        ("3 um", u.LENGTH, 3e-6),
        ("60 rev/min", u.ANGULAR_SPEED, 2 * math.pi),
        ("180 deg/s", u.ANGULAR_SPEED, math.pi),
        ("1 kg*m/s^2", u.FORCE, 1.0),
        ("2 N m", u.TORQUE, 2.0),  # a space multiplies
        ("5 1/s", u.FREQUENCY, 5.0),
        ("1 m^-1", u.LENGTH**-1, 1.0),
        ("2 m^(3/2)", u.LENGTH ** Fraction(3, 2), 2.0),
        ("1 mm^1.5", u.LENGTH ** Fraction(3, 2), 1e-3**1.5),
        ("3 N/(m*s)", u.FORCE / u.LENGTH / u.TIME, 3.0),
        ("4 N*m/rad", u.ROTATIONAL_STIFFNESS, 4.0),
        ("-0.04 m", u.LENGTH, -0.04),
        ("+.5 m", u.LENGTH, 0.5),
        ("0.3", u.DIMENSIONLESS, 0.3),  # a bare number string is SI
        ("0.3 m", u.LENGTH, 0.3),
    ],
)
def test_quantity_to_si(text: str, dim: u.Dimension, expected: float) -> None:
    assert to_si(text, dim) == pytest.approx(expected, rel=1e-15, abs=0)


def test_exact_decimal_prefixes_give_the_nearest_float() -> None:
    # 7.5 * 0.001 in floating point is 0.0075000000000000006; the parser is exact.
    assert to_si("7.5 mm", u.LENGTH) == 0.0075
    assert to_si("0.04 m", u.LENGTH) == 0.04
    assert to_si("15 mm", u.LENGTH) == 0.015


def test_plain_numbers_are_si() -> None:
    assert to_si(2.37, u.MASS) == 2.37
    assert to_si(3, u.ANGULAR_SPEED) == 3.0
    assert u.to_si_with_dimension(0.5, (u.ANGLE, u.LENGTH)) == (0.5, None)


def test_g_is_gram_for_a_mass_and_standard_gravity_for_an_acceleration() -> None:
    assert to_si("1 g", u.ACCELERATION) == 9.80665
    assert to_si("1 g", u.MASS) == 0.001
    assert to_si("2 kg", u.MASS) == 2.0  # a prefixed g is always the gram
    with pytest.raises(UnitError, match=r"'1 kg': expected an acceleration \[m/s\^2\], got a mass"):
        to_si("1 kg", u.ACCELERATION)


def test_alternatives_report_the_dimension_found() -> None:
    speed = (u.ANGULAR_SPEED, u.SPEED)
    assert u.to_si_with_dimension("300 rpm", speed) == (10 * math.pi, u.ANGULAR_SPEED)
    assert u.to_si_with_dimension("2 m/s", speed) == (2.0, u.SPEED)


@pytest.mark.parametrize(
    ("text", "dim", "message"),
    [
        ("0.72 m", u.MASS, "'0.72 m': expected a mass [kg], got a length [m]"),
        ("90 deg", u.TIME, "'90 deg': expected a time [s], got an angle [rad]"),
        ("300 rpm", u.SPEED, "'300 rpm': expected a speed [m/s], got an angular speed [rad/s]"),
        # the angle is tracked: a frequency is not an angular speed, a torque has no rad
        ("10 Hz", u.ANGULAR_SPEED, "'10 Hz': expected an angular speed [rad/s], got a frequency"),
        ("5 N*m/rad", u.TORQUE, "expected a torque [N*m], got a rotational stiffness [N*m/rad]"),
        ("1 g", u.LENGTH, "'1 g': expected a length [m], got a mass [kg] or an acceleration"),
        ("1e4 N/m", u.HERTZ_STIFFNESS, "expected a contact stiffness [N/m^1.5], got a stiffness"),
    ],
)
def test_wrong_dimension_names_the_value_and_both_dimensions(
    text: str, dim: u.Dimension, message: str
) -> None:
    with pytest.raises(UnitError) as err:
        to_si(text, dim)
    assert message in str(err.value)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("0,72 kg", "'0,72 kg': malformed number"),
        ("1.2.3 kg", "'1.2.3 kg': malformed number"),
        ("kg", "'kg': malformed number"),
        ("twelve kg", "'twelve kg': malformed number"),
        ("", "'': empty value"),
        ("1e400 kg", "'1e400 kg': must be finite"),
        (float("nan"), "nan: must be finite"),
        (True, "True: expected a number or a quantity string like '1 kg'"),
        ([1.0], "[1.0]: expected a number or a quantity string"),
        ("5 KG", "'5 KG': unknown unit 'KG' (did you mean 'kg'? unit names are case-sensitive)"),
        ("5 Nm", "'5 Nm': unknown unit 'Nm' (write N*m)"),
        ("5 furlong", "'5 furlong': unknown unit 'furlong'"),
        ("5 kg^", "'5 kg^': unit 'kg^' ends too early"),
        ("5 kg^x", "bad exponent in unit 'kg^x' at 'x'"),
        ("5 kg/", "unit 'kg/' ends too early"),
        ("5 (kg", "unit '(kg' ends too early"),
        ("5 kg)", "cannot read unit 'kg)' at ')'"),
        ("5 kg$", "cannot read unit 'kg$' at '$'"),
    ],
)
def test_malformed_values_are_named(value: object, message: str) -> None:
    with pytest.raises(UnitError) as err:
        to_si(value, u.MASS)
    assert message in str(err.value)


def test_unit_error_is_a_value_error() -> None:
    assert issubclass(UnitError, ValueError)


def test_from_si_expresses_a_value_in_a_unit() -> None:
    assert u.from_si(0.015, "mm") == pytest.approx(15.0, rel=1e-15)
    assert u.from_si(10 * math.pi, "rpm") == pytest.approx(300.0, rel=1e-15)


def test_dimension_algebra_and_names() -> None:
    assert u.FORCE == u.MASS * u.LENGTH / u.TIME**2
    assert u.HERTZ_STIFFNESS.si_unit() == "N/m^1.5"
    assert u.describe(u.ANGULAR_SPEED) == "an angular speed [rad/s]"
    assert (u.MASS * u.TIME).noun() == "[kg*s]"
    assert len(u.parse_unit("g")) == 2 and len(u.parse_unit("kg")) == 1


@pytest.mark.parametrize(
    ("text", "dim", "expected"),
    [
        ("1/12 kg*m^2", u.INERTIA, 1 / 12),
        ("2.28*(0.05^2 + 0.05^2)/12 kg*m^2", None, None),
        ("2.28*0.05^2/6 kg*m^2", u.INERTIA, 2.28 * 0.05**2 / 6),
        ("0.72*0.32^2/12 kg*m^2", u.INERTIA, 0.72 * 0.32**2 / 12),
        ("-1/4 N*m", u.TORQUE, -0.25),
        ("300/60 rev/s", u.ANGULAR_SPEED, 10 * math.pi),
        ("2 kg*m^2/12", u.INERTIA, 1 / 6),
        ("1e-3/4 kg", u.MASS, 2.5e-4),
        ("5 1/s", u.FREQUENCY, 5.0),
    ],
)
def test_unit_expressions_with_numbers(text: str, dim: u.Dimension | None, expected: float) -> None:
    """A value may carry its arithmetic: factors multiply, divide and take powers like
    units, left to right (``2 kg*m^2/12`` is a sixth of a kg*m^2)."""
    if dim is None:  # a sum is not a product of factors: named, not misread
        with pytest.raises(UnitError, match="cannot add or subtract"):
            to_si(text, u.INERTIA)
        return
    assert to_si(text, dim) == pytest.approx(expected, rel=1e-15)


def test_numbers_in_a_unit_keep_its_dimension_checked() -> None:
    with pytest.raises(UnitError, match=r"expected a moment of inertia \[kg\*m\^2\], got a mass"):
        to_si("1/12 kg", u.INERTIA)
