"""PROC, CALL and REPEAT: procedures registered, calls and loops expanded in place.

A CALL compiles the procedure's body where it is called, from the procedure's own
text; a REPEAT compiles its body once per pass. Each expanded statement names
where it was expanded from (the run's context), for its errors and warnings.
"""

from __future__ import annotations

import math
from dataclasses import replace

from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.state import CompileState, ProcEntry, frozen_map
from cosmos.lang.evaluate.evaluator import suggest
from cosmos.lang.parse.grammar import statement_keywords

MAX_STEPS = 100_000
"""Most steps a program may expand to (procedures and loops included)."""
MAX_EXPANSION_DEPTH = 150
"""Deepest nesting of procedure calls and REPEAT passes while expanding (each is
compiled recursively; the parser bounds the blocks written inside each other)."""


def register_procedure(run: CompileContext, statement: ast.ProcDef, state: CompileState) -> CompileState:
    """Register a PROC; its body is compiled where it is called."""
    key = statement.name.key
    if key in state.procedures and state.procedures[key].definition.span.file == statement.span.file:
        first = state.procedures[key].definition.span
        raise ProgramError(
            f"PROC {statement.name.name} is already defined at line {first.line}",
            statement.name.span,
        )
    entry = ProcEntry(statement, run.source)
    return replace(state, procedures=frozen_map({**state.procedures, key: entry}))


def expand_call(run: CompileContext, statement: ast.Call, state: CompileState) -> CompileState:
    """Compile the called procedure's body in place, from its own text."""
    key = statement.name.key
    entry = state.procedures.get(key)
    if entry is None:
        if key == "end":
            raise ProgramError("END without a PROC or REPEAT to close", statement.span)
        if statement.name.name.upper() in statement_keywords():
            raise ProgramError(f"{statement.name.name.upper()} needs more after it", statement.span)
        raise ProgramError(
            f"unknown procedure '{statement.name.name}'{suggest(statement.name.name, state.procedures)}",
            statement.name.span,
        )
    if key in run.call_stack:
        chain = " -> ".join([*run.call_stack, key])
        raise ProgramError(f"procedures call each other without end: {chain}", statement.span)
    _bounded_depth(run, statement)
    state = replace(state, called=state.called | {key})
    outer_source, outer_lines = run.source, run.lines
    run.source = entry.source
    run.lines = run.lines_of(entry.source)
    run.call_stack.append(key)
    run.context.append(f"PROC {entry.definition.name.name} called at line {statement.span.line}")
    try:
        for inner in entry.definition.body:
            state = run.statement(inner, state)
    finally:
        run.context.pop()
        run.call_stack.pop()
        run.source, run.lines = outer_source, outer_lines
    return state


def expand_repeat(run: CompileContext, statement: ast.Repeat, state: CompileState) -> CompileState:
    """Compile a REPEAT's body once per pass."""
    count_value = run.evaluator_for(state).expect_scalar(statement.count, units.DIMENSIONLESS, "REPEAT")
    if not math.isfinite(count_value) or count_value != int(count_value) or count_value < 0:
        raise ProgramError(
            f"REPEAT needs a whole number of times, not {run.text_of(statement.count.span)}",
            statement.count.span,
        )
    count = int(count_value)
    if count == 0:
        run.warn("REPEAT 0 runs its block no times", statement.count.span)
    if count > MAX_STEPS:
        raise ProgramError(f"REPEAT {count} is more than {MAX_STEPS} passes", statement.count.span)
    if count:
        _bounded_depth(run, statement)
    for index in range(count):
        run.context.append(f"REPEAT pass {index + 1} of {count} at line {statement.span.line}")
        try:
            for inner in statement.body:
                state = run.statement(inner, state)
        finally:
            run.context.pop()
    return state


def _bounded_depth(run: CompileContext, statement: ast.Call | ast.Repeat) -> None:
    """Refuse to expand one level deeper than :data:`MAX_EXPANSION_DEPTH`.

    Raises:
        ProgramError: At the CALL or REPEAT, naming the outermost expansions.
    """
    if len(run.context) >= MAX_EXPANSION_DEPTH:
        outer = "; ".join(run.context[:3])
        raise ProgramError(
            f"procedure calls and REPEAT blocks nest more than {MAX_EXPANSION_DEPTH} deep here "
            f"(from {outer}; ...); call fewer procedures from inside each other",
            statement.span,
        )


HANDLERS: dict[type, Handler] = {
    ast.ProcDef: register_procedure,
    ast.Call: expand_call,
    ast.Repeat: expand_repeat,
}
"""The handler of each statement type of this module (merged into the compiler's one table)."""
