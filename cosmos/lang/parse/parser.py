"""Source text to syntax tree: :func:`parse_program`, with errors in words a person knows.

The parser is Lark's (:mod:`cosmos.lang.parse.grammar`); block and parenthesis
nesting is bounded before it runs (:mod:`cosmos.lang.parse.nesting`), and its
errors become messages in :mod:`cosmos.lang.parse.syntax_errors`.
"""

from __future__ import annotations

from typing import Any

from lark.exceptions import UnexpectedInput, UnexpectedToken

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.parse.grammar import keyword_of, keywords, lark_parser
from cosmos.lang.parse.nesting import MAX_NESTING, check_block_nesting, check_nesting
from cosmos.lang.parse.spans import FILE
from cosmos.lang.parse.syntax_errors import syntax_error


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
        check_block_nesting(source, file)
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
    """Whether ``text`` ends inside a block (PROC, REPEAT, IF, WHILE, TRY): a REPL should read on.

    The parser then wants an END, or a TRY's ON FAIL, where the text ended.
    """
    try:
        _raw_parse(text)
    except UnexpectedToken as error:
        return error.token.type == "$END" and not {"END", "ON"}.isdisjoint(error.expected)
    except Exception:  # noqa: BLE001 - any other failure is reported by parse_program
        return False
    return False
