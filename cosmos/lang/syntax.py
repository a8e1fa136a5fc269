"""Syntax errors in words a person knows.

Lark reports an unexpected token and the set of terminals it expected. This
module turns that into a message: an unknown unit after a number, a misspelt
keyword (the nearest expected keyword, by difflib), a misspelt statement at the
start of a line, a block left open at the end of the file, or one of the common
slips recognised with Lark's ``match_examples`` (a MOVE without TO or BY, a
CONTACT without a direction, ...). Whatever is left reads "unexpected X;
expected A, B or C".
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable, Iterable
from typing import Any

from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from cosmos.errors import ProgramError, Span
from cosmos.lang import units

MAX_NESTING = 64
"""Deepest parenthesis nesting accepted (deeper input is refused before parsing)."""

STATEMENT_KEYWORDS = (
    "MOVE", "CONTACT", "SLIDE", "INSERT", "COMPLY", "OBSTACLE", "LET", "FRAME", "SPEED",
    "WAIT", "PROC", "REPEAT", "CALL",
)  # fmt: skip

# Display of non-keyword terminals in "expected ..." lists.
_PUNCTUATION = {
    "LPAR": "'('",
    "RPAR": "')'",
    "COMMA": "','",
    "EQUAL": "'='",
    "STAR": "'*'",
    "PLUS": "'+'",
    "MINUS": "'-'",
    "COMPARE": "'>' or '<'",
    "_NL": "the end of the line",
    "$END": "the end of the file",
    "QUANTITY": "a number",
    "WORD": "a name",
}

_DIRECTIONS = "+X -X +Y -Y +Z -Z, UP or DOWN"

# Common slips, recognised by the parser state they fail in (Lark match_examples).
_EXAMPLES: dict[str, list[str]] = {
    "expected TO or BY after MOVE: MOVE TO (0.5, 0.1, 0.3), MOVE TO hole, or MOVE BY (0, 0, -50 mm)": [
        "MOVE (0.5, 0.1, 0.3)",
        "MOVE 5 mm",
        "MOVE",
        "MOVE SPEED 3",
    ],
    f"CONTACT needs a direction first: {_DIRECTIONS} (as in CONTACT DOWN FORCE 10 N)": [
        "CONTACT FORCE 10 N",
        "CONTACT",
        "CONTACT (0, 0, 1)",
        "CONTACT 5",
    ],
    f"SLIDE needs a direction first: {_DIRECTIONS} (as in SLIDE +X BY 100 mm)": [
        "SLIDE BY 100 mm",
        "SLIDE",
        "SLIDE (1, 0, 0)",
        "SLIDE 5",
    ],
    f"INSERT needs a direction first: {_DIRECTIONS} (as in INSERT DOWN DEPTH 25 mm FORCE 15 N)": [
        "INSERT DEPTH 25 mm",
        "INSERT",
        "INSERT (0, 0, 1)",
        "INSERT 5",
    ],
    "expected '=' after the name: LET name = value": ["LET x 5", "LET x", "LET x (1, 2, 3)"],
    "expected '=' after the name: FRAME name = (x, y, z) RPY (roll, pitch, yaw)": [
        "FRAME f (0, 0, 0)",
        "FRAME f",
        "FRAME f 5",
    ],
    "LET needs a name: LET name = value": ["LET = 5", "LET 5 = 3", "LET"],
    "FRAME needs a name: FRAME name = (x, y, z)": ["FRAME = (0, 0, 0)", "FRAME 5", "FRAME"],
    "COMPLY needs axes (X Y Z RX RY RZ) or NONE, as in COMPLY X Y": [
        "COMPLY",
        "COMPLY STIFFNESS 3",
        "COMPLY 5",
        "COMPLY (1, 0, 0)",
    ],
    "OBSTACLE needs a name, then a shape (SPHERE, CYLINDER, BOX or PLANE): "
    "OBSTACLE ball SPHERE AT (0.4, 0.2, 0.5) RADIUS 50 mm": [
        "OBSTACLE ball AT (1, 2, 3)",
        "OBSTACLE ball",
        "OBSTACLE ball 5",
        "OBSTACLE",
        "OBSTACLE 5",
        "OBSTACLE (1, 2, 3)",
    ],
    "OBSTACLE REMOVE needs the obstacle's name": ["OBSTACLE REMOVE", "OBSTACLE REMOVE 3"],
    "UNTIL needs a comparison with > or <, as in UNTIL FORCE > 5 N": [
        "MOVE BY (0, 0, 1) UNTIL FORCE 5 N",
        "MOVE BY (0, 0, 1) UNTIL FORCE",
        "MOVE BY (0, 0, 1) UNTIL FORCE Z 5 N",
        "MOVE BY (0, 0, 1) UNTIL FORCE Z",
        "MOVE BY (0, 0, 1) UNTIL DISTANCE 4 mm",
        "MOVE BY (0, 0, 1) UNTIL DISTANCE",
    ],
    "UNTIL compares FORCE, TORQUE or DISTANCE with a value, as in UNTIL FORCE > 5 N": [
        "MOVE BY (0, 0, 1) UNTIL 5 N",
        "MOVE BY (0, 0, 1) UNTIL",
        "MOVE BY (0, 0, 1) UNTIL x > 3",
        "MOVE BY (0, 0, 1) UNTIL FORCE > 5 N AND",
        "MOVE BY (0, 0, 1) UNTIL FORCE > 5 N OR 3",
    ],
    "REPEAT needs a count: REPEAT 3 ... END": ["REPEAT\nEND", "REPEAT TIMES\nEND"],
    "PROC needs a name: PROC name ... END": ["PROC\nEND", "PROC 3\nEND"],
    "VIA needs one or more positions: MOVE TO p VIA a, b": [
        "MOVE TO (0, 0, 0) VIA",
        "MOVE TO (0, 0, 0) VIA SPEED 3",
    ],
    "CALL needs the name of a PROC": ["CALL", "CALL 3"],
    "RPY needs three angles: RPY (180 deg, 0, 0)": ["FRAME f = (0, 0, 0) RPY"],
}


_PREFIXES = ("", "WAIT 1 s\n", "PROC p\n", "PROC p\nWAIT 1 s\n")
"""Each slip is also tried after a line and inside a PROC: the parser's stack
differs there, and parser states are compared whole."""

_example_errors: list[tuple[str, UnexpectedToken, set[str]]] | None = None


def _match_example(error: UnexpectedToken, parse: Callable[[str], Any]) -> str | None:
    """The label of the common slip that fails in the same parser state as ``error``.

    Like Lark's ``UnexpectedInput.match_examples``, but the examples are parsed
    once per process rather than on every error.
    """
    global _example_errors
    if _example_errors is None:
        found = []
        for label, examples in _EXAMPLES.items():
            for prefix in _PREFIXES:
                for example in examples:
                    try:
                        parse(prefix + example)
                    except UnexpectedToken as failure:
                        found.append((label, failure, set(failure.accepts or failure.expected)))
                    except UnexpectedInput:
                        pass
        _example_errors = found
    accepts = set(error.accepts or error.expected)
    candidate = None
    for label, example_error, example_accepts in _example_errors:
        if example_error.state == error.state and example_accepts == accepts:
            if example_error.token.type == error.token.type:
                return label
            candidate = candidate or label
    return candidate


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


def _display(name: str, terminal_text: Callable[[str], str | None]) -> str:
    if name in _PUNCTUATION:
        return _PUNCTUATION[name]
    text = terminal_text(name)
    return text.upper() if text else name


def _join_or(items: Iterable[str]) -> str:
    listed = list(dict.fromkeys(items))
    if len(listed) <= 1:
        return "".join(listed)
    return ", ".join(listed[:-1]) + " or " + listed[-1]


def _expected_text(expected: Iterable[str], terminal_text: Callable[[str], str | None]) -> str:
    names = set(expected)
    value_start = {"QUANTITY", "LPAR", "WORD"}
    parts: list[str] = []
    if value_start <= names:
        parts.append("a value (a number like 10 N, a name, or (x, y, z))")
        names -= value_start | {"MINUS", "PLUS"}
    keywords = sorted(n for n in names if n not in _PUNCTUATION and terminal_text(n))
    others = [n for n in names if n not in keywords]
    parts += [_display(n, terminal_text) for n in keywords]
    parts += sorted(_display(n, terminal_text) for n in others if n != "_NL")
    if "_NL" in names:
        parts.append(_PUNCTUATION["_NL"])
    return _join_or(parts)


def _acceptable(error: UnexpectedToken) -> set[str]:
    """Terminals the parser could take where it failed.

    Lark's ``accepts`` tries each terminal on a copy of the parser (exact, where
    LALR's merged lookaheads are not); where it finds none, the terminals the
    parser state has actions for (the interactive parser's ``choices``) stand in.
    """
    parser = error.interactive_parser
    try:
        accepts = error.accepts
    except Exception:  # noqa: BLE001 - Lark's interactive parser is best effort here
        accepts = None
    if accepts:
        return set(accepts)
    if parser is not None:
        return set(parser.choices())
    return set(error.expected)


def _token_span(token: Any, file: str) -> Span:
    line = getattr(token, "line", None) or 1
    column = getattr(token, "column", None) or 1
    end_line = getattr(token, "end_line", None) or line
    end_column = getattr(token, "end_column", None) or column + 1
    if (end_line, end_column) <= (line, column):
        end_line, end_column = line, column + 1
    return Span(file, line, column, end_line, end_column)


def _describe_token(token: Any) -> str:
    if token.type == "_NL":
        return "end of line" if str(token) != ";" else "';'"
    if token.type == "$END":
        return "end of file"
    return f"'{token}'"


def _open_block(source: str, file: str) -> ProgramError | None:
    """The innermost PROC or REPEAT left without END, judged from line starts."""
    stack: list[tuple[int, int, str]] = []
    for number, line in enumerate(source.splitlines(), start=1):
        match = re.match(r"\s*([A-Za-z_]\w*)", line)
        if not match:
            continue
        word = match[1].upper()
        if word in ("PROC", "REPEAT"):
            stack.append((number, match.start(1) + 1, word))
        elif word == "END" and stack:
            stack.pop()
    if not stack:
        return None
    number, column, word = stack[-1]
    return ProgramError(
        f"this {word} has no END: close the block with a line that says END",
        Span(file, number, column, number, column + len(word)),
    )


def _closest(word: str, candidates: Iterable[str], cutoff: float) -> tuple[str, float] | None:
    best: tuple[str, float] | None = None
    for candidate in candidates:
        ratio = difflib.SequenceMatcher(None, word.upper(), candidate.upper()).ratio()
        if ratio >= cutoff and (best is None or ratio > best[1]):
            best = (candidate, ratio)
    return best


def _line_text(source: str, line: int) -> str:
    lines = source.splitlines()
    return lines[line - 1] if 1 <= line <= len(lines) else ""


def syntax_error(
    error: UnexpectedInput,
    source: str,
    file: str,
    parse: Callable[[str], Any],
    terminal_text: Callable[[str], str | None],
    keywords: frozenset[str],
) -> ProgramError:
    """A :class:`ProgramError` for a Lark parse error.

    Args:
        error: What Lark raised.
        source: The program text.
        file: The name spans carry.
        parse: Parses a text without mapping errors (for ``match_examples``).
        terminal_text: The keyword text of a terminal name (None if not a keyword).
        keywords: Every keyword, upper case.
    """
    if isinstance(error, UnexpectedCharacters):
        position = error.pos_in_stream if error.pos_in_stream is not None else -1
        char = source[position] if 0 <= position < len(source) else "?"
        shown = repr(char) if not char.isprintable() else f"'{char}'"
        hint = " (strings are not part of the language)" if char in "\"'" else ""
        span = Span(file, error.line, error.column, error.line, error.column + 1)
        return ProgramError(f"unexpected character {shown}{hint}", span)
    if not isinstance(error, UnexpectedToken):
        line = getattr(error, "line", 1) or 1
        column = getattr(error, "column", 1) or 1
        return ProgramError("unexpected end of the program", Span(file, line, column, line, column + 1))

    token = error.token
    expected = _acceptable(error)
    span = _token_span(token, file)
    text = str(token)
    before = _line_text(source, span.line)[: span.column - 1]

    if token.type == "$END" or (token.type == "_NL" and span.line > len(source.splitlines())):
        block = _open_block(source, file)
        if block is not None:
            return block

    if token.type == "END" and "END" not in expected and _open_block(source, file) is None:
        return ProgramError("END without a PROC or REPEAT to close", span)

    keyword_candidates = [n for n in expected if terminal_text(n)]
    if token.type == "WORD":
        keyword = _closest(text, [terminal_text(n) or "" for n in keyword_candidates], 0.7)
        if re.search(r"(\d|\d\.)[ \t]*$", before) and text.upper() not in keywords:
            unit = _closest(text, units.KNOWN_UNITS, 0.5)
            if keyword is None or (unit is not None and unit[1] > keyword[1]):
                return ProgramError(f"'{text}' is not a unit{units.suggest_unit(text)}", span)
        first = re.match(r"\s*([A-Za-z_]\w*)\s*$", before)
        if first and first[1].upper() not in STATEMENT_KEYWORDS:
            return _unknown_statement(first, span.line, file, keywords)
        if keyword is not None:
            return ProgramError(f"unknown word '{text}'; did you mean {keyword[0].upper()}?", span)
    else:
        first = re.match(r"\s*([A-Za-z_]\w*)\s*$", before)
        if first and first[1].upper() not in STATEMENT_KEYWORDS and first[1].upper() != "END":
            return _unknown_statement(first, span.line, file, keywords)

    label = _match_example(error, parse)
    if label is not None:
        return ProgramError(label, span)

    statement = re.match(r"\s*([A-Za-z_]\w*)", _line_text(source, span.line))
    if (
        statement
        and statement[1].upper() in STATEMENT_KEYWORDS
        and terminal_text(token.type)
        and token.type not in expected
        and "_NL" in expected
    ):
        return ProgramError(
            f"{text.upper()} is not a clause of {statement[1].upper()}; "
            f"expected {_expected_text(expected, terminal_text)}",
            span,
        )
    if "MOVE" in expected:
        return ProgramError(
            f"unexpected {_describe_token(token)}: a line starts with a statement "
            f"({', '.join(STATEMENT_KEYWORDS)}), or is a PROC's name alone (a call)",
            span,
        )
    return ProgramError(
        f"unexpected {_describe_token(token)}; expected {_expected_text(expected, terminal_text)}",
        span,
    )


def _unknown_statement(first: re.Match[str], line: int, file: str, keywords: frozenset[str]) -> ProgramError:
    """The first word of a line is not a statement keyword and more follows it."""
    word = first[1]
    column = first.start(1) + 1
    span = Span(file, line, column, line, column + len(word))
    if word.upper() in keywords:
        return ProgramError(
            f"{word.upper()} does not start a statement; a line starts with "
            f"{', '.join(STATEMENT_KEYWORDS)}, or is a PROC's name alone (a call)",
            span,
        )
    match = _closest(word, STATEMENT_KEYWORDS, 0.6)
    if match:
        return ProgramError(f"unknown statement '{word}'; did you mean {match[0]}?", span)
    return ProgramError(
        f"unknown statement '{word}': a line starts with a statement "
        f"({', '.join(STATEMENT_KEYWORDS)}), or is a PROC's name alone (a call)",
        span,
    )
