"""What a sweep may vary (``--vary NAME=DIST``), the distributions, and each run's draws.

A value is written as in the language (``1mm``, ``1 mm``, ``0.5 deg``, ``-2 N``; the units
are the language's, :func:`cosmos.lang.parse_unit`); a bare number takes the SI unit of the
parameter (metres, radians, newtons, kilograms). A distribution is ``normal(mean, sd)``,
``uniform(lo, hi)`` or one value (a constant).

Each run's values come from the sweep's seed and the run's index only: run ``i`` draws
parameter ``name`` from ``SeedSequence(seed, spawn_key=(i, crc32(name)))`` (``spawn_key=(i,)``
is the i-th child of ``SeedSequence(seed).spawn``), so a run is reproducible alone, and adding
or removing one ``--vary`` does not change the other parameters' draws.
"""

from __future__ import annotations

import math
import re
import zlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import Enum

import numpy as np

from cosmos.errors import UsageError

Dim = tuple[int, int, int, int]  # exponents of (m, kg, s, rad), as cosmos.lang.units
LENGTH: Dim = (1, 0, 0, 0)
ANGLE: Dim = (0, 0, 0, 1)
FORCE: Dim = (1, 1, -2, 0)
TORQUE: Dim = (2, 1, -2, 0)
MASS: Dim = (0, 1, 0, 0)
NUMBER: Dim = (0, 0, 0, 0)

FIXTURES = ("hole", "table", "slope")
"""The language's fixture frames whose real pose a sweep may move."""
POSE_AXES = ("x", "y", "z", "rx", "ry", "rz")
BIAS_AXES = ("fx", "fy", "fz", "tx", "ty", "tz")
SEED = "seed"
MODEL_ERROR = "model_error"
MODEL_ERROR_MAX = 0.5
"""The largest model-error scale: friction is drawn within twice it, so beyond it a drive's friction
could be negative (and beyond 1 a link's mass)."""


@dataclass(frozen=True)
class Parameter:
    """A quantity of the workcell a sweep may vary.

    Attributes:
        name: As written after ``--vary`` (``hole.x``).
        dim: Its dimension (exponents of m, kg, s, rad).
        si_unit: Unit of its SI value, for printing (``m``, ``rad``, ``N``).
        shown_unit: Unit for people (``mm``, ``deg``), and ``shown_scale`` SI -> shown.
        help: What it changes.
        minimum: Its least value: a constant or a uniform's end below it is refused, a normal's
            draws below it are clipped to it (None: no bound).
        maximum: Its greatest value, likewise (None: no bound).
    """

    name: str
    dim: Dim
    si_unit: str
    shown_unit: str
    shown_scale: float
    help: str
    minimum: float | None = None
    maximum: float | None = None

    def outside(self, value: float) -> bool:
        """Whether ``value`` [SI] is out of its range."""
        low = -math.inf if self.minimum is None else self.minimum
        high = math.inf if self.maximum is None else self.maximum
        return not low <= value <= high


def _parameters() -> dict[str, Parameter]:
    table: dict[str, Parameter] = {}
    for fixture in FIXTURES:
        for axis in ("x", "y", "z"):
            table[f"{fixture}.{axis}"] = Parameter(
                f"{fixture}.{axis}", LENGTH, "m", "mm", 1e3, f"{fixture} fixture moved along world {axis}"
            )
        for axis in ("rx", "ry", "rz"):
            table[f"{fixture}.{axis}"] = Parameter(
                f"{fixture}.{axis}",
                ANGLE,
                "rad",
                "deg",
                180.0 / math.pi,
                f"{fixture} fixture turned about world {axis[1]} through its frame's origin",
            )
    table["friction"] = Parameter(
        "friction", NUMBER, "", "", 1.0, "sliding friction of tool and fixture contacts (0.3)", 0.0
    )
    table["payload"] = Parameter(
        "payload", MASS, "", "kg", 1.0, "mass added to the tool at its centre of mass [kg]", 0.0
    )
    for axis in BIAS_AXES:
        force = axis.startswith("f")
        table[f"bias.{axis}"] = Parameter(
            f"bias.{axis}",
            FORCE if force else TORQUE,
            "N" if force else "Nm",
            "N" if force else "Nm",
            1.0,
            f"wrist sensor bias, {axis[1]} {'force' if force else 'torque'} (sensor axes)",
        )
    table[MODEL_ERROR] = Parameter(
        MODEL_ERROR,
        NUMBER,
        "",
        "",
        1.0,
        "the realistic plant's model error: link masses, inertias within it, friction within twice it "
        "(0.05; at most 0.5, where a drive's friction may be drawn as none)",
        0.0,
        MODEL_ERROR_MAX,
    )
    table[SEED] = Parameter(SEED, NUMBER, "", "", 1.0, "the wrist sensor's noise seed (a constant)")
    return table


PARAMETERS: Mapping[str, Parameter] = _parameters()
"""Every parameter a sweep may vary, by name."""


class Kind(Enum):
    """The shape of a distribution."""

    CONSTANT = "constant"
    NORMAL = "normal"
    UNIFORM = "uniform"


@dataclass(frozen=True)
class Vary:
    """One ``--vary NAME=DIST``: a parameter and its distribution, SI values.

    Attributes:
        name: The parameter's name.
        kind: Constant, normal or uniform.
        a: The constant, the mean or the low end [SI].
        b: 0, the standard deviation or the high end [SI].
    """

    name: str
    kind: Kind
    a: float
    b: float = 0.0

    @property
    def parameter(self) -> Parameter:
        """The parameter varied."""
        return PARAMETERS[self.name]

    def text(self) -> str:
        """The canonical ``NAME=DIST`` in SI units (exact floats), as the results file records it."""
        unit = self.parameter.si_unit
        if self.kind is Kind.CONSTANT:
            return f"{self.name}={_si(self.a, unit)}"
        return f"{self.name}={self.kind.value}({_si(self.a, unit)}, {_si(self.b, unit)})"

    def draw(self, seed: int, index: int) -> float:
        """Run ``index``'s value of this parameter [SI]."""
        if self.kind is Kind.CONSTANT:
            return self.a
        rng = np.random.default_rng(
            np.random.SeedSequence(seed, spawn_key=(index, zlib.crc32(self.name.encode())))
        )
        value = float(rng.normal(self.a, self.b) if self.kind is Kind.NORMAL else rng.uniform(self.a, self.b))
        low, high = self.parameter.minimum, self.parameter.maximum
        value = value if low is None else max(value, low)
        return value if high is None else min(value, high)


def _si(value: float, unit: str) -> str:
    return f"{value!r}{(' ' + unit) if unit else ''}"


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_QUANTITY = re.compile(rf"^\s*({_NUMBER})\s*(.*?)\s*$")
_CALL = re.compile(r"^\s*(normal|uniform)\s*\((.*)\)\s*$", re.IGNORECASE)


def parse_value(text: str, parameter: Parameter, where: str) -> float:
    """A value with the language's units (``1mm``, ``0.5 deg``) in SI; a bare number is SI.

    Raises:
        UsageError: Not a number, an unknown unit, or a unit of another dimension.
    """
    from cosmos.lang import UnknownUnit, parse_unit

    match = _QUANTITY.match(text)
    if match is None:
        raise UsageError(f"{where}: '{text.strip()}' is not a number with a unit (like 1 mm)")
    number, unit_text = float(match.group(1)), match.group(2)
    if not math.isfinite(number):
        raise UsageError(f"{where}: '{match.group(1)}' is not a finite number")
    if not unit_text:
        return number
    if parameter.dim == MASS:
        raise UsageError(f"{where}: {parameter.name} is a bare number in kg (the language has no mass unit)")
    try:
        unit = parse_unit(unit_text)
    except UnknownUnit as error:
        raise UsageError(f"{where}: {error}") from None
    if unit.dim != parameter.dim:
        shown = parameter.shown_unit or "a bare number"
        raise UsageError(f"{where}: {parameter.name} is in {shown}; '{unit_text}' is not a unit of that kind")
    return number * unit.factor


def parse_vary(text: str) -> Vary:
    """One ``NAME=DIST`` of ``--vary``.

    Raises:
        UsageError: An unknown name, a malformed distribution, a wrong unit, a negative spread.
    """
    where = f"--vary {text}"
    name, sep, dist = text.partition("=")
    name = name.strip()
    if not sep:
        raise UsageError(f"{where}: expected NAME=DIST, like hole.x=normal(0, 1mm)")
    if name not in PARAMETERS:
        raise UsageError(f"{where}: unknown parameter '{name}'; known: {', '.join(PARAMETERS)}")
    parameter = PARAMETERS[name]
    call = _CALL.match(dist)
    if call is None:
        value = parse_value(dist, parameter, where)
        if name == SEED and (value != int(value) or value < 0):
            raise UsageError(f"{where}: the noise seed is a whole number >= 0")
        _within_range(parameter, (value,), where)
        return Vary(name, Kind.CONSTANT, value)
    if name == SEED:
        raise UsageError(f"{where}: the noise seed is a constant (each run draws its own by default)")
    kind = Kind(call.group(1).lower())
    arguments = [part for part in call.group(2).split(",")]
    if len(arguments) != 2:
        raise UsageError(f"{where}: {kind.value}() takes two values, like {kind.value}(0, 1mm)")
    a, b = (parse_value(part, parameter, where) for part in arguments)
    if kind is Kind.NORMAL and b < 0:
        raise UsageError(f"{where}: the standard deviation must be >= 0")
    if kind is Kind.UNIFORM and b < a:
        raise UsageError(f"{where}: uniform(lo, hi) needs lo <= hi")
    _within_range(parameter, (a, b) if kind is Kind.UNIFORM else (), where)
    return Vary(name, kind, a, b)


def _within_range(parameter: Parameter, values: Sequence[float], where: str) -> None:
    """Refuse a constant or a uniform's end outside the parameter's range, naming the range."""
    if not any(parameter.outside(value) for value in values):
        return
    scale, unit = parameter.shown_scale, f" {parameter.shown_unit}" if parameter.shown_unit else ""
    low = "" if parameter.minimum is None else f"{parameter.minimum * scale:g}{unit}"
    high = "" if parameter.maximum is None else f"{parameter.maximum * scale:g}{unit}"
    bounds = f"from {low} to {high}" if low and high else (f"at least {low}" if low else f"at most {high}")
    raise UsageError(f"{where}: {parameter.name} must be {bounds}")


def parse_varies(texts: Sequence[str]) -> tuple[Vary, ...]:
    """Every ``--vary``, in the order given; a parameter given twice is an error."""
    varies = tuple(parse_vary(text) for text in texts)
    names = [vary.name for vary in varies]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise UsageError(f"--vary: {', '.join(twice)} given more than once")
    return varies


def noise_seed(seed: int, index: int) -> int:
    """Run ``index``'s wrist-sensor noise seed, from the sweep's seed (unless ``seed`` is varied)."""
    return int(np.random.SeedSequence(seed, spawn_key=(index,)).generate_state(1, np.uint32)[0])


def draw(varies: Sequence[Vary], seed: int, index: int) -> dict[str, float]:
    """Run ``index``'s values: every varied parameter [SI] and the noise ``seed``."""
    values = {vary.name: vary.draw(seed, index) for vary in varies}
    values.setdefault(SEED, float(noise_seed(seed, index)))
    return values
