"""When an input is complete: the rule that lets Enter run it or start a new line.

An input is complete unless a block is open (PROC, REPEAT, IF, WHILE, TRY: the
parser says it needs an END, or a TRY its ON FAIL) or the last line ends in a
backslash (a continuation). Two empty lines in a row end an input regardless,
so an unfinished block can always be handed over (and reported). An open
parenthesis does not continue the input: the language ends a statement at the
end of its line, so the parser's "expected ')'" is the useful answer.
"""

from __future__ import annotations

import re

from cosmos.lang import needs_more_input

INDENT = "    "
"""What a line inside a block is indented by."""
_BLOCK_START = re.compile(r"\s*(PROC|REPEAT|IF|WHILE|TRY|ELSE|ON\s+FAIL)\b", re.IGNORECASE)
_BLOCK_END = re.compile(r"\s*END\b", re.IGNORECASE)


def input_complete(text: str) -> bool:
    """Whether ``text`` is a whole input: run it on Enter rather than start a new line."""
    if not text.strip() or text.lstrip().startswith(":"):
        return True
    lines = text.split("\n")
    if len(lines) >= 3 and not lines[-1].strip() and not lines[-2].strip():
        return True
    if lines[-1].split("#", 1)[0].rstrip().endswith("\\"):
        return False
    return not needs_more_input(text)


def next_indent(line: str) -> str:
    """Indentation for the line after ``line``: deeper after a block's start, shallower after END."""
    indent = line[: len(line) - len(line.lstrip())]
    if _BLOCK_START.match(line):
        return indent + INDENT
    if _BLOCK_END.match(line):
        return indent[: max(len(indent) - len(INDENT), 0)]
    return indent
