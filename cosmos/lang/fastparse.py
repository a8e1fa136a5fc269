"""The fast path of parsing: Lark's LALR table, driven by a lean loop.

Lark parses a 10,000-line program in seconds; most of that is its general
machinery (a token object, a lexer per parser state, a tree-shaping wrapper per
rule), not the grammar. This module drives the very table Lark builds from
``grammar/cosmos.lark`` (:mod:`cosmos.lang.lalr_tables`) and hands the builder
the same children Lark would:

- one regular expression made of Lark's own terminal patterns lexes the text
  (no two terminals can start at the same character, apart from a keyword and
  WORD); a word that spells a keyword is lexed as that keyword, and becomes a
  WORD again where the parser state does not take the keyword, as Lark's
  contextual lexer decides it (``_WordsEverywhere``);
- each rule is reduced as Lark's tree builder would.

The text is parsed statement by statement (a statement ends at ``_NL``). What
the table does with a statement depends only on the parser's stack before it
and on the kinds of its tokens, so the first statement of each shape is run
through the table (:mod:`cosmos.lang.lalr_run`) and the actions it took are
replayed for the later ones (by code made for that shape the second time it is
seen, :mod:`cosmos.lang.replay_code`): the same reductions, with the same
children, in the same order.

It accepts exactly what Lark accepts, and gives up (raises :class:`GiveUp`) at
the first thing it does not: a syntax error, or a word outside ASCII, whose case
rules are Lark's to decide. Then the program is parsed again by Lark, and Lark's
error becomes the message as before; errors come from one place only.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import chain
from typing import Any

from cosmos.lang.lalr_run import END, GiveUp, Run, Tok, Trace
from cosmos.lang.lalr_tables import Role, Tables
from cosmos.lang.replay_code import Replay, replay_function

__all__ = ["GiveUp", "Tok", "parse"]


UNREAD = frozenset({"COMMA", "EQUAL", "STAR", "_NL"})
"""Terminals whose tokens the tree builder passes over without reading their
text or place (:mod:`cosmos.lang.tree_builder`): one shared token each, with no
place, stands for all of them (a fifth of a program's tokens made for nothing)."""


def statements(text: str, tables: Tables) -> Iterator[tuple[list[Tok], tuple[str, ...]]]:
    r"""The tokens of each statement (its ``_NL`` included) and its shape.

    Ignored tokens are dropped. The shape holds each token's kind (a word's is
    the keyword it spells, if any: the parser state decides whether it stands
    for it, :class:`Run`), so two statements of one shape are parsed alike from
    the same stack.

    The text is lexed a line at a time (:mod:`cosmos.lang.scanner`): no terminal
    reaches past a line break (one that holds a line break ends there), so each
    match is the one the whole text would give, and a token's column is counted
    from the lengths of what precedes it in its line (Lark counts lines by
    ``\n`` alone). Tokens are made without a call to their ``__init__`` (one call
    per token is a fifth of the lexing time), and those of :data:`UNREAD`
    terminals not at all.

    Raises:
        GiveUp: A character no terminal matches, or a word outside ASCII.
    """
    keywords = tables.keywords
    scan = tables.scanner
    findall = scan.pattern.findall
    first_kinds = scan.first_kinds
    role_of = {kind: role for kind, role in zip(tables.kinds, tables.roles, strict=True) if kind is not None}
    placed = frozenset(kind for kind, role in role_of.items() if role is Role.PLAIN) - UNREAD
    shared = {kind: Tok(kind, "", None, None, None, None) for kind in UNREAD}  # type: ignore[arg-type]
    ends = frozenset(kind for kind, role in role_of.items() if role is Role.BREAK)
    ignored = frozenset(kind for kind, role in role_of.items() if role in (Role.IGNORED, Role.IGNORED_BREAK))
    new = object.__new__
    found: list[Tok] = []
    shape: list[str] = []
    add_token = found.append
    add_kind = shape.append
    pieces = text.split("\n")
    last = pieces.pop()  # what follows the last line break
    lines = chain((piece + "\n" for piece in pieces), [last] if last else [])
    for line, piece in enumerate(lines, 1):
        column = 1
        for blanks, value in findall(piece):
            start = column + len(blanks)
            column = start + len(value)
            kind = first_kinds.get(value[0])
            if kind is None:  # a character that starts tokens of several kinds, or not ASCII
                kind = scan.kind_at(piece, start - 1)
            if kind == "WORD":
                if not value.isascii():
                    raise GiveUp
                kind = keywords.get(value.lower(), kind)
                token = new(Tok)
                token.type = kind
                token.value = value
                token.line = token.end_line = line
                token.column = start
                token.end_column = column
                add_token(token)
                add_kind(kind)
            elif kind in placed:
                token = new(Tok)
                token.type = kind
                token.value = value
                token.line = token.end_line = line
                token.column = start
                token.end_column = column
                add_token(token)
                add_kind(kind)
            elif kind in shared:
                add_token(shared[kind])
                add_kind(kind)
                if kind in ends:  # a statement's end (a line break, the line's last token, or ';')
                    yield found, tuple(shape)
                    found = []
                    shape = []
                    add_token = found.append
                    add_kind = shape.append
            elif kind not in ignored:  # a bad character, or a token of a kind this loop does not know
                raise GiveUp
    if found:
        yield found, tuple(shape)


def parse(text: str, tables: Tables) -> Any:
    """The value of the start rule for ``text``, built as Lark would build it.

    Raises:
        GiveUp: Lark would not accept the text the same way, or at all.
    """
    run = Run(tables)
    values = run.values
    states = run.states
    traces: dict[_Key, Trace] = {}
    replays: dict[_Key, tuple[Replay, tuple[int, ...]]] = {}
    for found, shape in statements(text, tables):
        key = (tuple(states), shape)
        known = replays.get(key)
        if known is None:
            trace = traces.get(key)
            if trace is None:  # a new shape: through the table
                traces[key] = run.feed(found)
                continue
            known = replays[key] = (replay_function(trace, tables.rules), trace.states)
        replay, after = known
        replay(found, values)
        states[:] = after
    end = Tok(END, "", 0, 0, 0, 0)
    run.feed([end])
    if not run.accepted:  # not reached: $END either completes the start rule or is refused
        raise GiveUp
    return run.result


_Key = tuple[tuple[int, ...], tuple[str, ...]]
"""A statement's shape and the stack of states it is parsed from."""
