"""Syntax errors in words a person knows.

Lark reports an unexpected token and the set of terminals it expected. This
module turns that into a message: an unknown unit after a number, a misspelt
keyword (the nearest expected keyword, by difflib), a misspelt statement at the
start of a line, a block left open at the end of the file, or one of the common
slips (:mod:`cosmos.lang.parse.slips`: a MOVE without TO or BY, a CONTACT
without a direction, ...). Whatever is left reads "unexpected X;
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
from cosmos.lang.parse.grammar import statement_keywords
from cosmos.lang.parse.slips import match_slip

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
    """The innermost block (PROC, REPEAT, IF, WHILE, TRY) left without END, judged from line starts."""
    stack: list[tuple[int, int, str]] = []
    for number, line in enumerate(source.splitlines(), start=1):
        match = re.match(r"\s*([A-Za-z_]\w*)", line)
        if not match:
            continue
        word = match[1].upper()
        if word in ("PROC", "REPEAT", "IF", "WHILE", "TRY"):
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


_LOOK_ALIKES = {
    **dict.fromkeys("\u2212\u2013\u2014", " (not the minus sign: write '-')"),
    "\u00b0": " (write angles with a unit: 90 deg)",
    **dict.fromkeys("\u00b5\u03bc", " (no unit has micro: write mm, 5 um = 0.005 mm)"),
    **dict.fromkeys("\u00a0\u2009\u202f", " (a non-breaking space: write an ordinary one)"),
    **dict.fromkeys("\u201c\u201d\u2018\u2019", " (strings are not part of the language)"),
    "\u00d7": " (write '*' to multiply)",
}
"""What a character pasted from a document stands for, where it looks like one the language has."""


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
        hint = " (strings are not part of the language)" if char in "\"'" else _LOOK_ALIKES.get(char, "")
        if char.isdigit() and not char.isascii():
            hint = " (a digit outside ASCII: write numbers with 0-9)"
        elif not hint and char.isalpha():
            hint = " (names are ASCII letters, digits and _)"
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

    if token.type == "END" and "ON" in expected:
        return ProgramError("TRY needs ON FAIL before its END: TRY ... ON FAIL ... END", span)
    if token.type == "END" and "END" not in expected and _open_block(source, file) is None:
        return ProgramError("END without a PROC or REPEAT to close (nor an IF, WHILE or TRY)", span)

    opening = re.match(r"\s*(IF|WHILE)\b", before, re.IGNORECASE)
    if opening and token.type == "WORD" and text.upper() in ("THEN", "DO") and "_NL" in expected:
        return ProgramError(
            f"{opening[1].upper()} takes no {text}: its statements follow on the next lines", span
        )
    keyword_candidates = [n for n in expected if terminal_text(n)]
    if token.type == "WORD":
        keyword = _closest(text, [terminal_text(n) or "" for n in keyword_candidates], 0.7)
        if re.search(r"(\d|\d\.)[ \t]*$", before) and text.upper() not in keywords:
            unit = _closest(text, units.KNOWN_UNITS, 0.5)
            if keyword is None or (unit is not None and unit[1] > keyword[1]):
                return ProgramError(f"'{text}' is not a unit{units.suggest_unit(text)}", span)
        first = re.match(r"\s*([A-Za-z_]\w*)\s*$", before)
        if first and first[1].upper() not in statement_keywords():
            return _unknown_statement(first, span.line, file, keywords)
        if keyword is not None:
            return ProgramError(f"unknown word '{text}'; did you mean {keyword[0].upper()}?", span)
    else:
        first = re.match(r"\s*([A-Za-z_]\w*)\s*$", before)
        if first and first[1].upper() not in statement_keywords() and first[1].upper() != "END":
            return _unknown_statement(first, span.line, file, keywords)

    label = match_slip(error, parse)
    if label is not None:
        return ProgramError(label, span)

    statement = re.match(r"\s*([A-Za-z_]\w*)", _line_text(source, span.line))
    if (
        statement
        and statement[1].upper() in statement_keywords()
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
            f"({', '.join(statement_keywords())}), or is a PROC's name alone (a call)",
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
            f"{', '.join(statement_keywords())}, or is a PROC's name alone (a call)",
            span,
        )
    match = _closest(word, statement_keywords(), 0.6)
    if match:
        return ProgramError(f"unknown statement '{word}'; did you mean {match[0]}?", span)
    return ProgramError(
        f"unknown statement '{word}': a line starts with a statement "
        f"({', '.join(statement_keywords())}), or is a PROC's name alone (a call)",
        span,
    )
