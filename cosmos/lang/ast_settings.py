"""Syntax-tree nodes of the statements that set what follows: SPEED, LIMIT FORCE, ROBOT.

Part of :mod:`cosmos.lang.ast` (which names them), kept apart to keep that module short.
"""

from __future__ import annotations

from dataclasses import dataclass

from cosmos.errors import Span
from cosmos.lang.expressions import Expr, Ident


@dataclass(frozen=True)
class SetSpeed:
    """``SPEED v``: the default speed limit for what follows."""

    value: Expr
    span: Span


@dataclass(frozen=True)
class SetLimit:
    """``LIMIT FORCE f``: the protective stop's force limit in free motion, for what follows."""

    value: Expr
    span: Span


@dataclass(frozen=True)
class ChooseRobot:
    """``ROBOT name``: the arm the program runs on (its first statement; the PUMA 560 without it)."""

    name: Ident
    span: Span
