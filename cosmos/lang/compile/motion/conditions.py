"""UNTIL conditions: from syntax to the plan's condition tree, with their checks."""

from __future__ import annotations

from collections.abc import Callable

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.hand.tool import Tool
from cosmos.lang import ast, units
from cosmos.lang.check import limits
from cosmos.lang.compile.state import TaskFrame
from cosmos.lang.evaluate.evaluator import Evaluator
from cosmos.rotations import signed_column

_QUANTITY_DIM = {
    plan.Quantity.FORCE: units.FORCE,
    plan.Quantity.FORCE_ALONG: units.FORCE,
    plan.Quantity.TORQUE: units.TORQUE,
    plan.Quantity.TORQUE_ABOUT: units.TORQUE,
    plan.Quantity.DISTANCE: units.LENGTH,
    plan.Quantity.FINGER_FORCE: units.FORCE,
}
_MAGNITUDES = (plan.Quantity.FORCE, plan.Quantity.TORQUE, plan.Quantity.DISTANCE, plan.Quantity.FINGER_FORCE)
_OPS = {op.value: op for op in plan.CompareOp}
"""CompareOp by its text (``plan.CompareOp(text)`` for the texts the grammar gives)."""
_DISTANCE = plan.Quantity.DISTANCE
_FORCE = plan.Quantity.FORCE
_TORQUE = plan.Quantity.TORQUE
_FORCE_ALONG = plan.Quantity.FORCE_ALONG
_TORQUE_ABOUT = plan.Quantity.TORQUE_ABOUT
_SENSED_DISTANCE = ast.Sensed.DISTANCE
_SENSED_FORCE = ast.Sensed.FORCE
_SENSED_FINGER = ast.Sensed.FINGER
_FINGER_FORCE = plan.Quantity.FINGER_FORCE
_BELOW = (plan.CompareOp.LT, plan.CompareOp.LE)
_NUMBER = ast.Number


def compile_condition(
    condition: ast.Condition,
    frame: TaskFrame,
    evaluator: Evaluator,
    text_of: Callable[[Span], str],
) -> plan.Condition:
    """The plan's condition for an UNTIL; axes are read in the statement's task frame.

    Raises:
        ProgramError: A unit mismatch, FORCE about a rotation axis, or a magnitude
            compared so that the condition always or never holds.
    """
    if isinstance(condition, ast.AllOf):
        return plan.AllOf(tuple(compile_condition(c, frame, evaluator, text_of) for c in condition.items))
    if isinstance(condition, ast.AnyOf):
        return plan.AnyOf(tuple([compile_condition(c, frame, evaluator, text_of) for c in condition.items]))
    if isinstance(condition, ast.LastOutcome):
        raise ProgramError(
            f"{text_of(condition.span)} is read by IF and WHILE; UNTIL ends a statement on what it senses",
            condition.span,
        )
    if condition.sensed is ast.Sensed.POSITION:
        raise ProgramError(
            "POSITION is read by IF and WHILE; in UNTIL use DISTANCE (from where the statement started)",
            condition.span,
        )
    quantity, direction_world = _quantity(condition, frame)
    dim = _QUANTITY_DIM[quantity]
    value_expr = condition.value
    value: float | None = None
    if type(value_expr) is _NUMBER:  # the usual case: no name needed unless there is an error
        value, value_dim = evaluator.number_value(value_expr)
        if value_dim is not None and value_dim != dim:
            value = None
    if value is None:
        value = evaluator.expect_scalar(value_expr, dim, _name(condition, text_of))
    problem = limits.scalar_problem(_name(condition, text_of), dim, value, text_of(value_expr.span))
    if problem is not None:
        raise ProgramError(f"UNTIL {problem}", value_expr.span)
    op = _OPS.get(condition.op) or plan.CompareOp(condition.op)
    if quantity in _MAGNITUDES:
        _check_magnitude(condition, op, value, text_of)
    return plan.Comparison(quantity, direction_world, op, value, text_of(condition.span), condition.span)


def _name(condition: ast.Comparison, text_of: Callable[[Span], str]) -> str:
    """What a comparison senses, as written (``"FORCE Z"``), for messages."""
    name: str = condition.sensed.value
    if condition.direction is not None:
        name += f" {text_of(condition.direction.span)}"
    return name


def _quantity(condition: ast.Comparison, frame: TaskFrame) -> tuple[plan.Quantity, plan.FloatArray | None]:
    direction = condition.direction
    sensed = condition.sensed
    if sensed is _SENSED_DISTANCE:
        return _DISTANCE, None
    if sensed is _SENSED_FINGER:
        return _FINGER_FORCE, None
    if direction is None:
        if sensed is _SENSED_FORCE:
            return _FORCE, None
        return _TORQUE, None
    axis = direction.axis.value
    if sensed is _SENSED_FORCE:
        if direction.axis.is_rotation:
            raise ProgramError(
                f"FORCE is measured along X, Y or Z; for the moment about {direction.axis.name} "
                f"write TORQUE {direction.axis.name}",
                direction.span,
            )
        return _FORCE_ALONG, signed_column(frame.rotation, axis, direction.sign)[0]
    return _TORQUE_ABOUT, signed_column(frame.rotation, axis % 3, direction.sign)[0]


def _check_magnitude(
    condition: ast.Comparison, op: plan.CompareOp, value: float, text_of: Callable[[Span], str]
) -> None:
    """A magnitude is never negative: refuse comparisons that always or never hold."""
    below = op in _BELOW
    if (below and value <= 0) or (not below and value < 0):
        name = _name(condition, text_of)
    if below and value <= 0:
        raise ProgramError(
            f"{name} {op.value} {value:g} can never hold: {name} is a magnitude, never below 0"
            + (f"; to test a component write {name} Z {op.value} ..." if name in _COMPONENTS else ""),
            condition.span,
        )
    if not below and value < 0:
        raise ProgramError(
            f"{name} {op.value} {value:g} always holds: {name} is a magnitude, never below 0"
            + (f"; to test a component write {name} Z {op.value} ..." if name in _COMPONENTS else ""),
            condition.span,
        )


_COMPONENTS = ("FORCE", "TORQUE")
"""The magnitudes that have components (FORCE Z, TORQUE RZ)."""


def require_gripper(condition: plan.Condition, tool: str) -> None:
    """FINGER FORCE reads the gripper's pads: refuse it when the hand is the peg.

    Raises:
        ProgramError: At the first FINGER FORCE, when ``tool`` is not the gripper.
    """
    if tool == Tool.GRIPPER.value:
        return
    for comparison in comparisons(condition):
        if comparison.quantity is _FINGER_FORCE:
            raise ProgramError(
                "FINGER FORCE reads the gripper's finger pads, and this program's tool is the peg; "
                "choose the gripper first with TOOL GRIPPER",
                comparison.span,
            )


def comparisons(condition: plan.Condition) -> list[plan.Comparison]:
    """Every comparison in a condition tree."""
    if isinstance(condition, plan.Comparison):
        return [condition]
    if isinstance(condition, plan.LastOutcome):
        return []
    return [c for term in condition.terms for c in comparisons(term)]


def holds_at_start(condition: plan.Condition, force_expected: bool) -> plan.Comparison | None:
    """A comparison that already holds when the statement starts, if one decides it.

    At the start the distance travelled is 0 and, unless a contact is held, the
    sensed force and moment are about 0.
    """
    if isinstance(condition, plan.AnyOf):
        for term in condition.terms:
            found = holds_at_start(term, force_expected)
            if found is not None:
                return found
        return None
    if isinstance(condition, plan.AllOf):
        found_all = [holds_at_start(term, force_expected) for term in condition.terms]
        return found_all[0] if found_all and all(found_all) else None
    if isinstance(condition, plan.LastOutcome):  # not in UNTIL (refused when compiled)
        return None
    below = condition.op in _BELOW
    if condition.quantity is _DISTANCE and below:
        return condition
    if (condition.quantity is _FORCE or condition.quantity is _TORQUE) and below:
        return None if force_expected else condition
    return None
