"""OBSTACLE and OBSTACLE REMOVE: obstacles added to and removed from the scene."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.check.limits import MAX_OBSTACLES
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.settings import _positive
from cosmos.lang.compile.state import CompileState, frozen_map
from cosmos.lang.evaluate.evaluator import suggest
from cosmos.rotations import IDENTITY, readonly


def compile_obstacle(run: CompileContext, statement: ast.Obstacle, state: CompileState) -> CompileState:
    """Add an obstacle to the scene (an AddObstacle step)."""
    evaluator = run.evaluator_for(state)
    key = statement.name.key
    if key in state.obstacles:
        first = state.obstacles[key]
        raise ProgramError(
            f"an obstacle named '{statement.name.name}' is already in the scene "
            f"(line {first.line}); OBSTACLE REMOVE {statement.name.name} first",
            statement.name.span,
        )
    if len(state.obstacles) >= MAX_OBSTACLES:
        raise ProgramError(
            f"the workcell holds at most {MAX_OBSTACLES} obstacles at once, and "
            f"{len(state.obstacles)} are in the scene here; OBSTACLE REMOVE one first",
            statement.span,
        )
    clauses = {c.kind: c.value for c in statement.clauses if isinstance(c, ast.ValueClause)}
    at = evaluator.expect_position(clauses[ast.ClauseKind.AT], "AT")
    rotation = IDENTITY if at.rotation is None else at.rotation
    position = at.position
    radius = height = None
    size = None
    shape = plan.ObstacleShape(statement.shape.value.lower())

    def length(kind: ast.ClauseKind) -> float:
        value = evaluator.expect_scalar(clauses[kind], units.LENGTH, kind.value)
        _positive(value, clauses[kind].span, kind.value)
        return value

    if ast.ClauseKind.RADIUS in clauses:
        radius = length(ast.ClauseKind.RADIUS)
    if ast.ClauseKind.HEIGHT in clauses:
        height = length(ast.ClauseKind.HEIGHT)
        # AT is the centre of the cylinder's base; the plan holds its centre.
        position = readonly(position + rotation[:, 2] * height / 2)
    if ast.ClauseKind.SIZE in clauses:
        expr = clauses[ast.ClauseKind.SIZE]
        size = evaluator.expect_vector3(expr, units.LENGTH, "SIZE")
        if np.any(size <= 0):
            raise ProgramError("SIZE needs three positive lengths", expr.span)
    if ast.ClauseKind.NORMAL in clauses:
        expr = clauses[ast.ClauseKind.NORMAL]
        if at.rotation is not None:
            raise ProgramError("give the plane a NORMAL or an RPY, not both", expr.span)
        rotation = _rotation_with_z(evaluator.expect_vector3(expr, units.DIMENSIONLESS, "NORMAL"), expr.span)
    velocity = readonly(np.zeros(3))
    if ast.ClauseKind.MOVING in clauses:
        velocity = evaluator.expect_vector3(clauses[ast.ClauseKind.MOVING], units.SPEED, "MOVING")
    influence = None
    if ast.ClauseKind.INFLUENCE in clauses:
        influence = length(ast.ClauseKind.INFLUENCE)
    gain = 1.0
    if ast.ClauseKind.GAIN in clauses:
        gain = evaluator.expect_scalar(clauses[ast.ClauseKind.GAIN], units.DIMENSIONLESS, "GAIN")
        _positive(gain, clauses[ast.ClauseKind.GAIN].span, "GAIN")
    run.emit(
        [
            plan.AddObstacle(
                name=statement.name.name,
                shape=shape,
                position_world=readonly(position),
                rotation_world=readonly(rotation),
                radius_m=radius,
                height_m=height,
                size_m=size,
                velocity_world_mps=velocity,
                influence_m=influence,
                gain_scale=gain,
                span=statement.span,
                line=statement.span.line,
                statement=run.text_of(statement.span),
            )
        ]
    )
    return replace(state, obstacles=frozen_map({**state.obstacles, key: statement.span}))


def compile_remove_obstacle(
    run: CompileContext, statement: ast.RemoveObstacle, state: CompileState
) -> CompileState:
    """Remove an obstacle from the scene (a RemoveObstacle step)."""
    key = statement.name.key
    if key not in state.obstacles:
        raise ProgramError(
            f"no obstacle named '{statement.name.name}' is in the scene"
            f"{suggest(statement.name.name, state.obstacles)}",
            statement.name.span,
        )
    run.emit(
        [
            plan.RemoveObstacle(
                name=statement.name.name,
                span=statement.span,
                line=statement.span.line,
                statement=run.text_of(statement.span),
            )
        ]
    )
    return replace(state, obstacles=frozen_map({k: v for k, v in state.obstacles.items() if k != key}))


def _rotation_with_z(normal: np.ndarray, span: Span) -> np.ndarray:
    """A rotation whose z axis is ``normal`` (normalised)."""
    length = float(np.linalg.norm(normal))
    if not length > 0 or not math.isfinite(length):
        raise ProgramError("NORMAL needs a non-zero direction, like (0, 0, 1)", span)
    z = normal / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return readonly(np.column_stack([x, y, z]))


HANDLERS: dict[type, Handler] = {ast.Obstacle: compile_obstacle, ast.RemoveObstacle: compile_remove_obstacle}
"""The handler of each statement type of this module (merged into the compiler's one table)."""
