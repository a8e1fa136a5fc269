"""The fast path of parsing: Lark's LALR table, driven by a lean loop.

Lark parses a 10,000-line program in seconds; most of that is its general
machinery (a token object, a lexer per parser state, a tree-shaping wrapper per
rule), not the grammar. This module drives the very table Lark builds from
``grammar/cosmos.lark`` (:mod:`cosmos.lang.lalr_tables`) and hands the builder
the same children Lark would:

- one regular expression made of Lark's own terminal patterns lexes the text
  (no two terminals can start at the same character, apart from a keyword and
  WORD), and a WORD becomes a keyword where the parser state takes that keyword,
  as Lark's contextual lexer decides it (``_WordsEverywhere``);
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


def statements(text: str, tables: Tables) -> Iterator[tuple[list[Tok], tuple[str, ...]]]:
    r"""The tokens of each statement (its ``_NL`` included) and its shape.

    Ignored tokens are dropped. The shape holds each token's kind, a WORD's as
    the keyword it may stand for (the parser state decides: :class:`Run`), so two
    statements of one shape are parsed alike from the same stack.

    The text is lexed a line at a time: no terminal reaches past a line break
    (one that holds a line break ends there), so each match is the one the
    whole text would give, and a token's offset in its line is its column - 1
    (Lark counts lines by ``\n`` alone). Tokens are made without a call to
    their ``__init__`` (one call per token is a fifth of the lexing time).

    Raises:
        GiveUp: A character no terminal matches, or a word outside ASCII.
    """
    keywords = tables.keywords
    kinds = tables.kinds
    roles = tables.roles
    finditer = tables.lexer.finditer
    new = object.__new__
    plain, word, ignored, bad, ignored_break = (
        Role.PLAIN,
        Role.WORD,
        Role.IGNORED,
        Role.BAD,
        Role.IGNORED_BREAK,
    )
    found: list[Tok] = []
    shape: list[str] = []
    add_token = found.append
    add_kind = shape.append
    pieces = text.split("\n")
    last = pieces.pop()  # what follows the last line break
    lines = chain((piece + "\n" for piece in pieces), [last] if last else [])
    for line, piece in enumerate(lines, 1):
        for match in finditer(piece):
            group: int = match.lastindex  # type: ignore[assignment]
            start, stop = match.span(group)
            role = roles[group]
            if role is plain:
                kind: str = kinds[group]  # type: ignore[assignment]
                token = new(Tok)
                token.type = kind
                token.value = piece[start:stop]
                token.line = token.end_line = line
                token.column = start + 1
                token.end_column = stop + 1
                add_token(token)
                add_kind(kind)
            elif role is word:
                value = piece[start:stop]
                if not value.isascii():
                    raise GiveUp
                token = new(Tok)
                token.type = "WORD"
                token.value = value
                token.line = token.end_line = line
                token.column = start + 1
                token.end_column = stop + 1
                add_token(token)
                add_kind(keywords.get(value.lower(), "WORD"))
            elif role is ignored or role is ignored_break:
                continue
            elif role is bad:
                raise GiveUp
            else:  # a statement's end (a line break, the line's last token, or ';')
                value = piece[start:stop]
                if value[-1] == "\n":
                    token = Tok(kinds[group], value, line, start + 1, line + 1, 1)  # type: ignore[arg-type]
                else:
                    token = Tok(kinds[group], value, line, start + 1, line, stop + 1)  # type: ignore[arg-type]
                add_token(token)
                add_kind(token.type)
                yield found, tuple(shape)
                found = []
                shape = []
                add_token = found.append
                add_kind = shape.append
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
