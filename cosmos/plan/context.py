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


ORIGIN_PARTS = 4
"""An origin deeper than this many expansions names the outermost two and the innermost two."""


def origin(context: str) -> str:
    """`` (in PROC p called at line 3; ...)``: how an expanded statement's message ends ("" at top level).

    A deep one keeps its ends: ``(in PROC a called at line 9; PROC b called at line 7; ... 146 more
    ...; PROC y called at line 3; PROC z called at line 2)``.
    """
    parts = context_parts(context)
    if len(parts) > ORIGIN_PARTS:
        parts = [*parts[:2], f"... {len(parts) - 4} more ...", *parts[-2:]]
    return f" (in {joined_context(parts)})" if parts else ""
