"""Source text to syntax tree: the Lark parser and its errors.

The grammar is ``grammar/cosmos.lark`` (shipped inside the wheel as
``cosmos/grammar/cosmos.lark``). Lark runs LALR with the contextual lexer and
calls the tree builder (:mod:`cosmos.lang.tree_builder`, a ``Transformer``) as
each rule is reduced, so no parse tree is kept. Every token is kept, and a
node's span runs from its first token to its last.
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

from lark import Lark
from lark.exceptions import UnexpectedInput, UnexpectedToken

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.spans import FILE
from cosmos.lang.syntax import MAX_NESTING, check_nesting, syntax_error
from cosmos.lang.tree_builder import TreeBuilder


def _grammar_text() -> str:
    """The grammar, from the installed package or else from the source tree."""
    packaged = resources.files("cosmos") / "grammar" / "cosmos.lark"
    if packaged.is_file():
        return packaged.read_text(encoding="utf-8")
    return (Path(__file__).parents[2] / "grammar" / "cosmos.lark").read_text(encoding="utf-8")


class _WordsEverywhere:
    """A no-op postlexer whose ``always_accept`` makes the lexer try WORD in every state.

    A keyword is then lexed as WORD and renamed by Lark only where the parser
    expects it, so keywords end at word boundaries and may double as names.
    """

    always_accept = ("WORD",)

    def process(self, stream: Any) -> Any:
        return stream


@cache
def lark_parser() -> Lark:
    """The shared Lark parser (LALR, contextual lexer, builds AST nodes inline)."""
    return Lark(
        _grammar_text(),
        parser="lalr",
        lexer="contextual",
        keep_all_tokens=True,
        maybe_placeholders=True,
        postlex=_WordsEverywhere(),
        transformer=TreeBuilder(),
    )


@cache
def _keywords() -> dict[str, str]:
    return {
        terminal.name: terminal.pattern.value
        for terminal in lark_parser().terminals
        if terminal.pattern.type == "str" and terminal.pattern.value.isalpha()
    }


def keyword_of(terminal_name: str) -> str | None:
    """The keyword a terminal stands for (``"SPEED"``), or None for other terminals."""
    return _keywords().get(terminal_name)


def keywords() -> frozenset[str]:
    """Every keyword of the language, upper case."""
    return frozenset(word.upper() for word in _keywords().values())


def _raw_parse(text: str) -> Any:
    """Parse without error mapping (used by match_examples)."""
    return lark_parser().parse(text if text.endswith("\n") else text + "\n")


def parse_program(source: str, file: str = "<input>") -> ast.Program:
    """Parse program text into an AST.

    Args:
        source: The program text.
        file: The name spans carry (a path, or ``<repl>``).

    Raises:
        ProgramError: A syntax error, with its span and the source attached.
    """
    try:
        check_nesting(source, file)
        token = FILE.set(file)
        try:
            statements = _raw_parse(source)
        finally:
            FILE.reset(token)
    except UnexpectedInput as error:
        raise syntax_error(error, source, file, _raw_parse, keyword_of, keywords()).with_source(
            source
        ) from None
    except RecursionError:
        raise ProgramError(
            f"the program nests too deeply to parse (more than {MAX_NESTING} levels)",
            Span(file, 1, 1, 1, 2),
            source,
        ) from None
    except ProgramError as error:
        raise error.with_source(source) from None
    return ast.Program(statements, file, source)


def needs_more_input(text: str) -> bool:
    """Whether ``text`` ends inside a PROC or REPEAT block (a REPL should read on)."""
    try:
        _raw_parse(text)
    except UnexpectedToken as error:
        return error.token.type == "$END" and "END" in set(error.expected)
    except Exception:  # noqa: BLE001 - any other failure is reported by parse_program
        return False
    return False
