"""Source text to syntax tree: the Lark parser and the tree builder.

The grammar is ``grammar/cosmos.lark`` (shipped inside the wheel as
``cosmos/grammar/cosmos.lark``). Lark runs LALR with the contextual lexer and
calls the builder below as each rule is reduced (an inline transformer), so no
parse tree is kept and nesting costs no recursion. Every token is kept, and a
node's span runs from its first token to its last.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from functools import cache, lru_cache
from importlib import resources
from pathlib import Path
from typing import Any

from lark import Lark, Token, Transformer, Tree
from lark.exceptions import UnexpectedInput, UnexpectedToken
from lark.lexer import PatternStr

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.fastparse import GiveUp, Tok, parse
from cosmos.lang.frozen_new import quick
from cosmos.lang.gc_pause import gc_paused
from cosmos.lang.lalr_tables import Tables, build_tables
from cosmos.lang.spans import FILE, TOKENS, between, new_span, span_of
from cosmos.lang.syntax import MAX_NESTING, check_nesting, syntax_error


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


def _nodes(children: Iterable[Any]) -> tuple[Any, ...]:
    """The children that are not tokens or placeholders."""
    return tuple(c for c in children if c is not None and not isinstance(c, TOKENS))


def _ident(token: Token | Tok) -> ast.Ident:
    return _Ident(token.value, new_span(_file(), token.line, token.column, token.end_line, token.end_column))


_QUANTITY = re.compile(r"((?:\d+\.?\d*|\.\d+)(?:e[+-]?\d+)?)[ \t]*(.*)", re.I | re.S)
"""A QUANTITY token: the number, then the unit as written (the terminal ends in the unit)."""
_CLAUSE_KINDS = {kind.name: kind for kind in ast.ClauseKind}
_AXES = {axis.name: axis for axis in ast.Axis}
_MOVE_MODES = {mode.name: mode for mode in ast.MoveMode}

_file = FILE.get
# The nodes made most often, made quickly (cosmos/lang/frozen_new.py).
_Number = quick(ast.Number)
_Name = quick(ast.Name)
_Vector = quick(ast.Vector)
_Binary = quick(ast.Binary)
_Unary = quick(ast.Unary)
_Pose = quick(ast.Pose)
_ValueClause = quick(ast.ValueClause)
_ViaClause = quick(ast.ViaClause)
_UntilClause = quick(ast.UntilClause)
_AxisRef = quick(ast.AxisRef)
_Direction = quick(ast.Direction)
_Comparison = quick(ast.Comparison)
_Move = quick(ast.Move)
_Contact = quick(ast.Contact)
_Slide = quick(ast.Slide)
_Insert = quick(ast.Insert)
_Let = quick(ast.Let)
_Ident = quick(ast.Ident)


@lru_cache(maxsize=4096)
def _quantity_parts(text: str) -> tuple[float, str | None]:
    """The number and the unit as written (None for a bare number) of a QUANTITY's text."""
    if not text[-1].isalpha():  # a bare number (a unit ends in a letter)
        return float(text), None
    match = _QUANTITY.fullmatch(text)
    assert match is not None  # the QUANTITY terminal has this shape
    number, unit = match.groups()
    return float(number), unit or None


class _Builder(Transformer):
    """Builds AST nodes as rules are reduced; children hold every token.

    Every grammar rule that reaches the builder has a method here;
    ``__default__`` raises, so a rule added to the grammar without a builder
    fails loudly (tests/lang/test_lang_parser.py also checks the two agree).
    """

    def __default__(self, data: Any, children: Any, meta: Any) -> Any:
        if str(data).startswith("_"):  # an inlined rule: its parent splices the children in
            return Tree(data, children)
        raise NotImplementedError(f"grammar rule '{data}' has no builder in cosmos/lang/parser.py")

    # ------------------------------------------------------------ program

    def start(self, children: list[Any]) -> tuple[ast.Statement, ...]:
        return _nodes(children)

    # --------------------------------------------------------- statements

    def move(self, children: list[Any]) -> ast.Move:
        first = children[0]
        last = children[-1].span  # the target or a clause
        span = new_span(_file(), first.line, first.column, last.end_line, last.end_column)
        return _Move(_MOVE_MODES[children[1].type], children[2], tuple(children[3:]), span)

    def contact(self, children: list[Any]) -> ast.Contact:
        return _Contact(children[1], tuple(children[2:]), _keyword_to_node(children))

    def slide(self, children: list[Any]) -> ast.Slide:
        return _Slide(children[1], tuple(children[2:]), _keyword_to_node(children))

    def insert(self, children: list[Any]) -> ast.Insert:
        return _Insert(children[1], tuple(children[2:]), _keyword_to_node(children))

    def wait(self, children: list[Any]) -> ast.Wait:
        return ast.Wait(children[1], tuple(children[2:]), span_of(children))

    def speed(self, children: list[Any]) -> ast.SetSpeed:
        return ast.SetSpeed(children[1], span_of(children))

    def comply(self, children: list[Any]) -> ast.Comply:
        return ast.Comply(children[1], tuple(children[2:]), span_of(children))

    def obstacle(self, children: list[Any]) -> ast.Obstacle:
        _, name, shape, *clauses = children
        return ast.Obstacle(_ident(name), ast.Shape[shape.type], tuple(clauses), span_of(children))

    def remove_obstacle(self, children: list[Any]) -> ast.RemoveObstacle:
        return ast.RemoveObstacle(_ident(children[2]), span_of(children))

    def let(self, children: list[Any]) -> ast.Let:
        return _Let(_ident(children[1]), children[3], _keyword_to_node(children))

    def frame(self, children: list[Any]) -> ast.FrameDef:
        return ast.FrameDef(_ident(children[1]), children[3], span_of(children))

    def proc(self, children: list[Any]) -> ast.ProcDef:
        keyword, name = children[0], children[1]
        body = _nodes(children[2:-2])
        return ast.ProcDef(_ident(name), body, _tag(children[-1]), span_of([keyword, name]))

    def repeat(self, children: list[Any]) -> ast.Repeat:
        keyword, count = children[0], children[1]
        body = _nodes(children[2:-2])
        return ast.Repeat(count, body, _tag(children[-1]), span_of([keyword, count]))

    def call(self, children: list[Any]) -> ast.Call:
        return ast.Call(_ident(children[-1]), span_of(children))

    # ------------------------------------------------------------ clauses

    def value_clause(self, children: list[Any]) -> ast.ValueClause:
        keyword, value = children
        last = value.span
        span = new_span(_file(), keyword.line, keyword.column, last.end_line, last.end_column)
        return _ValueClause(_CLAUSE_KINDS[keyword.type], value, span)

    def via_clause(self, children: list[Any]) -> ast.ViaClause:
        return _ViaClause(_nodes(children), _keyword_to_node(children))

    def until_clause(self, children: list[Any]) -> ast.UntilClause:
        return _UntilClause(children[1], _keyword_to_node(children))

    def comply_clause(self, children: list[Any]) -> ast.ComplyClause:
        return ast.ComplyClause(children[1], span_of(children))

    def axes(self, children: list[Any]) -> tuple[ast.AxisRef, ...]:
        return tuple(child for child in children if isinstance(child, ast.AxisRef))

    def axis(self, children: list[Token]) -> ast.AxisRef:
        token = children[0]
        span = new_span(_file(), token.line, token.column, token.end_line, token.end_column)
        return _AxisRef(_AXES[token.type], span)

    def direction(self, children: list[Any]) -> ast.Direction:
        last = children[-1]
        if isinstance(last, TOKENS):  # UP or DOWN
            return _Direction(ast.Axis.Z, 1 if last.type == "UP" else -1, span_of(children))
        sign = -1 if isinstance(children[0], TOKENS) and children[0].type == "MINUS" else 1
        return _Direction(last.axis, sign, span_of(children))

    # --------------------------------------------------------- conditions

    def any_of(self, children: list[Any]) -> ast.AnyOf:
        return ast.AnyOf(_flatten(_nodes(children), ast.AnyOf), span_of(children))

    def all_of(self, children: list[Any]) -> ast.AllOf:
        return ast.AllOf(_flatten(_nodes(children), ast.AllOf), span_of(children))

    def conjunction(self, children: list[Any]) -> ast.Condition:
        """A parenthesised condition: ``( condition )``."""
        return children[1]

    def comparison(self, children: list[Any]) -> ast.Comparison:
        (first, sensed, direction), op, value = children
        last = value.span
        span = new_span(_file(), first.line, first.column, last.end_line, last.end_column)
        return _Comparison(sensed, direction, op.value, value, span)

    def sensed(self, children: list[Any]) -> tuple[Token, ast.Sensed, ast.Direction | None]:
        direction = children[1] if len(children) > 1 else None
        return children[0], ast.Sensed[children[0].type], direction

    # -------------------------------------------------------- expressions

    def pose(self, children: list[Any]) -> ast.Expr:
        position, rpy = children[0], children[-1]
        return position if rpy is None else _Pose(position, rpy, between(position.span, rpy.span))

    def add(self, children: list[Any]) -> ast.Binary:
        left, _, right = children
        return _Binary("+", left, right, between(left.span, right.span))

    def subtract(self, children: list[Any]) -> ast.Binary:
        left, _, right = children
        return _Binary("-", left, right, between(left.span, right.span))

    def multiply(self, children: list[Any]) -> ast.Binary:
        left, _, right = children
        return _Binary("*", left, right, between(left.span, right.span))

    def negate(self, children: list[Any]) -> ast.Unary:
        return _Unary("-", children[1], _keyword_to_node(children))

    def plus(self, children: list[Any]) -> ast.Unary:
        return _Unary("+", children[1], _keyword_to_node(children))

    def unary(self, children: list[Any]) -> ast.Expr:
        """A parenthesised expression: ``( expr )``."""
        return children[1]

    def vector(self, children: list[Any]) -> ast.Vector:
        first, last = children[0], children[-1]
        span = new_span(_file(), first.line, first.column, last.end_line, last.end_column)
        return _Vector(tuple(children[1:-1:2]), span)

    def quantity(self, children: list[Token]) -> ast.Number:
        token = children[0]
        number, unit = _quantity_parts(token.value)
        span = new_span(_file(), token.line, token.column, token.end_line, token.end_column)
        return _Number(number, unit, span)

    def name(self, children: list[Token]) -> ast.Name:
        token = children[0]
        span = new_span(_file(), token.line, token.column, token.end_line, token.end_column)
        return _Name(token.value, span)


def _keyword_to_node(children: list[Any]) -> Span:
    """The span of children that start with a token and end with a node."""
    first = children[0]
    last = children[-1].span
    return new_span(_file(), first.line, first.column, last.end_line, last.end_column)


def _tag(token: Token | Tok | None) -> str | None:
    return None if token is None else token.type


def _flatten(children: Iterable[Any], kind: type[ast.AnyOf] | type[ast.AllOf]) -> tuple[Any, ...]:
    items: list[Any] = []
    for child in children:
        items.extend(child.items if isinstance(child, kind) else (child,))
    return tuple(items)


@cache
def lark_parser() -> Lark:
    """The shared Lark parser (LALR, contextual lexer, builds AST nodes inline)."""
    return Lark(
        _grammar_text(),
        parser="lalr",
        lexer="contextual",
        keep_all_tokens=True,
        maybe_placeholders=True,
        cache=True,
        postlex=_WordsEverywhere(),
        transformer=_Builder(),
    )


@cache
def _keywords() -> dict[str, str]:
    parser = lark_parser()
    return {
        terminal.name: terminal.pattern.value
        for terminal in parser.terminals
        if isinstance(terminal.pattern, PatternStr) and terminal.pattern.value.isalpha()
    }


def keyword_of(terminal_name: str) -> str | None:
    """The keyword a terminal stands for (``"SPEED"``), or None for other terminals."""
    return _keywords().get(terminal_name)


def keywords() -> frozenset[str]:
    """Every keyword of the language, upper case."""
    return frozenset(word.upper() for word in _keywords().values())


@cache
def _tables() -> Tables:
    return build_tables(lark_parser(), _Builder())


def _fast_parse(text: str) -> Any:
    """What :func:`_raw_parse` gives, faster; None where Lark is to decide (errors)."""
    try:
        return parse(text if text.endswith("\n") else text + "\n", _tables())
    except GiveUp:
        return None


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
            with gc_paused():
                statements = _fast_parse(source)
            if statements is None:  # not accepted as is: Lark parses it and says why
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
