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
