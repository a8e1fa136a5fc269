"""The parts statements are made of: expressions, names, directions and conditions.

Frozen dataclasses, each with its source span; :mod:`cosmos.lang.ast` holds the
statements and their clauses, and names these parts too (``ast.Number``, ``ast.Comparison``).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from cosmos.errors import Span


class Axis(enum.Enum):
    """One of the six axes of a task frame; ``value`` is its index in a 6-vector."""

    X = 0
    Y = 1
    Z = 2
    RX = 3
    RY = 4
    RZ = 5

    @property
    def is_rotation(self) -> bool:
        """True for RX, RY, RZ."""
        return self.value >= 3


# ---------------------------------------------------------------- expressions


@dataclass(frozen=True)
class Number:
    """A number as written, with its unit text (``None`` for a bare number)."""

    value: float
    unit: str | None
    span: Span


@dataclass(frozen=True)
class Name:
    """A reference to a LET, FRAME or fixture name."""

    name: str
    span: Span


@dataclass(frozen=True)
class Vector:
    """``(a, b, c)``: a parenthesised list of two or more expressions."""

    items: tuple[Expr, ...]
    span: Span


@dataclass(frozen=True)
class Unary:
    """``-x`` or ``+x``."""

    op: str
    operand: Expr
    span: Span


@dataclass(frozen=True)
class Binary:
    """``a + b``, ``a - b`` or ``a * b``."""

    op: str
    left: Expr
    right: Expr
    span: Span


@dataclass(frozen=True)
class Pose:
    """``position RPY (roll, pitch, yaw)``, angles about the fixed world axes."""

    position: Expr
    rpy: Expr
    span: Span


Expr = Number | Name | Vector | Unary | Binary | Pose


@dataclass(frozen=True)
class Ident:
    """A name where it is defined or used as a label (PROC, OBSTACLE, LET)."""

    name: str
    span: Span

    @property
    def key(self) -> str:
        """The case-folded name used for lookups."""
        return self.name.casefold()


@dataclass(frozen=True)
class Direction:
    """``+X``, ``-Z``, ``UP`` (= +Z), ``DOWN`` (= -Z), or a bare axis (= +axis)."""

    axis: Axis
    sign: int
    span: Span

    @property
    def text(self) -> str:
        """The direction as ``+X`` / ``-RZ``."""
        return f"{'+' if self.sign > 0 else '-'}{self.axis.name}"


@dataclass(frozen=True)
class AxisRef:
    """An axis named in COMPLY or an INSERT's COMPLY clause."""

    axis: Axis
    span: Span


# ----------------------------------------------------------------- conditions


class Sensed(enum.Enum):
    """What a condition measures (POSITION only in IF and WHILE; FINGER FORCE only with TOOL GRIPPER)."""

    FORCE = "FORCE"
    TORQUE = "TORQUE"
    DISTANCE = "DISTANCE"
    POSITION = "POSITION"
    FINGER = "FINGER FORCE"


@dataclass(frozen=True)
class Comparison:
    """``FORCE > 5 N``, ``FORCE Z < -3 N``, ``TORQUE RZ > 1 Nm``, ``DISTANCE > 40 mm``."""

    sensed: Sensed
    direction: Direction | None
    op: str
    value: Expr
    span: Span


@dataclass(frozen=True)
class AllOf:
    """Conditions joined by AND."""

    items: tuple[Condition, ...]
    span: Span


@dataclass(frozen=True)
class AnyOf:
    """Conditions joined by OR."""

    items: tuple[Condition, ...]
    span: Span


class LastKind(enum.Enum):
    """An outcome of the statement run last that a condition can ask about."""

    FAILED = "FAILED"
    STOPPED = "STOPPED"


@dataclass(frozen=True)
class LastOutcome:
    """``LAST FAILED`` / ``LAST STOPPED``: how the statement run last ended (IF and WHILE only)."""

    kind: LastKind
    span: Span


Condition = Comparison | AllOf | AnyOf | LastOutcome
