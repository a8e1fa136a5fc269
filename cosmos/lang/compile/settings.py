"""SPEED, LET, FRAME, COMPLY, ORIENTATION, POSTURE, ROBOT: statements that change the compile state only.

They emit no steps: SPEED sets the default speed, LET and FRAME bind a name,
COMPLY sets (or, without axes, clears) the compliance of task axes, ORIENTATION
FREE / HELD and POSTURE set what the null space does (seed section 4), ROBOT chooses the arm.
"""

from __future__ import annotations

import math
from dataclasses import replace

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.state import NO_COMPLIANCE, AxisCompliance, CompileState
from cosmos.lang.evaluate.values import Binding, BindingKind, Vec
from cosmos.robots import ROBOTS

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


def compile_orientation(
    run: CompileContext, statement: ast.SetOrientation, state: CompileState
) -> CompileState:
    """ORIENTATION FREE / HELD: whether the MOVE and WAIT that follow control the tool's orientation."""
    return replace(state, orientation_free=statement.free)


def compile_posture(run: CompileContext, statement: ast.SetPosture, state: CompileState) -> CompileState:
    """POSTURE q | name | NONE: the joint configuration the null space returns the arm to."""
    value = statement.value
    if value is None:
        return replace(state, posture=None)
    if type(value) is ast.Name and value.name.casefold() not in state.names:
        key = value.name.casefold()
        if key not in plan.NAMED_POSTURES:
            known = ", ".join(plan.NAMED_POSTURES)
            raise ProgramError(
                f"POSTURE names no known pose '{value.name}' (known: {known}; or joint angles "
                "like (0 deg, 45 deg, -180 deg, 0 deg, -45 deg, 180 deg))",
                value.span,
            )
        return replace(state, posture=plan.Posture(None, key, statement.span))
    evaluator = run.evaluator_for(state)
    angles = evaluator.evaluate(value)
    if not isinstance(angles, Vec) or angles.dim != units.ANGLE:
        raise ProgramError(
            "POSTURE needs one angle per joint with its unit, like (0 deg, 45 deg, -180 deg, 0 deg, "
            f"-45 deg, 180 deg), or a named pose ({', '.join(plan.NAMED_POSTURES)}) or NONE; "
            f"{run.text_of(value.span)} is not that",
            value.span,
        )
    if not all(math.isfinite(a) for a in angles.values):
        raise ProgramError("POSTURE's angles must be finite numbers", value.span)
    arm = ROBOTS[state.robot]
    if len(angles.values) != arm.dof:
        raise ProgramError(
            f"POSTURE gives {len(angles.values)} joint angles; the {arm.title} has {arm.dof} joints",
            value.span,
        )
    return replace(state, posture=plan.Posture(tuple(angles.values), None, statement.span))


def _positive(value: float, span: Span, what: str) -> None:
    if not value > 0 or not math.isfinite(value):
        raise ProgramError(f"{what} must be a positive number, not {value:g}", span)


def _not_negative(value: float, span: Span, what: str) -> None:
    if not value >= 0 or not math.isfinite(value):
        raise ProgramError(f"{what} cannot be negative ({value:g})", span)


def compile_robot(run: CompileContext, statement: ast.ChooseRobot, state: CompileState) -> CompileState:
    """Choose the arm the program runs on: the first statement, naming an arm of the workcell."""
    name = statement.name
    robot = ROBOTS.get(name.key)
    if robot is None:
        raise ProgramError(f"ROBOT {name.name}: no such arm; the workcell has {', '.join(ROBOTS)}", name.span)
    if state.robot_fixed and robot.name != state.robot:
        raise ProgramError(f"ROBOT {name.name}: this run is on the {state.robot} (--robot)", name.span)
    if state.statements:
        raise ProgramError(
            "ROBOT must be the program's first statement: it chooses the arm the whole program runs on",
            statement.span,
        )
    return replace(state, robot=robot.name)


HANDLERS: dict[type, Handler] = {
    ast.ChooseRobot: compile_robot,
    ast.SetSpeed: compile_speed,
    ast.SetLimit: compile_limit,
    ast.Let: compile_definition,
    ast.FrameDef: compile_definition,
    ast.Comply: compile_comply,
    ast.SetOrientation: compile_orientation,
    ast.SetPosture: compile_posture,
}
"""The handler of each statement type of this module (merged into the compiler's one table)."""
