"""The fast path of parsing: Lark's LALR table, driven by a lean loop.

Lark parses a 10,000-line program in seconds; most of that is its general
machinery (a token object, a lexer per parser state, a tree-shaping wrapper per
rule), not the grammar. This module drives the very table Lark builds from
``grammar/cosmos.lark``, and hands the builder the same children Lark would:

- one regular expression made of Lark's own terminal patterns lexes the text
  (no two terminals can start at the same character, apart from a keyword and
  WORD), and a WORD becomes a keyword where the parser state takes that keyword,
  as Lark's contextual lexer decides it (``_WordsEverywhere``);
- each rule is reduced as Lark's tree builder would (``_rule`` children spliced
  in, ``?rule`` with one child passed through, ``[x]`` placeholders as None).

It accepts exactly what Lark accepts, and gives up (returns None) at the first
thing it does not: a syntax error, or a word outside ASCII, whose case rules are
Lark's to decide. Then the program is parsed again by Lark, and Lark's error
becomes the message as before; errors come from one place only.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from lark import Lark
from lark.grammar import Rule
from lark.lexer import PatternStr, TerminalDef, _regexp_has_newline
from lark.parsers.lalr_analysis import Shift


class Tok:
    r"""A token, with the attributes of Lark's ``Token`` that the builder reads.

    Lines and columns count from 1 and as Lark counts them (a line ends at ``\n``);
    ``end_line``/``end_column`` are those of the character after the token.
    """

    __slots__ = ("type", "value", "line", "column", "end_line", "end_column")

    def __init__(self, type_: str, value: str, line: int, column: int, end_line: int, end_column: int):
        self.type = type_
        self.value = value
        self.line = line
        self.column = column
        self.end_line = end_line
        self.end_column = end_column

    def __str__(self) -> str:
        return self.value

    def __repr__(self) -> str:
        return f"Tok({self.type}, {self.value!r}, {self.line}:{self.column})"


_BAD = "bad"
"""The lexer's group for a character that no terminal matches (terminal names are upper case)."""


class GiveUp(Exception):
    """The fast path does not accept the text (Lark will say why)."""


Reduce = Callable[[list[Any]], Any]


_Rule = tuple[int, str, Reduce | None]
"""How to reduce one grammar rule: the number of symbols on its right-hand side
(popped), its nonterminal (for the goto), and what builds the value from the
popped values (None passes the one value through unchanged: a ``?rule`` of one
symbol)."""


@dataclass(frozen=True)
class Tables:
    """What the fast path needs from Lark, built once per parser and builder.

    Attributes:
        lexer: Lark's patterns of the terminals other than keywords, each a
            group named for its terminal, then a catch-all group (``_BAD``) for a
            character no terminal matches; blanks before a token are part of its
            match, outside its group.
        ignored: Terminal names that are skipped (comments, continuations).
        keywords: Terminal name by lower-case keyword text.
        actions: Per parser state, by symbol name: a shift or goto (the new
            state, >= 0) or a reduction (``~rule_index``, < 0).
        rules: The rules, by index.
        start: The start state.
        end: The accepting state.
    """

    lexer: re.Pattern[str]
    ignored: frozenset[str]
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


def _reducer(rule: Rule, builder: Any) -> Reduce | None:
    """The reduction of ``rule`` as Lark's tree builder does it (keep_all_tokens, placeholders).

    Children that are ``_rule`` values (lists here) are spliced in; placeholders
    for absent ``[x]`` are None; a ``?rule`` left with one child is that child;
    a ``_rule`` is the list of its children; any other rule calls the builder's
    method of the rule's alias or name.
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
        return None
    found = getattr(builder, name, None)

    def missing(children: list[Any]) -> Any:
        raise NotImplementedError(f"grammar rule '{name}' has no builder in cosmos/lang/parser.py")

    method: Reduce = missing if found is None else found

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

    if inline:
        if plain:
            return list  # a copy of the popped values, made in C
        if trailing == 0 and include[0][1] and not any(before for _, _, before in include):
            return _extender([expand for _, expand, _ in include[1:]])
        return shape
    if expand_one:

        def reduce_one(children: list[Any]) -> Any:
            filtered = shape(children)
            return filtered[0] if len(filtered) == 1 else method(filtered)

        return reduce_one
    if plain:
        return method
    expanded = [index for index, expand, _ in include if expand]
    if not any(before for _, _, before in include):
        if not expanded:  # only placeholders at the end: [x] last
            padding = [None] * trailing
            return lambda children: method(children + padding)
        if len(expanded) == 1 and not trailing:  # one _rule spliced in
            at = expanded[0]
            return lambda children: method(children[:at] + children[at] + children[at + 1 :])
    return lambda children: method(shape(children))


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
    groups = [f"(?P<{terminal.name}>{terminal.pattern.to_regexp()})" for terminal in lexed]
    prefix = "|".join([f"(?:{terminal.pattern.to_regexp()})" for terminal in blanks] or ["(?!)"])
    groups.append(f"(?P<{_BAD}>[\\s\\S])")
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
                rules.append((len(argument.expansion), argument.origin.name, _reducer(argument, builder)))
            actions[state][symbol] = ~rule_index[argument]
    return Tables(
        lexer=lexer,
        ignored=ignored,
        keywords=keywords,
        actions=actions,
        rules=rules,
        start=table.start_states["start"],
        end=table.end_states["start"],
    )


def tokens(text: str, tables: Tables) -> list[Tok]:
    """The tokens of ``text`` (ignored ones dropped), ending with ``$END``.

    Keywords are still WORD here; the parser state decides (:func:`parse`).

    Raises:
        GiveUp: A character no terminal matches.
    """
    found: list[Tok] = []
    append = found.append
    ignored = tables.ignored
    line = 1
    line_start = 0  # offset of the first character of the line
    for match in tables.lexer.finditer(text):
        kind: str = match.lastgroup  # type: ignore[assignment]
        if kind == _BAD:
            raise GiveUp
        value = match.group(kind)
        start = match.start(kind)
        column = start - line_start + 1
        if "\n" in value:  # only line breaks and continuations hold one
            end_line = line + value.count("\n")
            line_start = start + value.rindex("\n") + 1
            end_column = start + len(value) - line_start + 1
        else:
            end_line = line
            end_column = column + len(value)
        if kind not in ignored:
            append(Tok(kind, value, line, column, end_line, end_column))
        line = end_line
    last = found[-1] if found else Tok("$END", "", 1, 1, 1, 1)
    append(Tok("$END", "", last.line, last.column, last.end_line, last.end_column))
    return found


def parse(text: str, tables: Tables) -> Any:
    """The value of the start rule for ``text``, built as Lark would build it.

    Raises:
        GiveUp: Lark would not accept the text the same way, or at all.
    """
    actions = tables.actions
    rules = tables.rules
    keywords = tables.keywords
    end = tables.end
    states = [tables.start]
    values: list[Any] = []
    state = tables.start
    for token in tokens(text, tables):
        kind = token.type
        row = actions[state]
        if kind == "WORD":
            if not token.value.isascii():
                raise GiveUp
            keyword = keywords.get(token.value.lower())
            if keyword is not None and keyword in row:
                kind = token.type = keyword
        while True:
            action = row.get(kind)
            if action is None:
                raise GiveUp
            if action >= 0:
                states.append(action)
                values.append(token)
                state = action
                break
            size, origin, reduce = rules[~action]
            if reduce is None:  # one value passed through: only the state changes
                state = actions[states[-2]][origin]
                states[-1] = state
            else:
                if size:
                    children = values[-size:]
                    del values[-size:]
                    del states[-size:]
                else:
                    children = []
                values.append(reduce(children))
                below = states[-1]
                state = actions[below][origin]
                # Rules that pass the value through (?expr: sum) need only the goto.
                step = actions[state].get(kind, 0)
                while step < 0 and rules[~step][2] is None:
                    state = actions[below][rules[~step][1]]
                    step = actions[state].get(kind, 0)
                states.append(state)
                if state == end:
                    return values[-1]
            row = actions[state]
    raise GiveUp
