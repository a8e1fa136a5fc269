"""A statement's trace turned into straight-line Python code that redoes it.

A benchmark program repeats a few statement shapes thousands of times, and
each repeat performs the same reductions with the same children (see
:mod:`cosmos.lang.lalr_run`). Interpreting the trace step by step costs a loop
iteration, a list slice and a stack deletion per reduction; here each trace
becomes one Python function (compiled with :func:`exec`) in which every value
is a local variable and every reduction one line, e.g. for ``WAIT 1 s``::

    def replay(t, values):
        below1, below0 = values[-2:]
        del values[-2:]
        t[0].type = 'WAIT'
        below1 += [below0]
        ...
        v2 = m2([t[0], v1])
        values += [v2, t[2]]

The generated text holds only numbers, terminal names and names of its own
(the reductions are passed in as globals): nothing from the program's text.
Which children a reduction gets, and in which order, is exactly what the trace
recorded; :class:`~cosmos.lang.reductions.Recipe` says how each rule's value is
made from them, so the builder's method is called with the very list the
rule's reduce function would make.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from cosmos.lang.lalr_run import Tok, Trace
from cosmos.lang.lalr_tables import _Rule
from cosmos.lang.reductions import Form, Piece

Replay = Callable[[list[Tok], list[Any]], None]
"""Does to the value stack what the traced run did, with a statement's tokens."""


def replay_function(trace: Trace, rules: Sequence[_Rule]) -> Replay:
    """The function that performs ``trace``'s renames and reductions on other tokens.

    Args:
        trace: What a run did with a statement's tokens.
        rules: The table's rules (:attr:`~cosmos.lang.lalr_tables.Tables.rules`).
    """
    code = _Code()
    body = [f"t[{index}].type = {keyword!r}" for index, keyword in trace.renames]
    stack: list[_Value] = []  # the statement's values, bottom to top
    taken = 0  # values taken from below the statement's own (its first reductions end the one before)
    shifted = 0
    for start, stop, size, rule in trace.steps:
        stack += [f"t[{index}]" for index in range(start, stop)]
        shifted = stop
        if size > len(stack):
            more = size - len(stack)
            stack[:0] = [f"below{taken + deeper}" for deeper in reversed(range(more))]
            taken += more
        children = stack[len(stack) - size :]
        del stack[len(stack) - size :]
        stack.append(code.reduce(rules[rule], children, body))
    stack += [f"t[{index}]" for index in range(shifted, trace.count)]
    if taken:
        head = [f"{', '.join(f'below{k}' for k in reversed(range(taken)))}, = values[-{taken}:]"]
        body[:0] = [*head, f"del values[-{taken}:]"]
    if stack:
        body.append(f"values += [{', '.join(map(_spelt, stack))}]")
    source = "def replay(t, values):\n" + "".join(f"    {line}\n" for line in body or ["pass"])
    exec(compile(source, "<replay of a statement shape>", "exec"), code.names)  # noqa: S102 - our own text
    replay: Replay = code.names["replay"]
    return replay


_Value = str | list[str]
"""A value on the stack as code: an expression, or a list not made yet (its items'
expressions). Each value is popped once, by one reduction, so a list that is
only spliced into others need never be made."""


def _spelt(value: _Value) -> str:
    return value if isinstance(value, str) else f"[{', '.join(value)}]"


class _Code:
    """The reductions' code, and the functions it calls by name."""

    def __init__(self) -> None:
        self.names: dict[str, Any] = {}
        self.made = 0

    def _name(self, prefix: str, function: Any) -> str:
        name = f"{prefix}{len(self.names)}"
        self.names[name] = function
        return name

    def _assign(self, expression: str, body: list[str]) -> str:
        """A new variable, set to ``expression`` in ``body``."""
        made = f"v{self.made}"
        self.made += 1
        body.append(f"{made} = {expression}")
        return made

    def reduce(self, rule: _Rule, children: list[_Value], body: list[str]) -> _Value:
        """The value of reducing ``children`` by ``rule``; its code goes into ``body``."""
        _, _, reduce, recipe = rule
        assert reduce is not None and recipe is not None  # pass-through rules make no step
        form = recipe.form
        if form is Form.LIST:
            return [_spelt(child) for child in children]
        if form is Form.EXTEND:
            rest: list[_Value] = []
            for child, splice in recipe.pieces:
                assert child is not None  # an x* or x+ list has no placeholders
                rest.append(children[child] if splice else [_spelt(children[child])])
            return self._extend(children[0], rest, body)
        if form is not Form.OTHER:
            items, sized = _laid_out(recipe.pieces, children)
            if form is Form.ONE_OR_CALL and sized and len(items) == 1:
                return items[0]
            if form is Form.CALL or sized:  # ONE_OR_CALL with more than one item: the method
                return self._assign(f"{self._name('m', recipe.method)}([{', '.join(items)}])", body)
        return self._assign(f"{self._name('r', reduce)}([{', '.join(map(_spelt, children))}])", body)

    def _extend(self, first: _Value, rest: list[_Value], body: list[str]) -> _Value:
        """``first`` (a list) extended by the items of each of ``rest`` (lists: x*, x+)."""
        if isinstance(first, list) and all(isinstance(more, list) for more in rest):
            return first + [item for more in rest for item in more]
        if isinstance(first, list):
            first = self._assign(_spelt(first), body)
        body += [f"{first} += {_spelt(more)}" for more in rest]
        return first


def _laid_out(pieces: tuple[Piece, ...], children: list[_Value]) -> tuple[list[str], bool]:
    """The items of a builder method's list (children, lists spliced in, None).

    A list not made yet gives its items, one that was made ``*name``; the flag
    says whether the number of items is known (no ``*name``).
    """
    items: list[str] = []
    sized = True
    for child_index, splice in pieces:
        if child_index is None:
            items.append("None")
            continue
        child = children[child_index]
        if not splice:
            items.append(_spelt(child))
        elif isinstance(child, list):
            items += child
        else:
            items.append(f"*{child}")
            sized = False
    return items, sized
