"""UNTIL conditions: from syntax to the plan's condition tree, with their checks."""

from __future__ import annotations

from collections.abc import Callable

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.rotations import readonly
from cosmos.lang.state import TaskFrame
from cosmos.lang.values import Evaluator

_QUANTITY_DIM = {
    plan.Quantity.FORCE: units.FORCE,
    plan.Quantity.FORCE_ALONG: units.FORCE,
    plan.Quantity.TORQUE: units.TORQUE,
    plan.Quantity.TORQUE_ABOUT: units.TORQUE,
    plan.Quantity.DISTANCE: units.LENGTH,
}
_MAGNITUDES = (plan.Quantity.FORCE, plan.Quantity.TORQUE, plan.Quantity.DISTANCE)


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
        return plan.AnyOf(tuple(compile_condition(c, frame, evaluator, text_of) for c in condition.items))
    quantity, direction_world = _quantity(condition, frame)
    name = condition.sensed.value
    if condition.direction is not None:
        name += f" {text_of(condition.direction.span)}"
    value = evaluator.expect_scalar(condition.value, _QUANTITY_DIM[quantity], name)
    op = plan.CompareOp(condition.op)
    if quantity in _MAGNITUDES:
        _check_magnitude(condition, op, value, name)
    return plan.Comparison(
        quantity=quantity,
        direction_world=direction_world,
        op=op,
        value=value,
        text=text_of(condition.span),
        span=condition.span,
    )


def _quantity(condition: ast.Comparison, frame: TaskFrame) -> tuple[plan.Quantity, plan.FloatArray | None]:
    direction = condition.direction
    if condition.sensed is ast.Sensed.DISTANCE:
        return plan.Quantity.DISTANCE, None
    if direction is None:
        if condition.sensed is ast.Sensed.FORCE:
            return plan.Quantity.FORCE, None
        return plan.Quantity.TORQUE, None
    axis = direction.axis._value_
    if condition.sensed is ast.Sensed.FORCE:
        if direction.axis.is_rotation:
            raise ProgramError(
                f"FORCE is measured along X, Y or Z; for the moment about {direction.axis.name} "
                f"write TORQUE {direction.axis.name}",
                direction.span,
            )
        return plan.Quantity.FORCE_ALONG, readonly(frame.rotation[:, axis] * direction.sign)
    return plan.Quantity.TORQUE_ABOUT, readonly(frame.rotation[:, axis % 3] * direction.sign)


def _check_magnitude(condition: ast.Comparison, op: plan.CompareOp, value: float, name: str) -> None:
    """A magnitude is never negative: refuse comparisons that always or never hold."""
    below = op in (plan.CompareOp.LT, plan.CompareOp.LE)
    if below and value <= 0:
        raise ProgramError(
            f"{name} {op.value} {value:g} can never hold: {name} is a magnitude, never below 0"
            + (f"; to test a component write {name} Z {op.value} ..." if name != "DISTANCE" else ""),
            condition.span,
        )
    if not below and value < 0:
        raise ProgramError(
            f"{name} {op.value} {value:g} always holds: {name} is a magnitude, never below 0"
            + (f"; to test a component write {name} Z {op.value} ..." if name != "DISTANCE" else ""),
            condition.span,
        )


def comparisons(condition: plan.Condition) -> list[plan.Comparison]:
    """Every comparison in a condition tree."""
    if isinstance(condition, plan.Comparison):
        return [condition]
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
    below = condition.op in (plan.CompareOp.LT, plan.CompareOp.LE)
    if condition.quantity is plan.Quantity.DISTANCE and below:
        return condition
    if condition.quantity in (plan.Quantity.FORCE, plan.Quantity.TORQUE) and below:
        return None if force_expected else condition
    return None
