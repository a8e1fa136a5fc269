"""Frozen dataclass instances made without their ``__init__``, a third of the time.

A frozen dataclass sets each field through ``object.__setattr__``; the parser
makes a node and a span for every few characters of a program, so this fills the
new instance's dictionary directly instead. A class gets the quick maker only if
that builds an instance equal, field for field, to what its ``__init__`` builds
(checked once, on a probe); otherwise it keeps its own constructor.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, TypeVar

T = TypeVar("T")

_new = object.__new__


def _maker(cls: type[T], names: tuple[str, ...]) -> Callable[..., T] | None:
    """A function of the fields in order that fills a new instance's dictionary."""
    if len(names) == 2:
        a, b = names

        def make2(x: Any, y: Any) -> T:
            made = _new(cls)
            fields = made.__dict__
            fields[a] = x
            fields[b] = y
            return made

        return make2
    if len(names) == 3:
        a, b, c = names

        def make3(x: Any, y: Any, z: Any) -> T:
            made = _new(cls)
            fields = made.__dict__
            fields[a] = x
            fields[b] = y
            fields[c] = z
            return made

        return make3
    if len(names) == 4:
        a, b, c, d = names

        def make4(x: Any, y: Any, z: Any, w: Any) -> T:
            made = _new(cls)
            fields = made.__dict__
            fields[a] = x
            fields[b] = y
            fields[c] = z
            fields[d] = w
            return made

        return make4
    if len(names) == 5:
        a, b, c, d, e = names

        def make5(x: Any, y: Any, z: Any, w: Any, v: Any) -> T:
            made = _new(cls)
            fields = made.__dict__
            fields[a] = x
            fields[b] = y
            fields[c] = z
            fields[d] = w
            fields[e] = v
            return made

        return make5
    return None


def quick(cls: type[T]) -> Callable[..., T]:
    """A constructor of ``cls`` taking its fields in order, positionally.

    The quick one where ``cls`` is a plain frozen dataclass (no ``__post_init__``,
    no slots, every field set by ``__init__`` and none with a default) of two to
    five fields and the quick one gives the same instance; else ``cls`` itself.
    """
    if not dataclasses.is_dataclass(cls) or hasattr(cls, "__post_init__") or hasattr(cls, "__slots__"):
        return cls
    fields = dataclasses.fields(cls)
    if any(
        not f.init or f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING
        for f in fields
    ):
        return cls
    names = tuple(f.name for f in fields)
    maker = _maker(cls, names)
    if maker is None:
        return cls
    probe = [object() for _ in names]
    try:
        quick_one, slow_one = maker(*probe), cls(*probe)
    except (TypeError, ValueError, AttributeError):
        return cls
    same = type(quick_one) is type(slow_one) and vars(quick_one) == vars(slow_one)
    if not same or list(vars(quick_one)) != list(vars(slow_one)):
        return cls
    return maker


def spanned(cls: type[T], span_cls: type[Any]) -> Callable[..., T]:
    """A constructor of a node and its span in one call.

    It takes the fields of ``cls`` but the last, then the five fields of that
    last one (a ``span_cls``). Both are made as :func:`quick` makes them where that builds instances equal,
    field for field, to ``cls(*fields, span_cls(*span_fields))`` (checked on a
    probe); otherwise by those two calls.
    """

    def slow(*values: Any) -> T:
        return cls(*values[:-5], span_cls(*values[-5:]))  # type: ignore[call-arg]

    if quick(cls) is cls or quick(span_cls) is span_cls:
        return slow
    names = [f.name for f in dataclasses.fields(cls)]  # type: ignore[arg-type]
    span_names = [f.name for f in dataclasses.fields(span_cls)]
    if len(span_names) != 5:
        return slow
    maker = _spanned_maker(cls, names, span_cls, span_names)
    if maker is None:
        return slow
    probe = [object() for _ in range(len(names) + 4)]
    made, reference = maker(*probe), slow(*probe)
    same = vars(made) == vars(reference) and type(made) is type(reference)
    if not same or vars(getattr(made, names[-1])) != vars(getattr(reference, names[-1])):
        return slow
    return maker


def _spanned_maker(
    cls: type[T], names: list[str], span_cls: type[Any], span_names: list[str]
) -> Callable[..., T] | None:
    """The maker :func:`spanned` describes, for a node of two to five fields (span last).

    Written out per number of fields: one call per node is the point.
    """
    *fields, last = names
    f, ln, c, el, ec = span_names
    if len(fields) == 1:
        (a,) = fields

        def make1(x: Any, file: Any, line: Any, column: Any, end_line: Any, end_column: Any) -> T:
            span = _new(span_cls)
            values = span.__dict__
            values[f] = file
            values[ln] = line
            values[c] = column
            values[el] = end_line
            values[ec] = end_column
            made = _new(cls)
            values = made.__dict__
            values[a] = x
            values[last] = span
            return made

        return make1
    if len(fields) == 2:
        a, b = fields

        def make2(x: Any, y: Any, file: Any, line: Any, column: Any, end_line: Any, end_column: Any) -> T:
            span = _new(span_cls)
            values = span.__dict__
            values[f] = file
            values[ln] = line
            values[c] = column
            values[el] = end_line
            values[ec] = end_column
            made = _new(cls)
            values = made.__dict__
            values[a] = x
            values[b] = y
            values[last] = span
            return made

        return make2
    if len(fields) == 3:
        a, b, d = fields

        def make3(
            x: Any, y: Any, z: Any, file: Any, line: Any, column: Any, end_line: Any, end_column: Any
        ) -> T:
            span = _new(span_cls)
            values = span.__dict__
            values[f] = file
            values[ln] = line
            values[c] = column
            values[el] = end_line
            values[ec] = end_column
            made = _new(cls)
            values = made.__dict__
            values[a] = x
            values[b] = y
            values[d] = z
            values[last] = span
            return made

        return make3
    if len(fields) == 4:
        a, b, d, e = fields

        def make4(
            x: Any, y: Any, z: Any, w: Any, file: Any, line: Any, column: Any, end_line: Any, end_column: Any
        ) -> T:
            span = _new(span_cls)
            values = span.__dict__
            values[f] = file
            values[ln] = line
            values[c] = column
            values[el] = end_line
            values[ec] = end_column
            made = _new(cls)
            values = made.__dict__
            values[a] = x
            values[b] = y
            values[d] = z
            values[e] = w
            values[last] = span
            return made

        return make4
    return None


def quick_keywords(cls: type[T]) -> Callable[..., T]:
    """A constructor of ``cls`` taking every field by keyword (no defaults used).

    The quick one where ``cls`` is a plain frozen dataclass (as for :func:`quick`)
    and gives the same instance; it passes any other set of keywords to ``cls``.
    """
    if not dataclasses.is_dataclass(cls) or hasattr(cls, "__post_init__") or hasattr(cls, "__slots__"):
        return cls
    fields = dataclasses.fields(cls)
    if any(not f.init for f in fields):
        return cls
    names = frozenset(f.name for f in fields)

    def make(**values: Any) -> T:
        if values.keys() != names:  # a default to fill in, or a wrong name: the real __init__
            return cls(**values)
        made = _new(cls)
        made.__dict__.update(values)
        return made

    probe = {f.name: object() for f in fields}
    try:
        same = vars(make(**probe)) == vars(cls(**probe))
    except (TypeError, ValueError, AttributeError):
        return cls
    return make if same else cls
