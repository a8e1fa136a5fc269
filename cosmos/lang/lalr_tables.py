"""What the fast parser needs from Lark: its terminals, keywords and LALR table.

Built once per parser and builder from the very objects Lark builds from
``grammar/cosmos.lark``: the terminals' own patterns make one master regular
expression, the string terminals that WORD matches whole are the keywords (a
WORD becomes one where the parser state takes it, as Lark's contextual lexer
with ``_WordsEverywhere`` decides), and each rule gets the reduction Lark's tree
builder would perform (:mod:`cosmos.lang.reductions`).
"""

from __future__ import annotations

import enum
import re
from dataclasses import dataclass
from typing import Any

from lark import Lark
from lark.grammar import Rule
from lark.lexer import PatternStr, TerminalDef, _regexp_has_newline
from lark.parsers.lalr_analysis import Shift

from cosmos.lang.reductions import Recipe, Reduce, reduction
from cosmos.lang.scanner import Scanner, scanner

BAD = "bad"
"""The lexer's group for a character that no terminal matches (terminal names are upper case)."""


class Role(enum.Enum):
    """What the lexer does with a match of a terminal (or of no terminal: BAD)."""

    PLAIN = "a token"
    WORD = "a token that may be a keyword"
    BREAK = "a token that may hold line breaks, which ends a statement"
    IGNORED = "skipped"
    IGNORED_BREAK = "skipped, but may hold line breaks"
    BAD = "a character no terminal matches"


_Rule = tuple[int, str, Reduce | None, Recipe | None]
"""How to reduce one grammar rule: the number of symbols on its right-hand side
(popped), its nonterminal (for the goto), what builds the value from the popped
values and the recipe of that (both None pass the one value through unchanged:
a ``?rule`` of one symbol; :mod:`cosmos.lang.reductions`)."""


@dataclass(frozen=True)
class Tables:
    """What the fast path needs from Lark, built once per parser and builder.

    Attributes:
        lexer: Lark's patterns of the terminals other than keywords, each a
            group named for its terminal, then a catch-all group (``BAD``) for a
            character no terminal matches; blanks before a token are part of its
            match, outside its group.
        kinds: The terminal name (or ``BAD``) of each of the lexer's groups, by
            group number (a match's ``lastindex``); None for groups inside a
            terminal's own pattern.
        roles: What the lexer does with each group's match (None for groups
            inside a terminal's own pattern).
        scanner: The same expression, made for speed (:mod:`cosmos.lang.scanner`).
        keywords: Terminal name by lower-case keyword text.
        actions: Per parser state, by symbol name: a shift or goto (the new
            state, >= 0) or a reduction (``~rule_index``, < 0).
        rules: The rules, by index.
        start: The start state.
        end: The accepting state.
    """

    lexer: re.Pattern[str]
    kinds: tuple[str | None, ...]
    roles: tuple[Role | None, ...]
    scanner: Scanner
    keywords: dict[str, str]
    actions: list[dict[str, int]]
    rules: list[_Rule]
    start: int
    end: int


def _lark_order(terminal: TerminalDef) -> tuple[int, int, int, str]:
    """The order in which Lark's lexer tries terminals (lark.lexer.BasicLexer)."""
    return (-terminal.priority, -terminal.pattern.max_width, -len(terminal.pattern.value), terminal.name)


def _keywords(terminals: list[TerminalDef], word: TerminalDef) -> dict[str, str]:
    """The string terminals that WORD matches whole (Lark lexes them as WORD, then renames)."""
    found: dict[str, str] = {}
    word_re = re.compile(word.pattern.to_regexp())
    for terminal in terminals:
        pattern = terminal.pattern
        if not isinstance(pattern, PatternStr) or terminal.priority != word.priority:
            continue
        if word_re.fullmatch(pattern.value) is None:
            continue
        if not set(pattern.flags) <= set(word.pattern.flags) or "i" not in pattern.flags:
            raise ValueError(f"keyword {terminal.name} is not case-insensitive like WORD")
        if not pattern.value.isascii():
            raise ValueError(f"keyword {terminal.name} is not ASCII")
        key = pattern.value.lower()
        if key in found:
            raise ValueError(f"keywords {found[key]} and {terminal.name} are the same word")
        found[key] = terminal.name
    return found


def build_tables(lark: Lark, builder: Any) -> Tables:
    """The lexer, keyword and parse tables of ``lark`` (LALR, contextual lexer).

    Args:
        lark: The parser built from the grammar.
        builder: The object whose methods build nodes (named for rules and aliases).
    """
    conf = lark.lexer_conf
    terminals = list(conf.terminals)
    by_name = {terminal.name: terminal for terminal in terminals}
    keywords = _keywords(terminals, by_name["WORD"])
    ignored = frozenset(conf.ignore)
    # Blanks that hold no line break are matched in front of the next token.
    blanks = [by_name[n] for n in sorted(ignored) if not _regexp_has_newline(by_name[n].pattern.to_regexp())]
    lexed = sorted(
        (t for t in terminals if t.name not in keywords.values() and t not in blanks), key=_lark_order
    )
    names = [terminal.name for terminal in lexed] + [BAD]
    patterns = [terminal.pattern.to_regexp() for terminal in lexed] + [r"[\s\S]"]
    groups = [f"(?P<{name}>{pattern})" for name, pattern in zip(names, patterns, strict=True)]
    blank_patterns = [terminal.pattern.to_regexp() for terminal in blanks]
    prefix = "|".join([f"(?:{pattern})" for pattern in blank_patterns] or ["(?!)"])
    lexer = re.compile(f"(?:{prefix})*(?:{'|'.join(groups)})")

    table = lark.parser.parser.parser.parse_table
    rules: list[_Rule] = []
    rule_index: dict[Rule, int] = {}
    actions: list[dict[str, int]] = [{} for _ in range(max(table.states) + 1)]
    for state, row in table.states.items():
        for symbol, (action, argument) in row.items():
            if action is Shift:
                actions[state][symbol] = argument
                continue
            if argument not in rule_index:
                rule_index[argument] = len(rules)
                reduce, recipe = reduction(argument, builder)
                rules.append((len(argument.expansion), argument.origin.name, reduce, recipe))
            actions[state][symbol] = ~rule_index[argument]
    kinds: list[str | None] = [None] * (lexer.groups + 1)
    for name, number in lexer.groupindex.items():
        kinds[number] = name
    breaks = {t.name for t in lexed if _regexp_has_newline(t.pattern.to_regexp())}
    roles: list[Role | None] = [None] * len(kinds)
    for number, kind_name in enumerate(kinds):
        if kind_name is None:
            continue
        if kind_name == BAD:
            roles[number] = Role.BAD
        elif kind_name == "WORD":
            roles[number] = Role.WORD
        elif kind_name in ignored:
            roles[number] = Role.IGNORED_BREAK if kind_name in breaks else Role.IGNORED
        else:
            roles[number] = Role.BREAK if kind_name in breaks else Role.PLAIN
    return Tables(
        lexer=lexer,
        kinds=tuple(kinds),
        roles=tuple(roles),
        scanner=scanner(blank_patterns, patterns, lexer, tuple(kinds)),
        keywords=keywords,
        actions=actions,
        rules=rules,
        start=table.start_states["start"],
        end=table.end_states["start"],
    )
