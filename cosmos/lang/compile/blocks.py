"""PROC, CALL and REPEAT: procedures registered, calls and loops expanded in place.

A CALL compiles the procedure's body where it is called, from the procedure's own
text, with its parameters bound to the call's arguments (values with units,
evaluated where the call is); a REPEAT compiles its body once per pass. Each
expanded statement names where it was expanded from (the run's context), for its
errors and warnings. An argument that does not fit where the body uses its
parameter is an error at the argument.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import replace
from typing import Any

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.state import CompileState, ProcEntry, frozen_map
from cosmos.lang.evaluate.evaluator import suggest
from cosmos.lang.evaluate.values import Binding, BindingKind, SuppressedError
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
            raise ProgramError(
                "END without a PROC or REPEAT to close (nor an IF, WHILE or TRY)", statement.span
            )
        if key == "else":
            raise ProgramError("ELSE without an IF: ELSE goes between IF ... and its END", statement.span)
        if statement.name.name.upper() in statement_keywords():
            raise ProgramError(f"{statement.name.name.upper()} needs more after it", statement.span)
        raise ProgramError(
            f"unknown procedure '{statement.name.name}'{suggest(statement.name.name, state.procedures)}",
            statement.name.span,
        )
    if key in run.call_stack:
        chain = " -> ".join([*run.call_stack, key])
        raise EndlessCallsError(f"procedures call each other without end: {chain}", statement.span)
    _bounded_depth(run, statement)
    definition = entry.definition
    if not run.context:  # the outermost expansion: what it will emit, at least, is known now
        run.make_room(least_steps(definition.body, state.procedures), statement.span)
    caller_names = state.names
    state = replace(
        state, called=state.called | {key}, names=_bind_arguments(run, statement, definition, state)
    )
    outer_source, outer_lines = run.source, run.lines
    run.source = entry.source
    run.lines = run.lines_of(entry.source)
    run.call_stack.append(key)
    run.context.append(f"PROC {definition.name.name} called at line {statement.span.line}")
    caught: ProgramError | None = None
    try:
        for inner in definition.body:
            state = run.statement(inner, state)
    except ProgramError as error:
        caught = error
    finally:
        run.context.pop()
        run.call_stack.pop()
        run.source, run.lines = outer_source, outer_lines
    if caught is not None:  # raised here, back in the caller's text
        raise _argument_misfit(caught, statement, definition, run.text_of) or caught
    return replace(state, names=_restore_parameters(state.names, caller_names, definition.parameters))


def _bind_arguments(
    run: CompileContext, call: ast.Call, definition: ast.ProcDef, state: CompileState
) -> Mapping[str, Binding]:
    """The names the body sees: the caller's, and each parameter bound to its argument's value.

    Raises:
        ProgramError: The call gives more or fewer values than the procedure has
            parameters, or an argument has an error of its own.
    """
    parameters, arguments = definition.parameters, call.arguments
    if len(arguments) != len(parameters):
        name = definition.name.name
        wanted = f"{len(parameters)} value{'s' if len(parameters) != 1 else ''}"
        if parameters:
            wanted += f" ({', '.join(p.name for p in parameters)})"
        where = f"PROC {name} (line {definition.span.line}) takes {wanted}"
        raise ProgramError(f"{where}; this call gives {len(arguments)}", call.span)
    if not parameters:
        return state.names
    evaluator = run.evaluator_for(state)
    bound = dict(state.names)
    for parameter, argument in zip(parameters, arguments, strict=True):
        bound[parameter.key] = Binding(evaluator.evaluate(argument), BindingKind.PARAMETER, argument.span)
    return frozen_map(bound)


def _restore_parameters(
    names: Mapping[str, Binding], caller_names: Mapping[str, Binding], parameters: tuple[ast.Ident, ...]
) -> Mapping[str, Binding]:
    """After a call: its parameters are gone (the caller's names of the same spelling are back)."""
    if not parameters:
        return names
    restored = dict(names)
    for parameter in parameters:
        if parameter.key in caller_names:
            restored[parameter.key] = caller_names[parameter.key]
        else:
            restored.pop(parameter.key, None)
    return frozen_map(restored)


class EndlessCallsError(ProgramError):
    """A call inside the procedures it calls: the call's fault, not its arguments'."""


_CONTEXT = re.compile(r" \(in [^()]*\)$")
"""The ``(in PROC p called at line 3; ...)`` an error of an expanded statement ends with."""


def _argument_misfit(
    error: ProgramError, call: ast.Call, definition: ast.ProcDef, text_of: Callable[[Span], str]
) -> ProgramError | None:
    """An error of the body at a parameter's use, told at the call's argument (None: another error).

    Args:
        error: The error compiling the body raised.
        call: The call.
        definition: The procedure called.
        text_of: Reads the caller's text.
    """
    if isinstance(error, SuppressedError | EndlessCallsError) or not definition.parameters:
        return None
    keys = [p.key for p in definition.parameters]
    span = error.span
    if span is None:
        return None
    uses = [(used, name) for used, name in _names_used(definition.body) if name in keys]
    parameter_key = next((name for used, name in uses if used == span), None)
    if parameter_key is None:  # an expression holding one parameter's uses: (0, 0, h)
        inside = {name for used, name in uses if _within(used, span)}
        parameter_key = inside.pop() if len(inside) == 1 else None
    if parameter_key is None:
        return None
    index = keys.index(parameter_key)
    parameter, argument = definition.parameters[index], call.arguments[index]
    reason = _CONTEXT.sub("", error.message)
    return ProgramError(
        f"argument {index + 1} of {definition.name.name} ({parameter.name} = {text_of(argument.span)}) "
        f"does not fit line {span.line}, where {reason}",
        argument.span,
    )


def _within(inner: Span, outer: Span) -> bool:
    """Whether ``inner`` lies inside ``outer`` (same file)."""
    return (
        inner.file == outer.file
        and (inner.line, inner.column) >= (outer.line, outer.column)
        and (inner.end_line, inner.end_column) <= (outer.end_line, outer.end_column)
    )


def _names_used(node: Any) -> Iterator[tuple[Any, str]]:
    """(span, case-folded name) of every name read in a piece of syntax tree."""
    if isinstance(node, ast.Name):
        yield node.span, node.name.casefold()
    elif isinstance(node, tuple):
        for item in node:
            yield from _names_used(item)
    elif dataclasses.is_dataclass(node) and not isinstance(node, type):
        for field in dataclasses.fields(node):
            if field.name != "span":
                yield from _names_used(getattr(node, field.name))


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
    if not run.context:
        run.make_room(count * least_steps(statement.body, state.procedures), statement.span)
    for index in range(count):
        run.context.append(f"REPEAT pass {index + 1} of {count} at line {statement.span.line}")
        try:
            for inner in statement.body:
                state = run.statement(inner, state)
        finally:
            run.context.pop()
    return state


EMITTING = (ast.Move, ast.Contact, ast.Slide, ast.Insert, ast.Wait, ast.Grasp, ast.Release)
"""Statements that emit at least one step each."""


def least_steps(body: tuple[ast.Statement, ...], procedures: Mapping[str, ProcEntry]) -> int:
    """The fewest steps ``body`` expands to: its calls and REPEATs of a written count unrolled.

    A lower bound (a block that decides at run time, a REPEAT whose count is a name,
    counts none), so that a program past :data:`MAX_STEPS` is refused before it is
    expanded statement by statement (six nested procedures of ten calls took 17 s to be).
    """
    known: dict[str, int] = {}

    def least(statements: tuple[ast.Statement, ...], calling: frozenset[str]) -> int:
        total = 0
        for statement in statements:
            if isinstance(statement, EMITTING):
                total += 1
            elif isinstance(statement, ast.Repeat) and isinstance(statement.count, ast.Number):
                total += max(0, int(statement.count.value)) * least(statement.body, calling)
            elif isinstance(statement, ast.Call):
                key = statement.name.key
                entry = procedures.get(key)
                if entry is not None and key not in calling:  # recursion is refused where it is expanded
                    if key not in known:
                        known[key] = least(entry.definition.body, calling | {key})
                    total += known[key]
            if total > MAX_STEPS:
                break
        return total

    return least(body, frozenset())


def _bounded_depth(run: CompileContext, statement: ast.Call | ast.Repeat) -> None:
    """Refuse to expand one level deeper than :data:`MAX_EXPANSION_DEPTH`.

    Raises:
        ProgramError: At the CALL or REPEAT, naming the outermost expansions.
    """
    if len(run.context) >= MAX_EXPANSION_DEPTH:  # the message's origin names the outermost ones
        raise ProgramError(
            f"procedure calls and REPEAT blocks nest more than {MAX_EXPANSION_DEPTH} deep here; "
            "call fewer procedures from inside each other",
            statement.span,
        )


HANDLERS: dict[type, Handler] = {
    ast.ProcDef: register_procedure,
    ast.Call: expand_call,
    ast.Repeat: expand_repeat,
}
"""The handler of each statement type of this module (merged into the compiler's one table)."""
