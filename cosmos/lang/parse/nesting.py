"""Nesting bounded before parsing: parentheses and blocks (PROC, REPEAT, IF, WHILE, TRY).

The parser does not recurse, but what reads its tree does (the checker, the
compiler, the evaluator, ``repr``): a program nested deeper than these limits is
refused, at the place the limit is passed, before anything recurses over it.
"""

from __future__ import annotations

import re

from cosmos.errors import ProgramError, Span

MAX_NESTING = 64
"""Deepest parenthesis nesting accepted (deeper input is refused before parsing)."""

MAX_BLOCK_DEPTH = 100
"""Deepest nesting of blocks (PROC, REPEAT, IF, WHILE, TRY) accepted (deeper input is
refused before parsing)."""

_COMMENT = re.compile("#[^\n\r\v\f\x1c\x1d\x1e\x85\u2028\u2029]*")
"""A comment, to the end of its line as ``str.splitlines`` ends lines."""
_ONLY_PARENS = {code: None for code in range(128) if chr(code) not in "()"}
"""A ``str.translate`` table that drops every ASCII character but parentheses."""


def _surely_shallow(source: str) -> bool:
    """Whether no parenthesis outside comments is nested deeper than :data:`MAX_NESTING`.

    Told with string operations alone (no loop over the parentheses): each
    round drops the innermost pairs ``()``; when none is left after ``rounds``,
    a parenthesis lies inside at most ``rounds`` pairs and the unmatched ``(``
    left. False where that bound is over the limit (or a character outside
    ASCII stands between parentheses): then they are counted one by one.
    """
    parens = _COMMENT.sub("", source).translate(_ONLY_PARENS)
    for rounds in range(MAX_NESTING + 1):
        inner = parens.replace("()", "")
        if inner == parens:
            return rounds + parens.count("(") <= MAX_NESTING
        parens = inner
    return False


def check_nesting(source: str, file: str) -> None:
    """Refuse parentheses nested deeper than :data:`MAX_NESTING` (before parsing).

    Raises:
        ProgramError: At the first parenthesis past the limit.
    """
    if _surely_shallow(source):
        return
    depth = 0
    for line_number, line in enumerate(source.splitlines(), start=1):
        for column, char in enumerate(line.split("#", 1)[0], start=1):
            if char == "(":
                depth += 1
                if depth > MAX_NESTING:
                    raise ProgramError(
                        f"parentheses nested more than {MAX_NESTING} deep",
                        Span(file, line_number, column, line_number, column + 1),
                    )
            elif char == ")":
                depth = max(depth - 1, 0)


_OPENERS = ("PROC", "REPEAT", "IF", "WHILE", "TRY")
"""The keywords that open a block (END closes it)."""
_STATEMENT_START = re.compile(r"[ \t]*([A-Za-z_]\w*)")
"""The first word of a statement."""


def check_block_nesting(source: str, file: str) -> None:
    """Refuse blocks nested deeper than :data:`MAX_BLOCK_DEPTH` (before parsing).

    A statement that starts with PROC, REPEAT, IF, WHILE or TRY opens a block, one that starts
    with END closes it (statements end at a line break or ';', comments are
    dropped). Only an error can come of counting a line that does not parse.

    Raises:
        ProgramError: At the first block opened past the limit.
    """
    folded = source.upper()
    if sum(folded.count(word) for word in _OPENERS) <= MAX_BLOCK_DEPTH:
        return
    depth = 0
    for line_number, line in enumerate(source.splitlines(), start=1):
        code = _COMMENT.sub("", line)
        offset = 0
        for statement in code.split(";"):
            match = _STATEMENT_START.match(statement)
            if match is not None:
                word = match[1].upper()
                if word in _OPENERS:
                    depth += 1
                    if depth > MAX_BLOCK_DEPTH:
                        column = offset + match.start(1) + 1
                        raise ProgramError(
                            f"blocks nested more than {MAX_BLOCK_DEPTH} deep: this {word} is one too many; "
                            "move the inner blocks into a PROC",
                            Span(file, line_number, column, line_number, column + len(word)),
                        )
                elif word == "END":
                    depth = max(depth - 1, 0)
            offset += len(statement) + 1
