"""The tree builder: AST nodes from the children of each reduced grammar rule.

Lark (and the fast parser, :mod:`cosmos.lang.fastparse`) call the builder's
method named for a rule or alias as the rule is reduced, with every token kept,
so a node's span runs from its first token to its last
(:mod:`cosmos.lang.spans`). The nodes and spans made most often are made
without their frozen ``__init__`` (:mod:`cosmos.lang.frozen_new`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from functools import lru_cache
from typing import Any

from lark import Token, Transformer, Tree

from cosmos.errors import Span
from cosmos.lang import ast
from cosmos.lang.fastparse import Tok
from cosmos.lang.frozen_new import quick
from cosmos.lang.spans import FILE, TOKENS, between, new_span, span_of


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
        raise NotImplementedError(f"grammar rule '{data}' has no builder in cosmos/lang/tree_builder.py")

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


TreeBuilder = _Builder
"""Builds AST nodes as rules are reduced (a Lark ``Transformer``; one method per rule)."""
