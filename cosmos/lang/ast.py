"""The syntax tree of a COSMOS program: frozen dataclasses, each with its source span.

The tree stays close to the text: numbers keep the unit as written, names keep
their spelling (lookups fold case), and clauses keep their order. Meaning
(units, frames, selection axes) is given by the compiler. This module holds the
statements; the parts they are made of (expressions, conditions, clauses) are
in :mod:`cosmos.lang.expressions` and are named here too.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from cosmos.errors import Span
from cosmos.lang.expressions import (
    AllOf as AllOf,
)
from cosmos.lang.expressions import (
    AnyOf as AnyOf,
)
from cosmos.lang.expressions import (
    Axis as Axis,
)
from cosmos.lang.expressions import (
    AxisRef as AxisRef,
)
from cosmos.lang.expressions import (
    Binary as Binary,
)
from cosmos.lang.expressions import (
    Clause as Clause,
)
from cosmos.lang.expressions import (
    ClauseKind as ClauseKind,
)
from cosmos.lang.expressions import (
    Comparison as Comparison,
)
from cosmos.lang.expressions import (
    ComplyClause as ComplyClause,
)
from cosmos.lang.expressions import (
    Condition as Condition,
)
from cosmos.lang.expressions import (
    Direction as Direction,
)
from cosmos.lang.expressions import (
    Expr as Expr,
)
from cosmos.lang.expressions import (
    Ident as Ident,
)
from cosmos.lang.expressions import (
    Name as Name,
)
from cosmos.lang.expressions import (
    Number as Number,
)
from cosmos.lang.expressions import (
    Pose as Pose,
)
from cosmos.lang.expressions import (
    Sensed as Sensed,
)
from cosmos.lang.expressions import (
    Unary as Unary,
)
from cosmos.lang.expressions import (
    UntilClause as UntilClause,
)
from cosmos.lang.expressions import (
    ValueClause as ValueClause,
)
from cosmos.lang.expressions import (
    Vector as Vector,
)
from cosmos.lang.expressions import (
    ViaClause as ViaClause,
)

# ----------------------------------------------------------------- statements


class MoveMode(enum.Enum):
    """``MOVE TO`` an absolute target or ``MOVE BY`` an offset."""

    TO = "TO"
    BY = "BY"


class Shape(enum.Enum):
    """Obstacle primitives."""

    SPHERE = "SPHERE"
    CYLINDER = "CYLINDER"
    BOX = "BOX"
    PLANE = "PLANE"


@dataclass(frozen=True)
class Move:
    """``MOVE TO target`` / ``MOVE BY offset`` with clauses."""

    mode: MoveMode
    target: Expr
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class Contact:
    """``CONTACT direction`` with clauses."""

    direction: Direction
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class Slide:
    """``SLIDE direction BY distance`` with clauses."""

    direction: Direction
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class Insert:
    """``INSERT direction DEPTH d FORCE f`` with clauses."""

    direction: Direction
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class Comply:
    """``COMPLY axes [STIFFNESS k] [DAMPING d]``; ``axes`` empty for ``COMPLY NONE``."""

    axes: tuple[AxisRef, ...]
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class Obstacle:
    """``OBSTACLE name SHAPE AT p ...``."""

    name: Ident
    shape: Shape
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class RemoveObstacle:
    """``OBSTACLE REMOVE name``."""

    name: Ident
    span: Span


@dataclass(frozen=True)
class Let:
    """``LET name = value``."""

    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class FrameDef:
    """``FRAME name = position [RPY angles]``."""

    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class SetSpeed:
    """``SPEED v``: the default speed limit for what follows."""

    value: Expr
    span: Span


@dataclass(frozen=True)
class Wait:
    """``WAIT [t] [UNTIL c] [TIMEOUT t]``."""

    duration: Expr | None
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class ProcDef:
    """``PROC name`` ... ``END``; ``span`` covers the header line only."""

    name: Ident
    body: tuple[Statement, ...]
    end_tag: str | None
    span: Span


@dataclass(frozen=True)
class Repeat:
    """``REPEAT n [TIMES]`` ... ``END``; ``span`` covers the header line only."""

    count: Expr
    body: tuple[Statement, ...]
    end_tag: str | None
    span: Span


@dataclass(frozen=True)
class Call:
    """``CALL name`` or ``name`` alone on a line."""

    name: Ident
    span: Span


Statement = (
    Move
    | Contact
    | Slide
    | Insert
    | Comply
    | Obstacle
    | RemoveObstacle
    | Let
    | FrameDef
    | SetSpeed
    | Wait
    | ProcDef
    | Repeat
    | Call
)


@dataclass(frozen=True)
class Program:
    """A parsed source file."""

    statements: tuple[Statement, ...]
    file: str
    source: str
