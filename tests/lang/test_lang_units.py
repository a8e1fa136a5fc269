"""Units: conversions to SI and dimensions."""

from __future__ import annotations

import math

import pytest

from cosmos.lang import units


@pytest.mark.parametrize(
    ("text", "factor", "dim"),
    [
        ("mm", 1e-3, units.LENGTH),
        ("cm", 1e-2, units.LENGTH),
        ("m", 1.0, units.LENGTH),
        ("deg", math.pi / 180, units.ANGLE),
        ("rad", 1.0, units.ANGLE),
        ("ms", 1e-3, units.TIME),
        ("min", 60.0, units.TIME),
        ("N", 1.0, units.FORCE),
        ("kN", 1e3, units.FORCE),
        ("Nm", 1.0, units.TORQUE),
        ("N m", 1.0, units.TORQUE),
        ("N.m", 1.0, units.TORQUE),
        ("mm/s", 1e-3, units.SPEED),
        ("deg/s", math.pi / 180, units.ANGULAR_SPEED),
        ("N/mm", 1e3, units.STIFFNESS),
        ("Nm/rad", 1.0, units.ROTATIONAL_STIFFNESS),
        ("N m/rad", 1.0, units.ROTATIONAL_STIFFNESS),
        ("Nm/deg", 180 / math.pi, units.ROTATIONAL_STIFFNESS),
        ("N s/m", 1.0, units.DAMPING),
        ("N m s/rad", 1.0, units.ROTATIONAL_DAMPING),
        ("MM/S", 1e-3, units.SPEED),
    ],
)
def test_units_convert_to_si(text: str, factor: float, dim: units.Dim) -> None:
    unit = units.parse_unit(text)
    assert unit.factor == pytest.approx(factor)
    assert unit.dim == dim


def test_every_documented_unit_has_a_named_dimension() -> None:
    for text in units.KNOWN_UNITS:
        assert not units.describe(units.parse_unit(text).dim).startswith("a quantity in"), text


def test_unknown_unit_suggests_a_near_one() -> None:
    with pytest.raises(units.UnknownUnit, match="did you mean 'mm/s'"):
        units.parse_unit("mm/ss")


def test_torque_and_rotational_stiffness_differ() -> None:
    assert units.parse_unit("Nm").dim != units.parse_unit("Nm/rad").dim
