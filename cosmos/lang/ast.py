"""The syntax tree of a COSMOS program: frozen dataclasses, each with its source span.

The tree stays close to the text: numbers keep the unit as written, names keep their spelling
(lookups fold case), clauses keep their order; the compiler gives meaning (units, frames, axes).
The parts of statements (expressions, names, directions, conditions) are in
:mod:`cosmos.lang.expressions`, the null-space statements in :mod:`cosmos.lang.ast_null_space`.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from cosmos.errors import Span
from cosmos.lang.ast_hand import ChooseTool, DeclareObject, Grasp, Release
from cosmos.lang.ast_null_space import SetOrientation, SetPosture
from cosmos.lang.ast_settings import ChooseRobot, SetLimit, SetSpeed
from cosmos.lang.expressions import (
    AllOf,
    AnyOf,
    Axis,
    AxisRef,
    Binary,
    Comparison,
    Condition,
    Direction,
    Expr,
    Ident,
    LastKind,
    LastOutcome,
    Name,
    Number,
    Pose,
    Sensed,
    Unary,
    Vector,
)

__all__ = [  # the statements and clauses here, and the parts of cosmos.lang.expressions
    "AllOf",
    "AnyOf",
    "Axis",
    "AxisRef",
    "Binary",
    "Call",
    "ChooseRobot",
    "ChooseTool",
    "DeclareObject",
    "Grasp",
    "Release",
    "Clause",
    "ClauseKind",
    "Comparison",
    "Comply",
    "ComplyClause",
    "Condition",
    "Contact",
    "Direction",
    "Expr",
    "FrameDef",
    "Ident",
    "IfBlock",
    "Insert",
    "LastKind",
    "LastOutcome",
    "Let",
    "Move",
    "MoveMode",
    "Name",
    "Number",
    "Obstacle",
    "Pose",
    "ProcDef",
    "Program",
    "RemoveObstacle",
    "Repeat",
    "Retry",
    "SearchClause",
    "SearchPattern",
    "Sensed",
    "SetLimit",
    "SetOrientation",
    "SetPosture",
    "SetSpeed",
    "Shape",
    "Slide",
    "Statement",
    "TryBlock",
    "Unary",
    "UntilClause",
    "ValueClause",
    "Vector",
    "ViaClause",
    "Wait",
    "WhileBlock",
]


# -------------------------------------------------------------------- clauses


class ClauseKind(enum.Enum):
    """The keyword of a clause that takes one value."""

    SPEED = "SPEED"
    FORCE = "FORCE"
    TIMEOUT = "TIMEOUT"
    IN = "IN"
    BY = "BY"
    DEPTH = "DEPTH"
    STIFFNESS = "STIFFNESS"
    DAMPING = "DAMPING"
    AT = "AT"
    RADIUS = "RADIUS"
    HEIGHT = "HEIGHT"
    SIZE = "SIZE"
    MOVING = "MOVING"
    NORMAL = "NORMAL"
    INFLUENCE = "INFLUENCE"
    GAIN = "GAIN"
    MAX = "MAX"
    PITCH = "PITCH"
    MASS = "MASS"
    FRICTION = "FRICTION"
    WIDTH = "WIDTH"


@dataclass(frozen=True)
class ValueClause:
    """A clause made of a keyword and a value: ``SPEED 0.1 m/s``, ``AT (0.4, 0, 0)``."""

    kind: ClauseKind
    value: Expr
    span: Span


@dataclass(frozen=True)
class ViaClause:
    """``VIA a, b``: intermediate goals, in order."""

    points: tuple[Expr, ...]
    span: Span


@dataclass(frozen=True)
class UntilClause:
    """``UNTIL condition``."""

    condition: Condition
    span: Span


@dataclass(frozen=True)
class ComplyClause:
    """``COMPLY X Y RX RY`` inside INSERT; ``axes`` is empty for ``COMPLY NONE``."""

    axes: tuple[AxisRef, ...]
    span: Span


class SearchPattern(enum.Enum):
    """The pattern of INSERT's SEARCH."""

    SPIRAL = "SPIRAL"
    LISSAJOUS = "LISSAJOUS"


@dataclass(frozen=True)
class SearchClause:
    """``SEARCH SPIRAL RADIUS r PITCH p`` inside INSERT: the pattern and its RADIUS and PITCH."""

    pattern: SearchPattern
    parameters: tuple[ValueClause, ...]
    span: Span


Clause = ValueClause | ViaClause | UntilClause | ComplyClause | SearchClause


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
class Wait:
    """``WAIT [t] [UNTIL c] [TIMEOUT t]``."""

    duration: Expr | None
    clauses: tuple[Clause, ...]
    span: Span


@dataclass(frozen=True)
class ProcDef:
    """``PROC name[(p, q)]`` ... ``END``; ``span`` covers the header line only."""

    name: Ident
    parameters: tuple[Ident, ...]
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
    """``CALL name[(a, b)]`` or ``name[(a, b)]`` alone on a line."""

    name: Ident
    arguments: tuple[Expr, ...]
    span: Span


@dataclass(frozen=True)
class IfBlock:
    """``IF c [IN frame]`` ... [``ELSE`` ...] ``END``; ``span``: the header, ``else_span``: ELSE or None."""

    condition: Condition
    clauses: tuple[Clause, ...]
    then_body: tuple[Statement, ...]
    else_body: tuple[Statement, ...]
    else_span: Span | None
    end_tag: str | None
    span: Span


@dataclass(frozen=True)
class WhileBlock:
    """``WHILE condition [MAX n] [IN frame]`` ... ``END``; ``span`` covers the header line."""

    condition: Condition
    clauses: tuple[Clause, ...]
    body: tuple[Statement, ...]
    end_tag: str | None
    span: Span


@dataclass(frozen=True)
class TryBlock:
    """``TRY`` ... ``ON FAIL`` ... ``END``; ``span`` covers the TRY keyword, ``on_fail_span`` ON FAIL."""

    body: tuple[Statement, ...]
    handler: tuple[Statement, ...]
    on_fail_span: Span
    end_tag: str | None
    span: Span


@dataclass(frozen=True)
class Retry:
    """``RETRY n``: in a TRY's ON FAIL part, run the TRY block again (at most n times in all)."""

    count: Expr
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
    | SetLimit
    | SetOrientation
    | SetPosture
    | ChooseRobot
    | ChooseTool
    | DeclareObject
    | Grasp
    | Release
    | Wait
    | ProcDef
    | Repeat
    | Call
    | IfBlock
    | WhileBlock
    | TryBlock
    | Retry
)


@dataclass(frozen=True)
class Program:
    """A parsed source file."""

    statements: tuple[Statement, ...]
    file: str
    source: str
