"""Stop conditions (UNTIL, and what IF and WHILE read): comparisons of sensed quantities."""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from cosmos.errors import Span
from cosmos.plan.targets import FloatArray

# --------------------------------------------------------- stop conditions


class Quantity(enum.Enum):
    """A sensed quantity an UNTIL condition compares."""

    FORCE = "force"
    """Magnitude of the force the tool applies [N]."""
    FORCE_ALONG = "force_along"
    """Force the tool applies, projected on ``direction_world`` [N]."""
    TORQUE = "torque"
    """Magnitude of the moment the tool applies [N m]."""
    TORQUE_ABOUT = "torque_about"
    """Moment the tool applies, projected on ``direction_world`` [N m]."""
    DISTANCE = "distance"
    """Distance of the tool point from where the statement started [m]."""
    POSITION_ALONG = "position_along"
    """Decisions only: the tool point's coordinate along ``direction_world`` from ``origin_world`` [m]."""
    DISTANCE_FROM = "distance_from"
    """Decisions only: distance of the tool point from ``origin_world`` [m]."""
    FINGER_FORCE = "finger_force"
    """The grip: the smaller of the gripper's two pad forces, as their sensors read them [N]."""


class CompareOp(enum.Enum):
    """Comparison operators."""

    GT = ">"
    GE = ">="
    LT = "<"
    LE = "<="

    def holds(self, measured: float, value: float) -> bool:
        """``measured <op> value``."""
        if self is CompareOp.GT:
            return measured > value
        if self is CompareOp.GE:
            return measured >= value
        if self is CompareOp.LT:
            return measured < value
        return measured <= value


@dataclass(frozen=True, eq=False)
class Comparison:
    """``quantity <op> value``.

    Attributes:
        quantity: What is measured.
        direction_world: Unit vector, world, for FORCE_ALONG and TORQUE_ABOUT; else None.
        op: The comparison.
        value: Threshold in SI (N, N m or m).
        text: The condition as written.
        span: Where it is written.
        origin_world: For POSITION_ALONG and DISTANCE_FROM: the frame's origin [m],
            world, (3,); else None.
    """

    quantity: Quantity
    direction_world: FloatArray | None
    op: CompareOp
    value: float
    text: str
    span: Span
    origin_world: FloatArray | None = None


@dataclass(frozen=True, eq=False)
class AllOf:
    """True when every term is true (AND)."""

    terms: tuple[Condition, ...]


@dataclass(frozen=True, eq=False)
class AnyOf:
    """True when any term is true (OR)."""

    terms: tuple[Condition, ...]


class Ending(enum.Enum):
    """How a statement ended, as a decision asks about it (``LAST FAILED``, ``LAST STOPPED``)."""

    FAILED = "failed"
    """It failed (only inside a TRY: elsewhere a failure ends the program)."""
    STOPPED = "stopped"
    """Its UNTIL held: it ended early, with success."""


@dataclass(frozen=True, eq=False)
class LastOutcome:
    """Decisions only: true when the motion statement run last ended so.

    Attributes:
        ending: The ending asked about.
        text: The condition as written.
        span: Where it is written.
    """

    ending: Ending
    text: str
    span: Span


Condition = Comparison | AllOf | AnyOf | LastOutcome

_NOT_THE_WRIST = (Quantity.DISTANCE, Quantity.FINGER_FORCE)
"""Terms that do not read the wrist sensor: they expect no contact of the tool."""


def has_force_term(condition: Condition | None) -> tuple[bool, float]:
    """Whether an UNTIL compares a force or moment (a guarded motion), its largest threshold [N, N m]."""
    if condition is None:
        return False, 0.0
    if isinstance(condition, AllOf | AnyOf):
        found, largest = False, 0.0
        for term in condition.terms:
            has, value = has_force_term(term)
            found, largest = found or has, max(largest, value)
        return found, largest
    if isinstance(condition, LastOutcome) or condition.quantity in _NOT_THE_WRIST:
        return False, 0.0
    return True, abs(condition.value)


def condition_holds(
    condition: Condition,
    force_world: FloatArray,
    torque_world: FloatArray,
    distance_m: float,
    grip_n: float = 0.0,
) -> bool:
    """Evaluate a stop condition on measured values.

    Args:
        condition: The condition tree.
        force_world: Force the tool applies to the environment [N], world, (3,).
        torque_world: Moment the tool applies to the environment [N m], world, (3,).
        distance_m: Distance of the tool point from the statement's start [m].
        grip_n: The smaller of the gripper's pad forces [N] (FINGER FORCE; 0 without the gripper).
    """
    if isinstance(condition, AllOf):
        return all(condition_holds(t, force_world, torque_world, distance_m, grip_n) for t in condition.terms)
    if isinstance(condition, AnyOf):
        return any(condition_holds(t, force_world, torque_world, distance_m, grip_n) for t in condition.terms)
    if isinstance(condition, LastOutcome):  # the compiler keeps LAST out of UNTIL
        raise ValueError(f"{condition.text} is read by IF and WHILE, not by a stop condition")
    quantity = condition.quantity
    # Scalar arithmetic on the three components: this runs every servo tick.
    if quantity is Quantity.FORCE:
        measured = math.hypot(*force_world.tolist())
    elif quantity is Quantity.TORQUE:
        measured = math.hypot(*torque_world.tolist())
    elif quantity is Quantity.FORCE_ALONG:
        measured = float(force_world.dot(condition.direction_world))  # type: ignore[arg-type]
    elif quantity is Quantity.TORQUE_ABOUT:
        measured = float(torque_world.dot(condition.direction_world))  # type: ignore[arg-type]
    elif quantity is Quantity.FINGER_FORCE:
        measured = grip_n
    else:
        measured = distance_m
    return condition.op.holds(measured, condition.value)
