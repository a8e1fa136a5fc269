"""The fast lexer (cosmos/lang/scanner.py, fastparse.statements) against the master expression.

The master expression, one named group per terminal, is the reference: on any
text the fast lexer gives the same statements, of the same kinds, with the same
tokens at the same places, or gives up exactly where the reference meets a bad
character or a word outside ASCII.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cosmos.lang.fastparse import UNREAD, GiveUp, statements
from cosmos.lang.lalr_tables import Role, Tables
from cosmos.lang.parser import _tables
from cosmos.lang.scanner import blanks_pattern, non_capturing

ROOT = Path(__file__).parents[2]
CORPUS = [path.read_text() for path in sorted((ROOT / "programs").glob("*.cos"))]
CORPUS += re.findall(r"```cosmos\n(.*?)```", (ROOT / "docs" / "language.md").read_text(), re.S)


def _reference(text: str, tables: Tables) -> Any:
    """What the master expression makes of ``text``: (shape, placed tokens) per statement."""
    out: list[Any] = []
    shape: list[str] = []
    placed: list[tuple[str, str, int, int, int]] = []
    pieces = text.split("\n")
    lines = [piece + "\n" for piece in pieces[:-1]] + [pieces[-1]]
    for line, piece in enumerate(lines, 1):
        for match in tables.lexer.finditer(piece):
            group: int = match.lastindex  # type: ignore[assignment]
            kind, role = tables.kinds[group], tables.roles[group]
            start, stop = match.span(group)
            value = piece[start:stop]
            if role is Role.BAD or (role is Role.WORD and not value.isascii()):
                return "gives up"
            if role in (Role.IGNORED, Role.IGNORED_BREAK):
                continue
            assert kind is not None
            if role is Role.WORD:  # a word that spells a keyword is lexed as the keyword
                kind = tables.keywords.get(value.lower(), kind)
            shape.append(kind)
            if kind not in UNREAD:
                placed.append((kind, value, line, start + 1, stop + 1))
            if role is Role.BREAK:
                out.append((tuple(shape), placed))
                shape, placed = [], []
    if shape:
        out.append((tuple(shape), placed))
    return out


def _fast(text: str, tables: Tables) -> Any:
    try:
        return [
            (
                shape,
                [(t.type, t.value, t.line, t.column, t.end_column) for t in tokens if t.type not in UNREAD],
            )
            for tokens, shape in statements(text, tables)
        ]
    except GiveUp:
        return "gives up"


@pytest.mark.parametrize("text", CORPUS, ids=lambda text: repr(text[:30]))
def test_the_scanner_lexes_the_corpus_as_the_master_expression(text: str) -> None:
    tables = _tables()
    assert _fast(text, tables) == _reference(text, tables)


PIECES = [
    "MOVE", "to", "x", "_a1", "é", "\u212a", "\u017f", "\u0663", "1", "2.5", ".5", ".", "1e-3", "10 mm",
    "0.3 m/s", "5 N m/rad", "3 n*m", "2 Nm", "\\", "\\\n", "\\ \r\n", "\\\r", "(", ")", ",", "=", "+",
    "-", "*", ">", ">=", "<=", "\n", "\r", "\r\n", ";", "#c", "# é\n", " ", "\t", "\f", "\v", "@", "/",
]  # fmt: skip


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(PIECES) | st.characters(max_codepoint=400), max_size=30))
def test_the_scanner_lexes_character_soups_as_the_master_expression(pieces: list[str]) -> None:
    tables = _tables()
    text = "".join(pieces)
    assert _fast(text, tables) == _reference(text, tables)


def test_only_capturing_groups_become_non_capturing() -> None:
    assert non_capturing(r"(\r?\n|\r)") == r"(?:\r?\n|\r)"
    assert non_capturing(r"\([(](?i:a)(?=b)[]()]") == r"\([(](?i:a)(?=b)[]()]"


def test_blanks_of_repeated_classes_are_one_repeated_class() -> None:
    assert blanks_pattern(["[ \t]+", "[\\]x]+"]) == "[ \t\\]x]*"
    assert blanks_pattern(["[^a]+"]) == "(?:(?:[^a]+))*"  # a negated class is left as it is
    assert blanks_pattern([]) == "(?:(?!))*"
