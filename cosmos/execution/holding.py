"""The arm held where it is: after a failure, at an interruption, and after an UNTIL stopped it.

Every axis under position control at the measured pose, no force (the arm's own hold, not a
statement's). :func:`brake_to_rest` holds until the tool is at rest; :func:`brake_after_until`
so stops a free motion its UNTIL stopped, judges the impact it brakes through, and after a
guarded stop holds where the tool touched until its push has relaxed (:func:`settle_at_touch`).
"""

from __future__ import annotations

import numpy as np

from cosmos.execution.expected import braked_over_limit
from cosmos.execution.monitor import Outcome, Verdict
from cosmos.execution.supervision import ProtectiveStop, StopKind
from cosmos.plan import TOUCH_THRESHOLD_N, Segment
from cosmos.plan.conditions import AllOf, AnyOf, Comparison, Condition, Quantity
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

BRAKE_AT_REST = (5e-3, 0.05, 0.5)
"""The tool is at rest under this speed [m/s] and angular speed [rad/s]; a brake holds it at
most this long [s]."""
SETTLE_AT_TOUCH_S = 1.0
"""After a guarded stop, the longest the arm holds where the tool touched for its push to relax [s]."""


def hold_pose(runtime: Runtime, duration_s: float = 0.0) -> None:
    """Hold the measured pose with every axis under position control for ``duration_s``."""
    runtime.reset_clocks()
    ev = runtime.evaluation
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.HOLD,
            position=ev.position.copy(),
            rotation_to_world=ev.rotation_tool_to_world.copy(),
            start_s=runtime.time_s,
            force_start_world=runtime.wrench.copy(),
        )
    )
    end = runtime.time_s + duration_s
    while runtime.time_s < end - 1e-9:
        runtime.tick()


def brake_to_rest(runtime: Runtime) -> tuple[float, float]:
    """Hold the measured pose until the tool is at rest (:data:`BRAKE_AT_REST`).

    A statement its UNTIL stopped leaves the tool moving (at its SPEED, or faster on a
    DISTANCE); the next statement would turn that momentum round, and the wrist reads the
    tool's inertia (about 0.7 kg) as a push: after ``MOVE BY (0, 0, 100 mm) SPEED 0.2 m/s
    UNTIL DISTANCE > 50 mm``, a CONTACT DOWN "touched" 12 N 80 mm above the table. The
    statement stopped, so the arm stops.

    Returns:
        ``(peak [N], when [s])``: the largest force the wrist read while the arm braked, and when (a
        guarded motion's impact comes 2-16 ms after its UNTIL fired:
        :func:`cosmos.execution.expected.braked_over_limit`); ``(0, now)`` if it was at rest.
    """
    hold_pose(runtime)
    twist, wrench = runtime.servo.last_velocity, runtime.wrench
    speed, angular, longest = BRAKE_AT_REST
    end = runtime.time_s + longest
    peak, peak_s = 0.0, runtime.time_s
    while runtime.time_s < end - 1e-9 and (
        float(np.linalg.norm(twist[:3])) > speed or float(np.linalg.norm(twist[3:])) > angular
    ):
        runtime.tick()
        fx, fy, fz = wrench[:3].tolist()
        if (squared := fx * fx + fy * fy + fz * fz) > peak:
            peak, peak_s = squared, runtime.time_s
    return peak**0.5, peak_s


def brake_after_until(runtime: Runtime, segment: Segment, until_reason: str) -> Outcome | None:
    """Brake a free motion its UNTIL stopped to rest; a protective stop if it braked over its limit.

    A held contact or a spring keeps its force (no brake). A guarded motion meets its surface
    as its UNTIL fires, and the impact comes while the arm brakes: a force over the statement's
    limit then (:func:`cosmos.execution.expected.braked_over_limit`) fails it as a protective
    stop naming the peak, where it was "stopped" (174 N for UNTIL FORCE > 5 N, limit 40 N).
    Within it, an UNTIL on the wrist's force then holds where the tool touched until its push
    has relaxed (:func:`settle_at_touch`).

    Args:
        runtime: The runtime.
        segment: The segment its UNTIL stopped.
        until_reason: The stop's reason (``UNTIL FORCE > 5 N: 5.7 N at 3.16 s``).
    """
    if not bool(np.all(segment.motion_axes)) or any(segment.stiffness):
        return None
    braked = brake_to_rest(runtime)
    if over := braked_over_limit(segment, braked, until_reason):
        return Outcome(Verdict.FAILED, over, ProtectiveStop(StopKind.FORCE, over))
    if thresholds := force_thresholds_n(segment.until):
        settle_at_touch(runtime, min(TOUCH_THRESHOLD_N, *thresholds))
    return None


def force_thresholds_n(condition: Condition | None) -> tuple[float, ...]:
    """The thresholds of an UNTIL's terms on the wrist's force (FORCE, FORCE axis) [N]; () if none."""
    if isinstance(condition, AllOf | AnyOf):
        return tuple(value for term in condition.terms for value in force_thresholds_n(term))
    if isinstance(condition, Comparison) and condition.quantity in (Quantity.FORCE, Quantity.FORCE_ALONG):
        return (abs(condition.value),)
    return ()


def settle_at_touch(runtime: Runtime, push_n: float) -> None:
    """Hold the brake's pose, where a guarded motion's UNTIL fired, until the push is at most ``push_n``.

    The brake (:func:`brake_to_rest`) holds the pose at which the UNTIL fired, where the tool
    touched; the tool comes to rest below it, pressed into the surface by its momentum, and there
    the brake used to let go: the next statement's hold took that compressed pose and kept pressing
    (``MOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N`` onto the table: the UNTIL fired at 6.3-7.5 N,
    the arm came to rest pressing 10.1 N and 13.9 N, seeds 0 and 1, 27.9 N on the ideal plant, and
    the WAIT 1 s after it still pressed 2.4-3.1 N: MuJoCo's contact forces). Held at the touch, the
    surface pushes the tool back up to it: the push falls under a touch's
    (:data:`cosmos.plan.TOUCH_THRESHOLD_N`, or the UNTIL's own threshold if lower) in 0.15-0.25 s
    on the cushioned table, 10-25 ms on the steel hole fixture, and the next statement holds the
    tool where it touched (the WAIT: 0.3-1.7 N). At most :data:`SETTLE_AT_TOUCH_S` (something that
    keeps pushing is held as before).

    Args:
        runtime: The runtime, its servo holding the brake's setpoint.
        push_n: The push the tool may keep on its surface, in [N].
    """
    wrench = runtime.wrench
    end = runtime.time_s + SETTLE_AT_TOUCH_S
    while runtime.time_s < end - 1e-9:
        fx, fy, fz = wrench[:3].tolist()
        if fx * fx + fy * fy + fz * fz <= push_n * push_n:
            return
        runtime.tick()
