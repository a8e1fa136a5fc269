"""Running tokens through Lark's LALR table, and replaying what a run did.

:class:`Run` holds the parser's stacks and feeds it tokens, one statement at a
time, as Lark's parser would: shift, or reduce by a rule (the builder makes the
rule's value from the popped values), until the token is shifted. It writes
down what it did as a :class:`Trace`. Another statement whose tokens are of the
same kinds, fed from the same stack of states, takes exactly the same actions
(an LALR parser looks at nothing else), so :func:`replay` performs the trace's
reductions on its tokens without consulting the table.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from cosmos.lang.lalr_tables import Tables

END = "$END"
"""The kind of the token after the last one."""


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


class GiveUp(Exception):
    """The fast path does not accept the text (Lark will say why)."""


Step = tuple[int, int, int, int]
"""(start, stop, size, rule): shift the statement's tokens[start:stop], then
reduce ``size`` values by the rule of that index in :attr:`Tables.rules`."""


@dataclass(frozen=True)
class Trace:
    """What a run did with one statement's tokens.

    Attributes:
        renames: (index, "WORD") for each word lexed as a keyword that the
            parser took as a WORD (a name).
        steps: The reductions that build values, in order, each after its shifts
            (reductions that pass one value through change only the state).
        count: The number of tokens (those after the last step are shifted last).
        states: The stack of states afterwards.
    """

    renames: tuple[tuple[int, str], ...]
    steps: tuple[Step, ...]
    count: int
    states: tuple[int, ...]


class Run:
    """The parser's stacks, fed token by token through the table.

    Attributes:
        states: The stack of parser states.
        values: The stack of values (tokens and what reductions built).
        result: The value of the start rule, once the text is accepted.
    """

    def __init__(self, tables: Tables):
        self.tables = tables
        self.states: list[int] = [tables.start]
        self.values: list[Any] = []
        self.result: Any = None
        self.accepted = False

    def feed(self, tokens: list[Tok]) -> Trace:
        """Shift each token, after the reductions it calls for; what was done.

        Raises:
            GiveUp: The table has no action for a token (a syntax error).
        """
        tables = self.tables
        actions = tables.actions
        rules = tables.rules
        keywords = frozenset(tables.keywords.values())
        end = tables.end
        states = self.states
        values = self.values
        renames: list[tuple[int, str]] = []
        steps: list[Step] = []
        start = 0  # the first token shifted since the last reduction
        state = states[-1]
        row = actions[state]
        for index, token in enumerate(tokens):
            kind = token.type
            if kind in keywords and kind not in row:  # a keyword where a name is expected
                kind = token.type = "WORD"
                renames.append((index, kind))
            while True:
                action = row.get(kind)
                if action is None:
                    raise GiveUp
                if action >= 0:
                    states.append(action)
                    values.append(token)
                    state = action
                    row = actions[state]
                    break
                rule = ~action
                size, origin, reduce, _ = rules[rule]
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
                    steps.append((start, index, size, rule))
                    start = index
                    below = states[-1]
                    state = actions[below][origin]
                    # Rules that pass the value through (?expr: sum) need only the goto.
                    step = actions[state].get(kind, 0)
                    while step < 0 and rules[~step][2] is None:
                        state = actions[below][rules[~step][1]]
                        step = actions[state].get(kind, 0)
                    states.append(state)
                    if state == end:
                        self.result = values[-1]
                        self.accepted = True
                        return Trace(tuple(renames), tuple(steps), len(tokens), tuple(states))
                row = actions[state]
        return Trace(tuple(renames), tuple(steps), len(tokens), tuple(states))
