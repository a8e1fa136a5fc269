"""IF, WHILE, TRY and RETRY: blocks whose every branch is compiled, the executor choosing at run time.

Each branch is compiled ahead of the run into steps of its own, held by a plan
node (:class:`~cosmos.plan.Branch`, :class:`~cosmos.plan.Loop`,
:class:`~cosmos.plan.Attempt`, :class:`~cosmos.plan.Retry`). What a branch
leaves behind:

- names (LET, FRAME) and settings (SPEED, COMPLY) made inside a branch last
  until its END: after the block, those from before it are back;
- the held contact is the arm's, so every way out of a block must leave the
  same one (none, or the same CONTACT's): the statements after it are compiled
  once, for that contact. A WHILE pass ends with the contact it started with; a
  failure in a TRY leaves the arm held with no contact, so its ON FAIL part
  starts with none, and a RETRY must have the contact the TRY block started with.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.decisions import compile_decision, decision_frame
from cosmos.lang.compile.motion.conditions import require_gripper
from cosmos.lang.compile.state import WORLD, CompileState, HeldContact
from cosmos.plan.context import joined_context

DEFAULT_MAX_PASSES = 100
"""Passes a WHILE without MAX may make before it fails."""
MOST_PASSES = 10_000
"""The largest MAX a WHILE may give."""
MOST_RETRIES = 100
"""The largest count a RETRY may give."""


def compile_if(run: CompileContext, statement: ast.IfBlock, state: CompileState) -> CompileState:
    """Compile both branches of an IF into a :class:`~cosmos.plan.Branch`."""
    evaluator = run.evaluator_for(state)
    frame = decision_frame(statement.clauses, evaluator, run.text_of)
    condition = compile_decision(statement.condition, frame, evaluator, run.text_of)
    require_gripper(condition, state.tool)
    then_steps, then_state = run.block(statement.then_body, state)
    else_steps, else_state = run.block(statement.else_body, _carried(state, then_state))
    otherwise = "its ELSE branch" if statement.else_span is not None else "the way past it (no ELSE)"
    after = _merged(statement, state, [(then_state, "its IF branch"), (else_state, otherwise)], else_state)
    run.emit(
        [
            plan.Branch(
                condition,
                then_steps,
                else_steps,
                None if statement.else_span is None else statement.else_span.line,
                *_where(run, statement.span),
            )
        ]
    )
    return after


def compile_while(run: CompileContext, statement: ast.WhileBlock, state: CompileState) -> CompileState:
    """Compile a WHILE's body once into a :class:`~cosmos.plan.Loop`."""
    evaluator = run.evaluator_for(state)
    frame = decision_frame(statement.clauses, evaluator, run.text_of)
    condition = compile_decision(statement.condition, frame, evaluator, run.text_of)
    require_gripper(condition, state.tool)
    max_passes = DEFAULT_MAX_PASSES
    for clause in statement.clauses:
        if isinstance(clause, ast.ValueClause) and clause.kind is ast.ClauseKind.MAX:
            max_passes = _whole(run, state, clause.value, "MAX", MOST_PASSES)
    body, body_state = run.block(statement.body, state)
    if not any(isinstance(step, plan.Segment) for step in plan.all_steps(body)):
        raise ProgramError(
            "WHILE's statements do not move the arm or wait, so what it reads never changes "
            "from one pass to the next; give it a motion or a WAIT",
            statement.span,
        )
    if not _same_contact(state.contact, body_state.contact):
        raise ProgramError(
            f"a pass of this WHILE starts with {_held(state.contact)} and ends with "
            f"{_held(body_state.contact)}; every pass must start alike",
            statement.span,
        )
    run.emit([plan.Loop(condition, body, max_passes, *_where(run, statement.span))])
    return _carried(state, body_state)


def compile_try(run: CompileContext, statement: ast.TryBlock, state: CompileState) -> CompileState:
    """Compile a TRY block and its ON FAIL part into an :class:`~cosmos.plan.Attempt`."""
    body, body_state = run.block(statement.body, state)
    # A failure leaves the arm holding its pose with no force commanded: no contact is held.
    handler_start = replace(_carried(state, body_state), contact=None, contact_released_by=statement.span)
    run.attempts.append(state)
    try:
        handler, handler_state = run.block(statement.handler, handler_start)
    finally:
        run.attempts.pop()
    ends = [(body_state, "its TRY block")]
    if not (statement.handler and isinstance(statement.handler[-1], ast.Retry)):
        ends.append((handler_state, "its ON FAIL part"))
    after = _merged(statement, state, ends, handler_state)
    run.emit([plan.Attempt(body, handler, statement.on_fail_span.line, *_where(run, statement.span))])
    return after


def compile_retry(run: CompileContext, statement: ast.Retry, state: CompileState) -> CompileState:
    """Compile RETRY n into a :class:`~cosmos.plan.Retry` of the innermost TRY."""
    if not run.attempts:  # the checker keeps RETRY inside ON FAIL parts
        raise ProgramError("RETRY belongs in a TRY's ON FAIL part", statement.span)
    times = _whole(run, state, statement.count, "RETRY", MOST_RETRIES)
    start = run.attempts[-1]
    if not _same_contact(start.contact, state.contact):
        raise ProgramError(
            f"RETRY runs the TRY block again with {_held(state.contact)}, but the block starts "
            f"with {_held(start.contact)}: make the same contact before RETRY (a failure releases it)",
            statement.span,
        )
    run.emit([plan.Retry(times, *_where(run, statement.span))])
    return state


# ------------------------------------------------------------------ helpers


def _where(run: CompileContext, span: Span) -> tuple[Span, int, str, str]:
    """(span, line, statement text, context) of a node, as a segment has them."""
    return span, span.line, run.text_of(span), joined_context(run.context)


def _whole(run: CompileContext, state: CompileState, expr: ast.Expr, what: str, most: int) -> int:
    """A whole number from 1 to ``most``."""
    value = run.evaluator_for(state).expect_scalar(expr, units.DIMENSIONLESS, what)
    if not math.isfinite(value) or value != int(value) or not 1 <= value <= most:
        raise ProgramError(
            f"{what} needs a whole number from 1 to {most}, not {run.text_of(expr.span)}", expr.span
        )
    return int(value)


def _carried(before: CompileState, later: CompileState) -> CompileState:
    """``before`` with what ``later`` leaves to what follows: counters, procedures called, last frame."""
    return replace(
        before,
        statement_count=later.statement_count,
        segment_count=later.segment_count,
        called=later.called,
        last_frame=later.last_frame,
    )


def _merged(
    statement: ast.IfBlock | ast.TryBlock,
    before: CompileState,
    ends: list[tuple[CompileState, str]],
    compiled_last: CompileState,
) -> CompileState:
    """The state after a block: ``before``'s names and settings, the one contact every way out leaves.

    Args:
        statement: The IF or TRY.
        before: The state before it.
        ends: The state at each way out of it, and how to name that way.
        compiled_last: The state after the branch compiled last (its counters are the latest).

    Raises:
        ProgramError: Two ways out of the block leave different contacts.
    """
    first, first_label = ends[0]
    for other, label in ends[1:]:
        if not _same_contact(first.contact, other.contact):
            keyword = "IF" if isinstance(statement, ast.IfBlock) else "TRY"
            raise ProgramError(
                f"{first_label} ends with {_held(first.contact)}, {label} with {_held(other.contact)}; "
                f"what follows this {keyword} is compiled once, so end every branch alike "
                "(a MOVE releases a contact)",
                statement.span,
            )
    same_frame = all(np.allclose(other.last_frame.rotation, first.last_frame.rotation) for other, _ in ends)
    return replace(
        _carried(before, compiled_last),
        contact=first.contact,
        contact_released_by=first.contact_released_by,
        last_frame=first.last_frame if same_frame else WORLD,
    )


def _same_contact(a: HeldContact | None, b: HeldContact | None) -> bool:
    if a is b:
        return True
    if a is None or b is None:
        return False
    return (
        bool(np.allclose(a.direction_world, b.direction_world))
        and a.force_n == b.force_n
        and bool(np.allclose(a.frame.rotation, b.frame.rotation))
    )


def _held(contact: HeldContact | None) -> str:
    if contact is None:
        return "no contact held"
    return f"the contact of line {contact.span.line} held"


HANDLERS: dict[type, Handler] = {
    ast.IfBlock: compile_if,
    ast.WhileBlock: compile_while,
    ast.TryBlock: compile_try,
    ast.Retry: compile_retry,
}
"""The handler of each statement type of this module (merged into the compiler's one table)."""
