"""An expanded step's ``context``: the PROC calls and passes it came from, written one way.

The compiler writes it (``"REPEAT pass 2 of 3 at line 10; PROC pick called at line 12"``,
outermost first), the executor adds the WHILE pass or TRY retry it runs in, and both end an
expanded statement's messages with it: ``... (in PROC pick called at line 12)``.
"""

from __future__ import annotations

from collections.abc import Sequence

SEPARATOR = "; "
"""Between a context's parts, outermost first."""


def joined_context(parts: Sequence[str]) -> str:
    """Context parts (outermost first) as one context string ("" at top level)."""
    return SEPARATOR.join(part for part in parts if part)


def context_parts(context: str) -> list[str]:
    """A context string's parts, outermost first ([] at top level)."""
    return [part for part in context.split(SEPARATOR) if part]


def origin(context: str) -> str:
    """`` (in PROC p called at line 3; ...)``: how an expanded statement's message ends ("" at top level)."""
    return f" (in {context})" if context else ""
