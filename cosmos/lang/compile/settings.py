"""SPEED, LET, FRAME and COMPLY: the statements that change the compile state only.

They emit no steps: SPEED sets the default speed, LET and FRAME bind a name,
COMPLY sets (or, without axes, clears) the compliance of task axes.
"""

from __future__ import annotations

import math
from dataclasses import replace

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.state import NO_COMPLIANCE, AxisCompliance, CompileState
from cosmos.lang.evaluate.values import Binding, BindingKind

_LET = BindingKind.LET
_FRAME = BindingKind.FRAME
_STIFFNESS = ast.ClauseKind.STIFFNESS
_DAMPING = ast.ClauseKind.DAMPING


def compile_speed(run: CompileContext, statement: ast.SetSpeed, state: CompileState) -> CompileState:
    """Set the default speed of the motion statements that follow."""
    speed = run.evaluator_for(state).expect_scalar(statement.value, units.SPEED, "SPEED")
    _positive(speed, statement.value.span, "SPEED")
    return replace(state, default_speed_mps=speed)


def compile_limit(run: CompileContext, statement: ast.SetLimit, state: CompileState) -> CompileState:
    """Set the free-motion force limit of the protective stop for the statements that follow."""
    force = run.evaluator_for(state).expect_scalar(statement.value, units.FORCE, "LIMIT FORCE")
    _positive(force, statement.value.span, "LIMIT FORCE")
    return replace(state, force_limit_n=force)


def compile_definition(
    run: CompileContext, statement: ast.Let | ast.FrameDef, state: CompileState
) -> CompileState:
    """Bind a LET value or a FRAME to its name."""
    evaluator = run.evaluator_for(state)
    key = statement.name.key
    previous = state.names.get(key)
    if previous is not None and previous.kind is BindingKind.FIXTURE:
        run.warn(
            f"'{statement.name.name}' hides the workcell fixture of that name from here on",
            statement.name.span,
        )
    if isinstance(statement, ast.Let):
        value = evaluator.evaluate(statement.value)
        kind = _LET
    else:
        value = evaluator.expect_position(statement.value, "FRAME")
        kind = _FRAME
    return state.bind(key, Binding(value, kind, statement.name.span))


def compile_comply(run: CompileContext, statement: ast.Comply, state: CompileState) -> CompileState:
    """Set the compliance of the given task axes; COMPLY with no axes clears it."""
    if not statement.axes:
        return replace(state, compliance=NO_COMPLIANCE)
    evaluator = run.evaluator_for(state)
    clauses = {c.kind: c for c in statement.clauses if type(c) is ast.ValueClause}
    rotations = {ref.axis.is_rotation for ref in statement.axes}
    if len(rotations) > 1 and clauses:
        raise ProgramError(
            "one STIFFNESS or DAMPING cannot serve both translation and rotation axes "
            "(N/m against Nm/rad); write one COMPLY for X Y Z and another for RX RY RZ",
            statement.span,
        )
    rotation = rotations.pop()
    stiffness = 0.0
    damping: float | None = None
    if _STIFFNESS in clauses:
        expr = clauses[_STIFFNESS].value
        dim = units.ROTATIONAL_STIFFNESS if rotation else units.STIFFNESS
        stiffness = evaluator.expect_scalar(expr, dim, "STIFFNESS")
        _not_negative(stiffness, expr.span, "STIFFNESS")
    if _DAMPING in clauses:
        expr = clauses[_DAMPING].value
        dim = units.ROTATIONAL_DAMPING if rotation else units.DAMPING
        damping = evaluator.expect_scalar(expr, dim, "DAMPING")
        _not_negative(damping, expr.span, "DAMPING")
    compliance = list(state.compliance)
    setting = AxisCompliance(stiffness, damping, statement.span)  # immutable: shared by the axes
    for ref in statement.axes:
        compliance[ref.axis.value] = setting
    return replace(state, compliance=tuple(compliance))


def _positive(value: float, span: Span, what: str) -> None:
    if not value > 0 or not math.isfinite(value):
        raise ProgramError(f"{what} must be a positive number, not {value:g}", span)


def _not_negative(value: float, span: Span, what: str) -> None:
    if not value >= 0 or not math.isfinite(value):
        raise ProgramError(f"{what} cannot be negative ({value:g})", span)


HANDLERS: dict[type, Handler] = {
    ast.SetSpeed: compile_speed,
    ast.SetLimit: compile_limit,
    ast.Let: compile_definition,
    ast.FrameDef: compile_definition,
    ast.Comply: compile_comply,
}
"""The handler of each statement type of this module (merged into the compiler's one table)."""
