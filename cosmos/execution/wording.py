"""How a failed statement is named in messages: its head, and the head with the reason."""

from __future__ import annotations

_CLAUSE_WORDS = frozenset(("UNTIL", "TIMEOUT", "IN", "SPEED"))


def statement_head(statement: str) -> str:
    """The statement's keyword and its first operand, as messages name it (``CONTACT UP``, ``WAIT 2 s``)."""
    words = statement.split()
    unit = len(words) > 2 and words[1][:1].isdigit() and words[2].isalpha()  # WAIT 2 s
    return " ".join(words[:3] if unit and words[2].upper() not in _CLAUSE_WORDS else words[:2])


def failure_text(statement: str, reason: str) -> str:
    """A failed statement's message, its head and the reason.

    ``CONTACT UP found no contact within 1.5 s``; a protective stop after a colon:
    ``MOVE BY: protective stop: tool hit fixture 'table' at 2.60 s, 31.2 N``.
    """
    joiner = ": " if reason.startswith("protective stop") else " "
    return f"{statement_head(statement)}{joiner}{reason}".strip()
