"""How a stop condition is written in messages: as the program wrote it, with the values that fired it."""

from __future__ import annotations

import math

import numpy as np

from cosmos.plan import AllOf, AnyOf, Comparison, Condition, LastOutcome, Quantity

FloatArray = np.ndarray


_UNITS = {
    Quantity.FORCE: (1.0, "N", 1),
    Quantity.FORCE_ALONG: (1.0, "N", 1),
    Quantity.TORQUE: (1.0, "N m", 2),
    Quantity.TORQUE_ABOUT: (1.0, "N m", 2),
    Quantity.DISTANCE: (1e3, "mm", 1),
    Quantity.FINGER_FORCE: (1.0, "N", 1),
}


def condition_text(condition: Condition) -> str:
    """The condition as written: a comparison's own text, AND and OR in parentheses."""
    if isinstance(condition, Comparison | LastOutcome):
        return condition.text
    joiner = " AND " if isinstance(condition, AllOf) else " OR "
    return "(" + joiner.join(condition_text(term) for term in condition.terms) + ")"


def reads_grip(condition: Condition) -> bool:
    """Whether the condition reads the gripper's pads (FINGER FORCE)."""
    if isinstance(condition, LastOutcome):
        return False
    return any(term.quantity is Quantity.FINGER_FORCE for term in _terms(condition))


def _value(
    comparison: Comparison, force: FloatArray, torque: FloatArray, distance_m: float, grip_n: float
) -> float:
    quantity = comparison.quantity
    if quantity is Quantity.FINGER_FORCE:
        return grip_n
    if quantity is Quantity.FORCE:
        return math.hypot(*force.tolist())
    if quantity is Quantity.TORQUE:
        return math.hypot(*torque.tolist())
    if quantity is Quantity.FORCE_ALONG:
        return float(np.dot(force, comparison.direction_world))  # type: ignore[arg-type]
    if quantity is Quantity.TORQUE_ABOUT:
        return float(np.dot(torque, comparison.direction_world))  # type: ignore[arg-type]
    return distance_m


def measured_text(
    condition: Condition, force: FloatArray, torque: FloatArray, distance_m: float, grip_n: float = 0.0
) -> str:
    """What each term of a condition measured: ``4.6 N``, or ``DISTANCE 20.3 mm, FORCE 0.4 N``.

    ``grip_n`` is the FINGER FORCE read this tick (the smaller pad force) [N].
    """
    terms = _terms(condition)
    parts = []
    for term in terms:
        scale, unit, digits = _UNITS[term.quantity]
        value = f"{_value(term, force, torque, distance_m, grip_n) * scale:.{digits}f} {unit}"
        label = term.text.partition(term.op.value)[0].strip().lstrip("(").strip()  # "(FORCE Z < -3 N)"
        parts.append(value if len(terms) == 1 else f"{label} {value}")
    return ", ".join(parts)


def _terms(condition: Condition) -> list[Comparison]:
    if isinstance(condition, Comparison):
        return [condition]
    assert isinstance(condition, AllOf | AnyOf)
    return [leaf for term in condition.terms for leaf in _terms(term)]
