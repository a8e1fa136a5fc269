"""How a failed statement is named in messages: its head, the reason, and where it was expanded from."""

from __future__ import annotations

import re
from collections.abc import Sequence

from cosmos.plan.context import context_parts, joined_context, origin

_CLAUSE_WORDS = frozenset(("UNTIL", "TIMEOUT", "IN", "SPEED"))


def statement_head(statement: str) -> str:
    """The statement's keyword and its first operand, as messages name it (``CONTACT UP``, ``WAIT 2 s``).

    A decision's is its keyword alone: its condition's first word (``WHILE POSITION``) names nothing.
    """
    words = statement.split()
    if words and words[0].upper() in ("IF", "WHILE"):
        return words[0]
    if len(words) > 1 and words[1].upper() in {"FORCE", "WIDTH", "SPEED", "TIMEOUT"}:  # GRASP FORCE 40 N
        return words[0]
    unit = len(words) > 2 and words[1][:1].isdigit() and words[2].isalpha()  # WAIT 2 s
    return " ".join(words[:3] if unit and words[2].upper() not in _CLAUSE_WORDS else words[:2])


def failure_text(statement: str, reason: str, context: str = "") -> str:
    """A failed statement's message: its head, the reason and, for an expanded statement, its origin.

    ``CONTACT UP found no contact within 1.5 s``; a protective stop after a colon:
    ``MOVE BY: protective stop: tool hit fixture 'table' at 2.60 s, 31.2 N``; a
    statement of a procedure or a loop's pass ends as the compiler's errors do:
    ``CONTACT DOWN found no contact within 0.5 s (in PROC probe called at line 5)``; a reason
    that is a sentence of its own after a colon too: ``RELEASE: the gripper holds nothing``.
    """
    joiner = ": " if reason.startswith(("protective stop", "the ")) else " "
    return f"{statement_head(statement)}{joiner}{reason}".strip() + origin(context)


def run_context(static: str, frames: Sequence[tuple[str, str]]) -> str:
    """A statement's context at run time: its compiled one with the passes the walker is in.

    The compiler knows the PROC calls and REPEAT passes a statement was expanded
    from (``static``); only the run knows a WHILE's pass or a TRY's retry. Each
    frame is ``(the loop's own compiled context, "WHILE pass 2 at line 6")``;
    a statement inside the loop has the loop's context as the start of its own,
    so the frame goes in after it.

    Args:
        static: The statement's compiled context.
        frames: The walker's open frames, outermost first.
    """
    parts = context_parts(static)
    merged: list[str] = []
    used = 0
    for frame_static, text in frames:
        outer = context_parts(frame_static)
        merged.extend(parts[used : len(outer)])
        merged.append(text)
        used = max(used, len(outer))
    merged.extend(parts[used:])
    return joined_context(merged)


def short_context(context: str) -> str:
    """A context as a replay table's row shows it: ``pass 2/2 @6 > probe @7`` (outermost first)."""
    return " > ".join(_short(part) for part in context_parts(context))


def _short(part: str) -> str:
    part = re.sub(r" at line (\d+)$", r" @\1", part)
    part = re.sub(r"^PROC (\S+) called ", r"\1 ", part)
    part = re.sub(r"^REPEAT pass (\d+) of (\d+)", r"pass \1/\2", part)
    return part
