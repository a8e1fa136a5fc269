"""Units and dimensions of the language's quantities.

A dimension is the tuple of exponents of (metre, kilogram, second, radian); the
radian is kept as a base dimension so that a torque (N m) and a rotational
stiffness (N m/rad) stay distinct. Values are converted to SI on reading, and a
bare number (no unit) takes the SI unit of the slot it is written in.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass

Dim = tuple[int, int, int, int]
"""Exponents of (m, kg, s, rad)."""

DIMENSIONLESS: Dim = (0, 0, 0, 0)
LENGTH: Dim = (1, 0, 0, 0)
TIME: Dim = (0, 0, 1, 0)
ANGLE: Dim = (0, 0, 0, 1)
FORCE: Dim = (1, 1, -2, 0)
TORQUE: Dim = (2, 1, -2, 0)
SPEED: Dim = (1, 0, -1, 0)
ANGULAR_SPEED: Dim = (0, 0, -1, 1)
STIFFNESS: Dim = (0, 1, -2, 0)
ROTATIONAL_STIFFNESS: Dim = (2, 1, -2, -1)
DAMPING: Dim = (0, 1, -1, 0)
ROTATIONAL_DAMPING: Dim = (2, 1, -1, -1)
MASS: Dim = (0, 1, 0, 0)

_DESCRIPTIONS: dict[Dim, tuple[str, str]] = {
    DIMENSIONLESS: ("a plain number", "3"),
    LENGTH: ("a length", "25 mm"),
    TIME: ("a duration", "2 s"),
    ANGLE: ("an angle", "90 deg"),
    FORCE: ("a force", "10 N"),
    TORQUE: ("a torque", "2 Nm"),
    SPEED: ("a speed", "0.1 m/s"),
    ANGULAR_SPEED: ("an angular speed", "30 deg/s"),
    STIFFNESS: ("a stiffness", "400 N/m"),
    ROTATIONAL_STIFFNESS: ("a rotational stiffness", "20 Nm/rad"),
    DAMPING: ("a damping", "40 N s/m"),
    ROTATIONAL_DAMPING: ("a rotational damping", "2 N m s/rad"),
    MASS: ("a mass", "0.5 kg"),
}

# Numerator and denominator words, lower case, spaces and '.', '*' removed.
_NUMERATORS: dict[str, tuple[float, Dim]] = {
    "mm": (1e-3, LENGTH),
    "cm": (1e-2, LENGTH),
    "m": (1.0, LENGTH),
    "ms": (1e-3, TIME),
    "s": (1.0, TIME),
    "min": (60.0, TIME),
    "n": (1.0, FORCE),
    "kn": (1e3, FORCE),
    "nm": (1.0, TORQUE),
    "ns": (1.0, (1, 1, -1, 0)),
    "nms": (1.0, (2, 1, -1, 0)),
    "deg": (math.pi / 180.0, ANGLE),
    "rad": (1.0, ANGLE),
    "kg": (1.0, MASS),
    "g": (1e-3, MASS),
}
_DENOMINATORS: dict[str, tuple[float, Dim]] = {
    "mm": (1e-3, LENGTH),
    "cm": (1e-2, LENGTH),
    "m": (1.0, LENGTH),
    "ms": (1e-3, TIME),
    "s": (1.0, TIME),
    "min": (60.0, TIME),
    "deg": (math.pi / 180.0, ANGLE),
    "rad": (1.0, ANGLE),
}

KNOWN_UNITS: tuple[str, ...] = (
    "mm", "cm", "m", "N", "kN", "Nm", "N m", "deg", "rad", "s", "ms", "min",
    "m/s", "mm/s", "deg/s", "rad/s", "N/m", "N/mm", "Nm/rad", "N m/rad", "N s/m", "N m s/rad",
    "kg", "g",
)  # fmt: skip
"""Units as documented (docs/language.md); matching ignores case and spacing."""


@dataclass(frozen=True)
class Unit:
    """A parsed unit: multiply a number by ``factor`` to get SI of dimension ``dim``."""

    text: str
    factor: float
    dim: Dim


_SEPARATORS = str.maketrans("", "", " \t.*")
"""What may stand between the words of a unit (``N m``, ``N.m``, ``N*m``), dropped."""


class UnknownUnit(ValueError):
    """A unit the language does not know; ``str()`` says which and suggests one."""


def parse_unit(text: str) -> Unit:
    """Parse a unit as written (``mm/s``, ``N m/rad``, ``Nm``), ignoring case and spaces.

    Raises:
        UnknownUnit: The text is not a known unit.
    """
    compact = text.casefold().translate(_SEPARATORS)
    numerator, _, denominator = compact.partition("/")
    num = _NUMERATORS.get(numerator)
    den = _DENOMINATORS.get(denominator) if denominator else (1.0, DIMENSIONLESS)
    if num is None or den is None:
        raise UnknownUnit(f"unknown unit '{text}'{suggest_unit(text)}")
    dim = tuple(a - b for a, b in zip(num[1], den[1], strict=True))
    return Unit(text=text, factor=num[0] / den[0], dim=dim)  # type: ignore[arg-type]


def suggest_unit(word: str) -> str:
    """``" (did you mean 'mm'?)"`` for a near miss, else a list of units."""
    folded = {unit.casefold(): unit for unit in KNOWN_UNITS}
    close = difflib.get_close_matches(word.casefold(), list(folded), n=1, cutoff=0.5)
    if close:
        return f"; did you mean '{folded[close[0]]}'?"
    return "; expected a unit like " + ", ".join(KNOWN_UNITS[:12])


def describe(dim: Dim) -> str:
    """``"a force"``, ``"a length"``, or the exponents for an unnamed dimension."""
    if dim in _DESCRIPTIONS:
        return _DESCRIPTIONS[dim][0]
    parts = [
        f"{base}^{power}" if power != 1 else base
        for base, power in zip(("m", "kg", "s", "rad"), dim, strict=True)
        if power
    ]
    return "a quantity in " + " ".join(parts)


def plural(dim: Dim) -> str:
    """``"lengths"``, ``"angles"``: the dimension's name without article, plural."""
    return describe(dim).split(" ", 1)[1] + "s"


def example(dim: Dim) -> str:
    """An example value of the dimension, for messages (``"10 N"``)."""
    return _DESCRIPTIONS.get(dim, ("", "1"))[1]


def multiply(a: Dim, b: Dim) -> Dim:
    """The dimension of a product."""
    return tuple(x + y for x, y in zip(a, b, strict=True))  # type: ignore[return-value]
