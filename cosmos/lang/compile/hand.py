"""TOOL and OBJECT: the hand on the flange and the objects of the workcell.

Both describe the workcell the run is built with, once, before anything moves: the plant
mounts the gripper and adds each object as a free body at the start
(:class:`cosmos.execution.session.Session`). So both must come before the first motion
statement, and an object's pose, size and mass are checked here against the workcell:
its footprint on the table, its base on or above the table top, a mass the arm can carry.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.hand.tool import DEFAULT_GRIP_FORCE_N, GRIPPER, Tool, gripper_of, tool_named
from cosmos.hand.work_object import (
    DEFAULT_OBJECT_FRICTION,
    SHIPPED_BLOCKS,
    SHIPPED_OBJECTS,
    SHIPPED_PEG,
    ObjectShape,
    WorkObject,
)
from cosmos.lang import ast, units
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.state import CompileState
from cosmos.lang.evaluate.evaluator import suggest
from cosmos.rotations import IDENTITY, matrix_to_quaternion

TABLE_X_M = (0.30, 0.94)
TABLE_Y_M = (-0.60, 0.40)
TABLE_TOP_Z_M = 0.20
"""The table top of both arms' workcells (``cosmos/models/*/scene.xml``, ``table_top``) [m]."""
HIGHEST_BASE_M = 0.60
"""An object's base may start at most this high above the world origin [m] (it falls from there)."""
MAX_OBJECT_MASS_KG = 2.5
"""The PUMA 560's rated payload [kg] (Unimation's datasheet); heavier objects are refused."""
SMALLEST_SIZE_M = 0.005
"""An object's smallest edge or diameter [m]: thinner slivers tunnel through contacts."""
LARGEST_SIZE_M = 0.30
"""Its largest edge [m]."""
_EPS_M = 1e-3
_SHIPPED = SHIPPED_OBJECTS
_SHIPPED_TEXT = {
    SHIPPED_PEG.name: " (the gripper's workcell has it: the peg in its holder)",
    **{b.name: " (the gripper's workcell has it: one of its blocks)" for b in SHIPPED_BLOCKS},
}


def compile_tool(run: CompileContext, statement: ast.ChooseTool, state: CompileState) -> CompileState:
    """Choose the hand: ``TOOL PEG`` (the default) or ``TOOL GRIPPER``, before any motion."""
    tool = tool_named(statement.name.name)
    if tool is None:
        names = ", ".join(t.value.upper() for t in Tool)
        raise ProgramError(
            f"TOOL {statement.name.name}: no such tool; the workcell has {names}", statement.name.span
        )
    _before_motion(state, statement.span, "TOOL")
    if tool is Tool.GRIPPER:
        if state.tool == Tool.GRIPPER.value:  # chosen already (twice, or a REPL's --tool gripper)
            return state
        # The gripper's workcell: the peg in its holder beside the hole, and the blocks, come with it.
        return replace(state, tool=tool.value, objects=(*_SHIPPED, *state.objects))
    return replace(state, tool=tool.value, objects=tuple(o for o in state.objects if o not in _SHIPPED))


def compile_object(run: CompileContext, statement: ast.DeclareObject, state: CompileState) -> CompileState:
    """Declare a free object of the workcell (module docstring); AT is the centre of its base."""
    _before_motion(state, statement.span, "OBJECT")
    name = statement.name
    if any(item.name.casefold() == name.key for item in state.objects):
        shipped = _SHIPPED_TEXT.get(name.key, "")
        raise ProgramError(f"an object named '{name.name}' is already in the workcell{shipped}", name.span)
    shape = ObjectShape(statement.shape.lower())  # the grammar allows BOX and CYLINDER
    clauses = {c.kind: c for c in statement.clauses if isinstance(c, ast.ValueClause)}
    evaluator = run.evaluator_for(state)

    def required(kind: ast.ClauseKind, example: str) -> ast.ValueClause:
        if kind not in clauses:
            raise ProgramError(f"OBJECT {name.name} needs {kind.value} ({example})", statement.span)
        return clauses[kind]

    if shape is ObjectShape.BOX:
        size_clause = required(ast.ClauseKind.SIZE, "SIZE (40 mm, 30 mm, 50 mm)")
        size = evaluator.expect_vector3(size_clause.value, units.LENGTH, "SIZE")
        _sizes(size, size_clause.value.span)
        half = (size[0] / 2, size[1] / 2, size[2] / 2)
    else:
        radius_clause = required(ast.ClauseKind.RADIUS, "RADIUS 10 mm")
        height_clause = required(ast.ClauseKind.HEIGHT, "HEIGHT 80 mm")
        radius = evaluator.expect_scalar(radius_clause.value, units.LENGTH, "RADIUS")
        height = evaluator.expect_scalar(height_clause.value, units.LENGTH, "HEIGHT")
        _sizes(np.array([2 * radius]), radius_clause.value.span)
        _sizes(np.array([height]), height_clause.value.span)
        half = (radius, radius, height / 2)
    mass_clause = required(ast.ClauseKind.MASS, "MASS 0.5 kg")
    mass = evaluator.expect_scalar(mass_clause.value, units.MASS, "MASS")
    if not 0 < mass <= MAX_OBJECT_MASS_KG or not math.isfinite(mass):
        raise ProgramError(
            f"MASS must be more than 0 and at most {MAX_OBJECT_MASS_KG:g} kg (the arm's rated payload), "
            f"not {mass:g} kg",
            mass_clause.span,
        )
    friction = DEFAULT_OBJECT_FRICTION
    if ast.ClauseKind.FRICTION in clauses:
        friction_clause = clauses[ast.ClauseKind.FRICTION]
        friction = evaluator.expect_scalar(friction_clause.value, units.DIMENSIONLESS, "FRICTION")
        if not 0 < friction <= 2 or not math.isfinite(friction):
            raise ProgramError(
                f"FRICTION is a coefficient between 0 and 2, not {friction:g}", friction_clause.span
            )
    at_clause = required(ast.ClauseKind.AT, "AT table + (0, 0, 0)")
    at = evaluator.expect_position(at_clause.value, "AT")
    rotation = IDENTITY if at.rotation is None else at.rotation
    base = np.asarray(at.position, dtype=float)
    _in_workcell(base, at_clause.span)
    centre = base + np.array([0.0, 0.0, half[2]])  # the base rests on what is below it
    quat = matrix_to_quaternion(rotation)
    base_in_body = np.asarray(rotation).T @ np.array([0.0, 0.0, -half[2]])
    item = WorkObject(
        name=name.name,
        shape=shape,
        half_extents_m=(float(half[0]), float(half[1]), float(half[2])),
        mass_kg=float(mass),
        position_m=(float(centre[0]), float(centre[1]), float(centre[2])),
        quat_wxyz=(float(quat[0]), float(quat[1]), float(quat[2]), float(quat[3])),
        friction=float(friction),
        base_in_body_m=(float(base_in_body[0]), float(base_in_body[1]), float(base_in_body[2])),
    )
    return replace(state, objects=(*state.objects, item))


def _before_motion(state: CompileState, span: Span, what: str) -> None:
    if state.statement_count:
        raise ProgramError(
            f"{what} must come before the first motion statement: "
            "it describes the workcell the run starts in",
            span,
        )


def _sizes(sizes: np.ndarray, span: Span) -> None:
    if not np.all(np.isfinite(sizes)) or np.any(sizes < SMALLEST_SIZE_M) or np.any(sizes > LARGEST_SIZE_M):
        raise ProgramError(
            f"an object's sizes must be between {SMALLEST_SIZE_M * 1e3:g} mm and "
            f"{LARGEST_SIZE_M * 1e3:g} mm, "
            f"not {', '.join(f'{s * 1e3:g} mm' for s in sizes)}",
            span,
        )


def _in_workcell(base: np.ndarray, span: Span) -> None:
    x, y, z = base
    on_table = TABLE_X_M[0] <= x <= TABLE_X_M[1] and TABLE_Y_M[0] <= y <= TABLE_Y_M[1]
    if not on_table or not TABLE_TOP_Z_M - _EPS_M <= z <= HIGHEST_BASE_M:
        raise ProgramError(
            f"the object's base at ({x * 1e3:.0f}, {y * 1e3:.0f}, {z * 1e3:.0f}) mm is not over the table: "
            f"x {TABLE_X_M[0] * 1e3:.0f} .. {TABLE_X_M[1] * 1e3:.0f} mm, y {TABLE_Y_M[0] * 1e3:.0f} .. "
            f"{TABLE_Y_M[1] * 1e3:.0f} mm, from its top (z {TABLE_TOP_Z_M * 1e3:.0f} mm) up to "
            f"{HIGHEST_BASE_M * 1e3:.0f} mm",
            span,
        )


def compile_grasp(run: CompileContext, statement: ast.Grasp, state: CompileState) -> CompileState:
    """GRASP: a hand step closing the gripper at a grip force the drive can hold."""
    _needs_gripper(state, statement.span, "GRASP")
    name = None
    if statement.object_name is not None:
        ident = statement.object_name
        known = {item.name.casefold(): item.name for item in state.objects}
        if ident.key not in known:
            raise ProgramError(f"GRASP {ident.name}: no such object{suggest(ident.name, known)}", ident.span)
        name = known[ident.key]
    clauses = {c.kind: c for c in statement.clauses if isinstance(c, ast.ValueClause)}
    evaluator = run.evaluator_for(state)
    force = DEFAULT_GRIP_FORCE_N
    if ast.ClauseKind.FORCE in clauses:
        clause = clauses[ast.ClauseKind.FORCE]
        force = evaluator.expect_scalar(clause.value, units.FORCE, "GRASP FORCE")  # checked: limits.py
        hand = gripper_of(state.robot)
        if force > hand.grip_force_max_n:
            raise ProgramError(
                f"GRASP FORCE {force:g} N is more than the {state.robot}'s gripper holds "
                f"({hand.grip_force_max_n:g} N)",
                clause.value.span,
            )
    width = None
    if ast.ClauseKind.WIDTH in clauses:
        clause = clauses[ast.ClauseKind.WIDTH]
        width = evaluator.expect_scalar(clause.value, units.LENGTH, "WIDTH")
        stroke = gripper_of(state.robot).stroke_m
        if not 0 < width < stroke:
            raise ProgramError(
                f"WIDTH is what the fingers close to, between 0 and the {stroke * 1e3:g} mm "
                f"stroke, not {width * 1e3:g} mm",
                clause.span,
            )
    run.emit([_hand_step(run, plan.HandAction.GRASP, name, force, width, statement.span)])
    return state


def compile_release(run: CompileContext, statement: ast.Release, state: CompileState) -> CompileState:
    """RELEASE: a hand step opening the gripper."""
    _needs_gripper(state, statement.span, "RELEASE")
    run.emit([_hand_step(run, plan.HandAction.RELEASE, None, GRIPPER.grip_force_min_n, None, statement.span)])
    return state


def _hand_step(
    run: CompileContext,
    action: plan.HandAction,
    name: str | None,
    force: float,
    width: float | None,
    span: Span,
) -> plan.HandStep:
    return plan.HandStep(action, name, force, width, span, span.line, run.text_of(span))


def _needs_gripper(state: CompileState, span: Span, what: str) -> None:
    if state.tool != Tool.GRIPPER.value:
        raise ProgramError(f"{what} needs the gripper: write TOOL GRIPPER before the first motion", span)


HANDLERS: dict[type, Handler] = {
    ast.ChooseTool: compile_tool,
    ast.DeclareObject: compile_object,
    ast.Grasp: compile_grasp,
    ast.Release: compile_release,
}
