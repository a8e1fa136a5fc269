"""Syntax-tree nodes of the hand: TOOL, OBJECT, GRASP, RELEASE (docs/language.md, "Hand")."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from cosmos.errors import Span
from cosmos.lang.expressions import Ident

# The clauses are :mod:`cosmos.lang.ast`'s (``Clause``); named loosely here, as that module
# names these nodes in its ``Statement`` union and an import back would be a circle.
Clauses = tuple[Any, ...]


@dataclass(frozen=True)
class ChooseTool:
    """``TOOL name``: the hand on the flange (``PEG``, the default, or ``GRIPPER``)."""

    name: Ident
    span: Span


@dataclass(frozen=True)
class DeclareObject:
    """``OBJECT name BOX|CYLINDER SIZE ... MASS ... AT pose [FRICTION mu]``: a free body of the workcell."""

    name: Ident
    shape: str  # BOX or CYLINDER, as the grammar spells the keyword
    clauses: Clauses
    span: Span


@dataclass(frozen=True)
class Grasp:
    """``GRASP [object] [FORCE f] [WIDTH w]``: close the gripper on an object and hold it."""

    object_name: Ident | None
    clauses: Clauses
    span: Span


@dataclass(frozen=True)
class Release:
    """``RELEASE``: open the gripper and let go of what it holds."""

    span: Span
