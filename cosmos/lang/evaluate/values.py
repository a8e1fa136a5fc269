"""The values expressions evaluate to, and the bindings names hold.

Values carry a dimension (:mod:`cosmos.lang.units`) or none: a bare number keeps
``dim=None`` until it meets a slot, where it takes the slot's SI unit.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from cosmos.errors import ProgramError, Span
from cosmos.lang import units
from cosmos.lang.units import Dim
from cosmos.rotations import FloatArray


@dataclass(frozen=True)
class Scalar:
    """A number in SI; ``dim`` None for a bare number."""

    value: float
    dim: Dim | None


@dataclass(frozen=True)
class Vec:
    """Two or more numbers in SI sharing one dimension (None if all bare)."""

    values: tuple[float, ...]
    dim: Dim | None


@dataclass(frozen=True, eq=False)
class FrameValue:
    """A frame: an origin in the world and, optionally, an orientation.

    Attributes:
        position: Origin [m], world, (3,).
        rotation: Frame to world, (3, 3); None for a frame given as a bare position
            (it has the world's axes under IN, and keeps the tool's orientation as a
            MOVE target).
    """

    position: FloatArray
    rotation: FloatArray | None


Value = Scalar | Vec | FrameValue


class BindingKind(enum.Enum):
    """Where a name comes from."""

    LET = "LET"
    FRAME = "FRAME"
    FIXTURE = "fixture"
    PARAMETER = "parameter"
    """A procedure's parameter, bound to its argument while the call is compiled."""


@dataclass(frozen=True)
class Binding:
    """A name's value; ``value`` None marks a name whose definition had an error."""

    value: Value | None
    kind: BindingKind
    span: Span | None


class SuppressedError(ProgramError):
    """An error caused by an earlier, already reported one (a broken definition)."""


def kind_of(value: Value) -> str:
    """``"a length"``, ``"a vector of 3 lengths"``, ``"a frame"`` for messages."""
    if isinstance(value, FrameValue):
        return "a frame"
    if isinstance(value, Vec):
        inner = "numbers" if value.dim is None else units.plural(value.dim)
        return f"a vector of {len(value.values)} {inner}"
    return "a plain number" if value.dim is None else units.describe(value.dim)
