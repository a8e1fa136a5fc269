"""The grammar and the Lark parser built from it, and the language's keywords.

The grammar is ``grammar/cosmos.lark`` (shipped inside the wheel as
``cosmos/grammar/cosmos.lark``). Lark runs LALR with the contextual lexer and
calls the tree builder (:mod:`cosmos.lang.parse.builder`, a ``Transformer``) as
each rule is reduced, so no parse tree is kept. Every token is kept, so a
node's span runs from its first token to its last (an inline transformer gets
no ``meta``, so Lark's ``propagate_positions`` would add nothing).

The analysed grammar is cached in the user's own cache directory
(``$COSMOS_CACHE_DIR``, else ``$XDG_CACHE_HOME/cosmos`` or ``~/.cache/cosmos``), which saves about 0.1 s
per start. Lark's ``cache=True`` is not used: it writes a pickle under a
predictable name in the shared temporary directory and loads whatever file it
finds there. Where the cache directory cannot be made (a read-only home), the
parser is built each time; a stale or broken cache file is rebuilt by Lark.
"""

from __future__ import annotations

import hashlib
import sys
from functools import cache
from pathlib import Path
from typing import Any

import lark
from lark import Lark

from cosmos.lang.parse.builder import TreeBuilder
from cosmos.user_cache import user_cache_root


def _grammar_text() -> str:
    """The grammar, from the installed package or else from the source tree.

    Read by path: a wheel installs it as ``cosmos/grammar/cosmos.lark`` (asking
    :mod:`importlib.resources` for that file cost 1.8 ms of every run).
    """
    here = Path(__file__).resolve().parents[2]
    packaged = here / "grammar" / "cosmos.lark"
    if packaged.is_file():
        return packaged.read_text(encoding="utf-8")
    return (here.parent / "grammar" / "cosmos.lark").read_text(encoding="utf-8")


class _WordsEverywhere:
    """A no-op postlexer whose ``always_accept`` makes the lexer try WORD in every state.

    A keyword is then lexed as WORD and renamed by Lark only where the parser
    expects it, so keywords end at word boundaries and may double as names.
    """

    always_accept = ("WORD",)

    def process(self, stream: Any) -> Any:
        return stream


def _cache_file(grammar: str) -> str | bool:
    """Where the analysed grammar is cached (named by the grammar, Lark and Python), or False.

    In the user cache (:func:`cosmos.user_cache.user_cache_root`: ``$COSMOS_CACHE_DIR`` if set),
    with the compiled kernels and the other kept results.
    """
    directory = user_cache_root()
    try:
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError:
        return False
    digest = hashlib.sha256(grammar.encode("utf-8")).hexdigest()[:16]
    python = f"{sys.version_info[0]}{sys.version_info[1]}"
    return str(directory / f"grammar-{digest}-lark{lark.__version__}-py{python}.cache")


@cache
def lark_parser() -> Lark:
    """The shared Lark parser (LALR, contextual lexer, builds AST nodes inline)."""
    grammar = _grammar_text()
    return Lark(
        grammar,
        parser="lalr",
        lexer="contextual",
        keep_all_tokens=True,
        maybe_placeholders=True,
        postlex=_WordsEverywhere(),
        transformer=TreeBuilder(),
        cache=_cache_file(grammar),
    )


@cache
def _keywords() -> dict[str, str]:
    return {
        terminal.name: terminal.pattern.value
        for terminal in lark_parser().terminals
        if terminal.pattern.type == "str" and terminal.pattern.value.isalpha()
    }


def keyword_of(terminal_name: str) -> str | None:
    """The keyword a terminal stands for (``"SPEED"``), or None for other terminals."""
    return _keywords().get(terminal_name)


def keywords() -> frozenset[str]:
    """Every keyword of the language, upper case."""
    return frozenset(word.upper() for word in _keywords().values())


@cache
def statement_keywords() -> tuple[str, ...]:
    """The keywords a statement starts with, in the grammar's order (``MOVE``, ``CONTACT``, ...).

    Read from the grammar: the first keyword of each rule ``_statement`` names, so a
    statement added there is known to the messages, the checker and the REPL.
    """
    parser = lark_parser()
    found: list[str] = []
    for rule in parser.rules:
        if rule.origin.name != "_statement":
            continue
        statement = rule.expansion[0].name
        for alternative in parser.rules:
            if alternative.origin.name == statement and alternative.expansion:
                word = keyword_of(alternative.expansion[0].name)
                if word is not None:
                    found.append(word.upper())
    return tuple(dict.fromkeys(found))
