"""Conditions of IF and WHILE: what the arm senses when the statement is reached.

A decision reads FORCE and TORQUE as an UNTIL does (axes of its frame), and
also ``POSITION X`` (the tool point's coordinate along an axis of the frame,
from its origin), ``DISTANCE`` (of the tool point from the frame's origin) and
the ending of the statement run last (``LAST FAILED``, ``LAST STOPPED``). The
frame is ``IN frame`` on the IF or WHILE, else the world.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.compile.motion.conditions import compile_condition
from cosmos.lang.compile.state import TaskFrame
from cosmos.lang.evaluate.evaluator import Evaluator
from cosmos.lang.evaluate.values import FrameValue
from cosmos.rotations import IDENTITY, FloatArray, readonly, signed_column

_ENDINGS = {ast.LastKind.FAILED: plan.Ending.FAILED, ast.LastKind.STOPPED: plan.Ending.STOPPED}


@dataclass(frozen=True, eq=False)
class DecisionFrame:
    """The frame a decision reads its axes in.

    Attributes:
        name: As written (``"world"`` without IN).
        origin_world: Its origin [m], world, (3,).
        rotation: Frame to world, (3, 3).
        given: Whether IN named it.
    """

    name: str
    origin_world: FloatArray
    rotation: FloatArray
    given: bool


WORLD_DECISION = DecisionFrame("world", readonly(np.zeros(3)), IDENTITY, False)


def decision_frame(
    clauses: tuple[ast.Clause, ...], evaluator: Evaluator, text_of: Callable[[Span], str]
) -> DecisionFrame:
    """The frame of an IF or WHILE: its IN clause's, else the world.

    Raises:
        ProgramError: IN names something that is not a frame.
    """
    for clause in clauses:
        if isinstance(clause, ast.ValueClause) and clause.kind is ast.ClauseKind.IN:
            value = evaluator.evaluate(clause.value)
            if not isinstance(value, FrameValue):
                raise ProgramError(
                    f"IN takes a frame, like IN hole; {text_of(clause.value.span)} is not one",
                    clause.value.span,
                )
            rotation = IDENTITY if value.rotation is None else value.rotation
            return DecisionFrame(text_of(clause.value.span), value.position, rotation, True)
    return WORLD_DECISION


def compile_decision(
    condition: ast.Condition, frame: DecisionFrame, evaluator: Evaluator, text_of: Callable[[Span], str]
) -> plan.Condition:
    """The plan's condition of an IF or WHILE.

    Raises:
        ProgramError: A unit mismatch, an axis that does not fit the quantity, a
            DISTANCE without a frame, a magnitude compared so that it always or never holds.
    """
    if isinstance(condition, ast.AllOf):
        return plan.AllOf(tuple(compile_decision(c, frame, evaluator, text_of) for c in condition.items))
    if isinstance(condition, ast.AnyOf):
        return plan.AnyOf(tuple(compile_decision(c, frame, evaluator, text_of) for c in condition.items))
    if isinstance(condition, ast.LastOutcome):
        return plan.LastOutcome(_ENDINGS[condition.kind], text_of(condition.span), condition.span)
    if condition.sensed is ast.Sensed.POSITION:
        return _position(condition, frame, evaluator, text_of)
    if condition.sensed is ast.Sensed.DISTANCE:
        return _distance(condition, frame, evaluator, text_of)
    return compile_condition(condition, TaskFrame(frame.name, frame.rotation), evaluator, text_of)


def _position(
    condition: ast.Comparison, frame: DecisionFrame, evaluator: Evaluator, text_of: Callable[[Span], str]
) -> plan.Comparison:
    direction = condition.direction
    assert direction is not None  # the grammar gives POSITION an axis
    if direction.axis.is_rotation:
        raise ProgramError(
            f"POSITION is read along X, Y or Z, not about {direction.axis.name}", direction.span
        )
    value = evaluator.expect_scalar(condition.value, units.LENGTH, f"POSITION {direction.axis.name}")
    axis_world = signed_column(frame.rotation, direction.axis.value, 1)[0]
    return plan.Comparison(
        plan.Quantity.POSITION_ALONG,
        axis_world,
        plan.CompareOp(condition.op),
        value,
        text_of(condition.span),
        condition.span,
        frame.origin_world,
    )


def _distance(
    condition: ast.Comparison, frame: DecisionFrame, evaluator: Evaluator, text_of: Callable[[Span], str]
) -> plan.Comparison:
    if not frame.given:
        raise ProgramError(
            "DISTANCE in IF and WHILE is measured from a frame's origin: name it, "
            "as in IF DISTANCE < 10 mm IN hole",
            condition.span,
        )
    value = evaluator.expect_scalar(condition.value, units.LENGTH, "DISTANCE")
    op = plan.CompareOp(condition.op)
    below = op in (plan.CompareOp.LT, plan.CompareOp.LE)
    if (below and value <= 0) or (not below and value < 0):
        holds = "can never hold" if below else "always holds"
        raise ProgramError(
            f"DISTANCE {op.value} {value:g} {holds}: a distance is never below 0", condition.span
        )
    return plan.Comparison(
        plan.Quantity.DISTANCE_FROM,
        None,
        op,
        value,
        text_of(condition.span),
        condition.span,
        frame.origin_world,
    )
