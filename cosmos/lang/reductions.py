"""How the value of each grammar rule is built from its popped values, as Lark builds it.

Lark's tree builder (``keep_all_tokens``, ``maybe_placeholders``) splices the
children that are ``_rule`` values (lists here) into their parent, puts None
where an absent ``[x]`` would be, passes the one child of a ``?rule`` through,
makes a ``_rule`` the list of its children, and calls the builder's method of
any other rule's alias or name. Each rule gets a function that does exactly
that (:func:`reduction`), and a :class:`Recipe` saying the same in terms that
generated code can spell out (:mod:`cosmos.lang.replay_code`).
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple

from lark.grammar import Rule

Reduce = Callable[[list[Any]], Any]


class Form(enum.Enum):
    """How a rule's value is made from its children."""

    LIST = "the list of the children (a _rule)"
    EXTEND = "the first child, a list, extended in place by the others (a _rule: x*, x+)"
    CALL = "the builder's method, on the children laid out as the recipe's pieces say"
    ONE_OR_CALL = "as CALL, but the laid-out item itself if there is just one (a ?rule)"
    OTHER = "only the rule's reduce function says"


class Piece(NamedTuple):
    """One item of the list a builder's method gets: a child, spliced or not, or None."""

    child: int | None
    """The child's index among the popped values; None for a placeholder."""
    splice: bool
    """Whether the child is a _rule's list whose items go in (else the child itself)."""


@dataclass(frozen=True)
class Recipe:
    """How a rule's value is made, for code that spells it out.

    Attributes:
        form: What is made.
        method: The builder's method (``CALL``, ``ONE_OR_CALL``; None otherwise).
        pieces: For ``CALL`` and ``ONE_OR_CALL``, the method's list, item by item; for ``EXTEND``,
            what extends the first child, in order (children 1, 2, ...).
    """

    form: Form
    method: Reduce | None
    pieces: tuple[Piece, ...]


def reduction(rule: Rule, builder: Any) -> tuple[Reduce | None, Recipe | None]:
    """The reduction of ``rule`` as Lark's tree builder does it, and its recipe.

    Both are None for a ``?rule`` of one symbol (the value passes through).
    """
    expansion = rule.expansion
    size = len(expansion)
    empty = rule.options.empty_indices
    if empty:
        runs = "".join(str(int(flag)) for flag in empty).split("0")
        nones = [len(run) for run in runs]
    else:
        nones = [0] * (size + 1)
    include = [
        (index, not symbol.is_term and symbol.name.startswith("_"), nones[index])
        for index, symbol in enumerate(expansion)
    ]
    trailing = nones[size]
    plain = trailing == 0 and not any(expand or before for _, expand, before in include)
    expand_one = rule.options.expand1 and not rule.alias
    name = rule.alias or rule.options.template_source or rule.origin.name
    inline = name.startswith("_")
    if plain and expand_one and size == 1:
        return None, None
    found = getattr(builder, name, None)

    def missing(children: list[Any]) -> Any:
        raise NotImplementedError(f"grammar rule '{name}' has no builder in cosmos/lang/tree_builder.py")

    method: Reduce = missing if found is None else found
    pieces: list[Piece] = []
    for index, expand, before in include:
        pieces += [Piece(None, False)] * before
        pieces.append(Piece(index, expand))
    pieces += [Piece(None, False)] * trailing

    def shape(children: list[Any]) -> list[Any]:
        if plain:
            return children
        filtered: list[Any] = []
        for index, expand, before in include:
            if before:
                filtered += [None] * before
            if expand:
                if filtered:
                    filtered += children[index]
                else:  # left recursion (x*, x+): extend the list in place, as Lark does
                    filtered = children[index]
            else:
                filtered.append(children[index])
        if trailing:
            filtered += [None] * trailing
        return filtered

    other = Recipe(Form.OTHER, None, ())
    if inline:
        if plain:
            return list, Recipe(Form.LIST, None, ())  # a copy of the popped values, made in C
        if trailing == 0 and include[0][1] and not any(before for _, _, before in include):
            return _extender([expand for _, expand, _ in include[1:]]), Recipe(
                Form.EXTEND, None, tuple(pieces[1:])
            )
        return shape, other
    if expand_one:

        def reduce_one(children: list[Any]) -> Any:
            filtered = shape(children)
            return filtered[0] if len(filtered) == 1 else method(filtered)

        return reduce_one, Recipe(Form.ONE_OR_CALL, method, tuple(pieces))
    recipe = Recipe(Form.CALL, method, tuple(pieces))
    if plain:
        return method, recipe
    expanded = [index for index, expand, _ in include if expand]
    if not any(before for _, _, before in include):
        if not expanded:  # only placeholders at the end: [x] last
            padding = [None] * trailing
            return lambda children: method(children + padding), recipe
        if len(expanded) == 1 and not trailing:  # one _rule spliced in
            at = expanded[0]
            return lambda children: method(children[:at] + children[at] + children[at + 1 :]), recipe
    return lambda children: method(shape(children)), recipe


def _extender(expands: list[bool]) -> Reduce:
    """The reduction of a ``_rule`` whose first symbol is a ``_rule`` (``x*``, ``x+``, a list).

    Its list grows in place, as Lark's does, so a long list is never copied.
    """
    if expands == [True]:

        def extend_one(children: list[Any]) -> Any:
            items = children[0]
            items += children[1]
            return items

        return extend_one
    if not any(expands):

        def append_rest(children: list[Any]) -> Any:
            items = children[0]
            items += children[1:]
            return items

        return append_rest

    def extend(children: list[Any]) -> Any:
        items = children[0]
        for child, expand in zip(children[1:], expands, strict=True):
            if expand:
                items += child
            else:
                items.append(child)
        return items

    return extend
