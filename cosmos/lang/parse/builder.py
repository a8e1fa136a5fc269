"""The tree builder: AST nodes from the children of each reduced grammar rule.

Lark calls the builder's method named for a rule or alias as the rule is
reduced, with every token kept, so a node's span runs from its first token to
its last (:mod:`cosmos.lang.parse.spans`).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable
from typing import Any

from lark import Token, Transformer, Tree

from cosmos.lang import ast
from cosmos.lang.parse.spans import span_between, span_of


def _nodes(children: Iterable[Any]) -> tuple[Any, ...]:
    """The children that are not tokens or placeholders."""
    return tuple(c for c in children if c is not None and not isinstance(c, Token))


def _ident(token: Token) -> ast.Ident:
    return ast.Ident(token.value, span_between(token, token))


_QUANTITY = re.compile(r"((?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:e[+-]?[0-9]+)?)[ \t]*(.*)", re.I | re.S)
"""A QUANTITY token: the number, then the unit as written (the terminal ends in the unit)."""
_CLAUSE_KINDS = {kind.name: kind for kind in ast.ClauseKind}
_AXES = {axis.name: axis for axis in ast.Axis}
_MOVE_MODES = {mode.name: mode for mode in ast.MoveMode}


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
        raise NotImplementedError(f"grammar rule '{data}' has no builder in cosmos/lang/parse/builder.py")

    # ------------------------------------------------------------ program

    def start(self, children: list[Any]) -> tuple[ast.Statement, ...]:
        return _nodes(children)

    # --------------------------------------------------------- statements

    # A statement or clause that starts with its keyword and ends with a node
    # (its value or last clause) spans from the one to the other.

    def move(self, children: list[Any]) -> ast.Move:
        first, last = children[0], children[-1].span  # the target or a clause
        mode, target, clauses = _MOVE_MODES[children[1].type], children[2], tuple(children[3:])
        return ast.Move(mode, target, clauses, span_between(first, last))

    def contact(self, children: list[Any]) -> ast.Contact:
        first, last = children[0], children[-1].span
        direction, clauses = children[1], tuple(children[2:])
        return ast.Contact(direction, clauses, span_between(first, last))

    def slide(self, children: list[Any]) -> ast.Slide:
        first, last = children[0], children[-1].span
        direction, clauses = children[1], tuple(children[2:])
        return ast.Slide(direction, clauses, span_between(first, last))

    def insert(self, children: list[Any]) -> ast.Insert:
        first, last = children[0], children[-1].span
        direction, clauses = children[1], tuple(children[2:])
        return ast.Insert(direction, clauses, span_between(first, last))

    def wait(self, children: list[Any]) -> ast.Wait:
        return ast.Wait(children[1], tuple(children[2:]), span_of(children))

    def speed(self, children: list[Any]) -> ast.SetSpeed:
        return ast.SetSpeed(children[1], span_of(children))

    def limit(self, children: list[Any]) -> ast.SetLimit:
        return ast.SetLimit(children[-1], span_of(children))

    def orientation(self, children: list[Any]) -> ast.SetOrientation:
        return ast.SetOrientation(children[1].type == "FREE", span_of(children))

    def posture(self, children: list[Any]) -> ast.SetPosture:
        value = children[1]
        none = isinstance(value, Token) and value.type == "NONE"
        return ast.SetPosture(None if none else value, span_of(children))

    def robot(self, children: list[Any]) -> ast.ChooseRobot:
        return ast.ChooseRobot(_ident(children[1]), span_of(children))

    def tool(self, children: list[Any]) -> ast.ChooseTool:
        return ast.ChooseTool(_ident(children[1]), span_of(children))

    def object(self, children: list[Any]) -> ast.DeclareObject:
        _, name, shape, *clauses = children
        return ast.DeclareObject(_ident(name), shape.type, tuple(clauses), span_of(children))

    def grasp(self, children: list[Any]) -> ast.Grasp:
        _, name, *clauses = children
        return ast.Grasp(
            None if name is None else _ident(name),
            tuple(clauses),
            span_of([c for c in children if c is not None]),
        )

    def release(self, children: list[Any]) -> ast.Release:
        return ast.Release(span_of(children))

    def comply(self, children: list[Any]) -> ast.Comply:
        return ast.Comply(children[1], tuple(children[2:]), span_of(children))

    def obstacle(self, children: list[Any]) -> ast.Obstacle:
        _, name, shape, *clauses = children
        return ast.Obstacle(_ident(name), ast.Shape[shape.type], tuple(clauses), span_of(children))

    def remove_obstacle(self, children: list[Any]) -> ast.RemoveObstacle:
        return ast.RemoveObstacle(_ident(children[2]), span_of(children))

    def let(self, children: list[Any]) -> ast.Let:
        first, last = children[0], children[-1].span
        name, value = _ident(children[1]), children[3]
        return ast.Let(name, value, span_between(first, last))

    def frame(self, children: list[Any]) -> ast.FrameDef:
        return ast.FrameDef(_ident(children[1]), children[3], span_of(children))

    def proc(self, children: list[Any]) -> ast.ProcDef:
        keyword, name, parameters = children[0], children[1], children[2]
        body = _nodes(children[3:-2])
        header = [keyword, name] if parameters is None else [keyword, name, parameters[-1]]
        names = () if parameters is None else parameters[0]
        return ast.ProcDef(_ident(name), names, body, _tag(children[-1]), span_of(header))

    def parameters(self, children: list[Any]) -> tuple[tuple[ast.Ident, ...], Token]:
        """The parameter names, and the closing parenthesis (the header's end)."""
        names = tuple(_ident(c) for c in children if isinstance(c, Token) and c.type == "WORD")
        return names, children[-1]

    def repeat(self, children: list[Any]) -> ast.Repeat:
        keyword, count = children[0], children[1]
        body = _nodes(children[2:-2])
        return ast.Repeat(count, body, _tag(children[-1]), span_of([keyword, count]))

    def call(self, children: list[Any]) -> ast.Call:
        arguments = children[-1]
        name = children[-2]
        if arguments is None:
            return ast.Call(_ident(name), (), span_of(children[:-1]))
        items, closing = arguments
        return ast.Call(_ident(name), items, span_of([*children[:-1], closing]))

    def arguments(self, children: list[Any]) -> tuple[tuple[ast.Expr, ...], Token]:
        """The argument expressions, and the closing parenthesis (the call's end)."""
        return _nodes(children), children[-1]

    def if_block(self, children: list[Any]) -> ast.IfBlock:
        keyword, condition = children[0], children[1]
        clauses = tuple(c for c in children[2:] if isinstance(c, ast.ValueClause))
        otherwise = children[-3]
        then_end = -3
        body = _nodes(children[2 + len(clauses) : then_end])
        else_body: tuple[ast.Statement, ...] = ()
        else_span = None
        if otherwise is not None:
            else_body, else_span = otherwise
        last = clauses[-1].span if clauses else condition.span
        return ast.IfBlock(
            condition, clauses, body, else_body, else_span, _tag(children[-1]), span_between(keyword, last)
        )

    def else_part(self, children: list[Any]) -> tuple[tuple[ast.Statement, ...], Any]:
        keyword = children[0]
        return _nodes(children[1:]), span_between(keyword, keyword)

    def while_block(self, children: list[Any]) -> ast.WhileBlock:
        keyword, condition = children[0], children[1]
        clauses = tuple(c for c in children[2:] if isinstance(c, ast.ValueClause))
        body = _nodes(children[2 + len(clauses) : -2])
        last = clauses[-1].span if clauses else condition.span
        return ast.WhileBlock(condition, clauses, body, _tag(children[-1]), span_between(keyword, last))

    def try_block(self, children: list[Any]) -> ast.TryBlock:
        keyword = children[0]
        handler, on_fail_span = children[-3]
        body = _nodes(children[1:-3])
        return ast.TryBlock(body, handler, on_fail_span, _tag(children[-1]), span_between(keyword, keyword))

    def on_fail(self, children: list[Any]) -> tuple[tuple[ast.Statement, ...], Any]:
        return _nodes(children[2:]), span_of(children[:2])

    def retry(self, children: list[Any]) -> ast.Retry:
        return ast.Retry(children[1], span_of(children))

    # ------------------------------------------------------------ clauses

    def value_clause(self, children: list[Any]) -> ast.ValueClause:
        keyword, value = children
        last = value.span
        kind = _CLAUSE_KINDS[keyword.type]
        return ast.ValueClause(kind, value, span_between(keyword, last))

    def via_clause(self, children: list[Any]) -> ast.ViaClause:
        first, last = children[0], children[-1].span
        return ast.ViaClause(_nodes(children), span_between(first, last))

    def until_clause(self, children: list[Any]) -> ast.UntilClause:
        first, last = children[0], children[-1].span
        return ast.UntilClause(children[1], span_between(first, last))

    def comply_clause(self, children: list[Any]) -> ast.ComplyClause:
        return ast.ComplyClause(children[1], span_of(children))

    def search_clause(self, children: list[Any]) -> ast.SearchClause:
        parameters = tuple(c for c in children[2:] if isinstance(c, ast.ValueClause))
        last = parameters[-1].span if parameters else children[1]
        pattern = ast.SearchPattern[children[1].type]
        return ast.SearchClause(pattern, parameters, span_between(children[0], last))

    def axes(self, children: list[Any]) -> tuple[ast.AxisRef, ...]:
        return tuple(child for child in children if isinstance(child, ast.AxisRef))

    def axis(self, children: list[Token]) -> ast.AxisRef:
        token = children[0]
        axis = _AXES[token.type]
        return ast.AxisRef(axis, span_between(token, token))

    def direction(self, children: list[Any]) -> ast.Direction:
        first, last = children[0], children[-1]
        if isinstance(last, Token):  # UP or DOWN
            sign = 1 if last.type == "UP" else -1
            return ast.Direction(ast.Axis.Z, sign, span_between(last, last))
        end = last.span
        if first is last:  # an axis without a sign
            sign, first = 1, end
        else:
            sign = -1 if first.type == "MINUS" else 1
        return ast.Direction(last.axis, sign, span_between(first, end))

    # --------------------------------------------------------- conditions

    def any_of(self, children: list[Any]) -> ast.AnyOf:
        return ast.AnyOf(_flatten(_nodes(children), ast.AnyOf), span_of(children))

    def all_of(self, children: list[Any]) -> ast.AllOf:
        return ast.AllOf(_flatten(_nodes(children), ast.AllOf), span_of(children))

    def conjunction(self, children: list[Any]) -> ast.Condition:
        """A parenthesised condition: ``( condition )``, its span taking in the parentheses."""
        return dataclasses.replace(children[1], span=span_of(children))

    def comparison(self, children: list[Any]) -> ast.Comparison:
        (first, sensed, direction), op, value = children
        last = value.span
        return ast.Comparison(sensed, direction, op.value, value, span_between(first, last))

    def sensed(self, children: list[Any]) -> tuple[Token, ast.Sensed, ast.Direction | None]:
        if children[0].type == "FINGER":  # FINGER FORCE: the grip the pads feel, no axis
            return children[0], ast.Sensed.FINGER, None
        direction = children[1] if len(children) > 1 else None
        if isinstance(direction, ast.AxisRef):  # POSITION X: the coordinate along +X
            direction = ast.Direction(direction.axis, 1, direction.span)
        return children[0], ast.Sensed[children[0].type], direction

    def last_outcome(self, children: list[Token]) -> ast.LastOutcome:
        return ast.LastOutcome(ast.LastKind[children[1].type], span_of(children))

    # -------------------------------------------------------- expressions

    def pose(self, children: list[Any]) -> ast.Expr:
        position, rpy = children[0], children[-1]
        if rpy is None:
            return position
        first, last = position.span, rpy.span
        return ast.Pose(position, rpy, span_between(first, last))

    def add(self, children: list[Any]) -> ast.Binary:
        return _binary("+", children)

    def subtract(self, children: list[Any]) -> ast.Binary:
        return _binary("-", children)

    def multiply(self, children: list[Any]) -> ast.Binary:
        return _binary("*", children)

    def negate(self, children: list[Any]) -> ast.Unary:
        return _unary("-", children)

    def plus(self, children: list[Any]) -> ast.Unary:
        return _unary("+", children)

    def unary(self, children: list[Any]) -> ast.Expr:
        """A parenthesised expression: ``( expr )``."""
        return children[1]

    def vector(self, children: list[Any]) -> ast.Vector:
        first, last = children[0], children[-1]
        items = tuple(children[1:-1:2])
        return ast.Vector(items, span_between(first, last))

    def quantity(self, children: list[Token]) -> ast.Number:
        token = children[0]
        number, unit = _quantity_parts(token.value)
        return ast.Number(number, unit, span_between(token, token))

    def name(self, children: list[Token]) -> ast.Name:
        token = children[0]
        return ast.Name(token.value, span_between(token, token))


def _binary(op: str, children: list[Any]) -> ast.Binary:
    left, _, right = children
    first, last = left.span, right.span
    return ast.Binary(op, left, right, span_between(first, last))


def _unary(op: str, children: list[Any]) -> ast.Unary:
    first, last = children[0], children[1].span
    return ast.Unary(op, children[1], span_between(first, last))


def _tag(token: Token | None) -> str | None:
    return None if token is None else token.type


def _flatten(children: Iterable[Any], kind: type[ast.AnyOf] | type[ast.AllOf]) -> tuple[Any, ...]:
    items: list[Any] = []
    for child in children:
        items.extend(child.items if isinstance(child, kind) else (child,))
    return tuple(items)


TreeBuilder = _Builder
"""Builds AST nodes as rules are reduced (a Lark ``Transformer``; one method per rule)."""
