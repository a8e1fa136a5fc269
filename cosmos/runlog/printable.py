"""Text from a log made safe to print: no control characters reach the terminal.

A log's metadata, statements and reasons are untrusted text; an escape
sequence in them would be interpreted by the terminal (colours, a window title
change, a cleared screen). :func:`printable` replaces every control character
(C0, DEL, C1) and every bidirectional-override and zero-width format character
with U+FFFD, so what is printed is what the text says, visibly.
"""

from __future__ import annotations

import re
from typing import Final

REPLACEMENT: Final = "\ufffd"

# C0 controls, DEL and C1 controls; the bidirectional embeddings, overrides and isolates
# (U+202A..U+202E, U+2066..U+2069), marks (U+200E, U+200F, U+061C) and the line and paragraph
# separators (U+2028, U+2029), which move or reorder what a terminal shows.
_UNSAFE: Final = re.compile("[\x00-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028\u2029\u202a-\u202e\u2066-\u2069]")
_UNSAFE_KEEP_LINES: Final = re.compile(
    "[\x00-\x09\x0b-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028\u2029\u202a-\u202e\u2066-\u2069]"
)


def printable(text: str, *, keep_newlines: bool = False) -> str:
    """``text`` with every control character replaced by U+FFFD.

    Args:
        text: Text read from a log.
        keep_newlines: Keep line feeds (for multi-line text such as a program).
    """
    pattern = _UNSAFE_KEEP_LINES if keep_newlines else _UNSAFE
    return pattern.sub(REPLACEMENT, text)
