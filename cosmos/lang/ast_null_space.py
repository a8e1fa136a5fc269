"""The syntax tree's nodes of the null-space statements (seed section 4): ORIENTATION and POSTURE.

Kept beside :mod:`cosmos.lang.ast`, which names them in its ``Statement`` union.
"""

from __future__ import annotations

from dataclasses import dataclass

from cosmos.errors import Span
from cosmos.lang.expressions import Expr


@dataclass(frozen=True)
class SetOrientation:
    """``ORIENTATION FREE`` / ``ORIENTATION HELD``: whether MOVE and WAIT control the tool's orientation."""

    free: bool
    span: Span


@dataclass(frozen=True)
class SetPosture:
    """``POSTURE q`` (joint angles, or a named pose such as ``home``) or ``POSTURE NONE``."""

    value: Expr | None
    span: Span
