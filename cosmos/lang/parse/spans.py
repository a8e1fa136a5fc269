"""Spans of syntax-tree nodes: from the first placed child to the last one.

A node's span starts where its first child that has a place in the text starts
(a token, or a node's span) and ends where its last one ends; line breaks and
placeholders have none. Only the two ends are looked at, so a span costs the
same however large the node.
"""

from __future__ import annotations

import contextvars
from collections.abc import Sequence
from typing import Any

from lark import Token

from cosmos.errors import Span

FILE: contextvars.ContextVar[str] = contextvars.ContextVar("cosmos_source_file", default="<input>")
"""The name the spans being built carry (set around each parse)."""


def span_between(first: Any, last: Any) -> Span:
    """The span from where ``first`` starts to where ``last`` ends (tokens or spans)."""
    return Span(FILE.get(), first.line, first.column, last.end_line, last.end_column)


def _place(item: Any) -> Any:
    """What holds the item's line, column, end_line and end_column, or None.

    A token is its own place (a line break has none), a node's is its span, a
    sequence's runs from its first placed item to its last one.
    """
    if isinstance(item, Token):
        return None if item.type == "_NL" or item.line is None else item
    if item is None:
        return None
    span = getattr(item, "span", None)
    if span is not None:
        return span
    if isinstance(item, tuple | list):
        first, last = _ends(item)
        if first is not None:
            return span_between(first, last)
    return None


def _ends(items: Sequence[Any]) -> tuple[Any, Any]:
    """The places of the first and the last placed items (None, None if none is)."""
    for item in items:
        first = _place(item)
        if first is not None:
            break
    else:
        return None, None
    for item in reversed(items):
        last = _place(item)
        if last is not None:
            return first, last
    return first, first  # not reached: the first placed item is also found from the end


def span_of(children: Sequence[Any]) -> Span:
    """The span from the first to the last placed child.

    Only the ends are looked at (a child's span already covers its own children).
    """
    first, last = _ends(children)
    if first is None:
        return Span(FILE.get(), 1, 1, 1, 1)
    return span_between(first, last)
