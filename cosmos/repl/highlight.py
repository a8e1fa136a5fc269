"""Syntax highlighting of typed input: a prompt_toolkit lexer built from the language's keywords.

Line by line, left to right: comments, REPL commands, numbers with their
units, directions (``+X``, ``-RZ``), statement keywords (first on a line or
after ``;``), other keywords, names the session knows (frames, obstacles,
procedures), punctuation. Nothing here judges the input; the parser does that
when it runs.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from functools import cache

from prompt_toolkit.document import Document
from prompt_toolkit.formatted_text import StyleAndTextTuples
from prompt_toolkit.lexers import Lexer
from prompt_toolkit.styles import Style

from cosmos.lang import units
from cosmos.lang.parse.grammar import keywords, statement_keywords

STYLE = Style.from_dict(
    {
        "statement": "bold ansiblue",
        "keyword": "ansicyan",
        "number": "ansigreen",
        "direction": "ansiyellow",
        "name": "ansimagenta",
        "comment": "italic ansibrightblack",
        "command": "bold ansiyellow",
        "bottom-toolbar": "noreverse bg:ansiblack ansiwhite",
    }
)
"""Colours of the token classes below, and of the bottom toolbar."""


@cache
def _token_pattern() -> re.Pattern[str]:
    unit_words = sorted(units.KNOWN_UNITS, key=len, reverse=True)
    unit = "|".join(re.escape(u).replace(r"\ ", r"[ \t]*") for u in unit_words)
    return re.compile(
        rf"""
        (?P<comment>\#.*)
        | (?P<command>^\s*:\w*)
        | (?P<number>(?:\d+\.?\d*|\.\d+)(?:e[+-]?\d+)?(?:[ \t]*(?:{unit})(?![A-Za-z0-9_]))?)
        | (?P<direction>[+-]R?[XYZ](?![A-Za-z0-9_]))
        | (?P<word>[A-Za-z_]\w*)
        | (?P<other>.)
        """,
        re.VERBOSE | re.IGNORECASE,
    )


def highlight_line(line: str, known_names: set[str]) -> StyleAndTextTuples:
    """Styled fragments of one line.

    Args:
        line: The text.
        known_names: Case-folded names the session defines (shown as names).
    """
    words = keywords()
    fragments: StyleAndTextTuples = []
    at_start = True  # the next word starts a statement
    for match in _token_pattern().finditer(line):
        kind = match.lastgroup or "other"
        text = match.group()
        style = ""
        starts = at_start
        if not text.isspace():
            at_start = text == ";"
        if kind == "word":
            upper = text.upper()
            if starts and (upper in statement_keywords() or upper == "END"):
                style = "class:statement"
            elif text.casefold() in known_names:
                style = "class:name"
            elif upper in words:
                style = "class:keyword"
        elif kind != "other":
            style = f"class:{kind}"
        fragments.append((style, text))
    return fragments


class CosmosLexer(Lexer):
    """Highlights input as it is typed.

    Args:
        names: Returns the case-folded names the session knows now.
    """

    def __init__(self, names: Callable[[], set[str]]):
        self._names = names

    def lex_document(self, document: Document) -> Callable[[int], StyleAndTextTuples]:
        """A function from line number to the line's styled fragments."""
        lines = document.lines
        known = self._names()

        def line_fragments(number: int) -> StyleAndTextTuples:
            if not 0 <= number < len(lines):
                return []
            return highlight_line(lines[number], known)

        return line_fragments
