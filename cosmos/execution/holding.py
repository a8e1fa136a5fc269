"""The arm held where it is: after a failure, at an interruption, and after an UNTIL stopped it.

Every axis under position control at the measured pose, no force (the arm's own hold, not a
statement's). :func:`brake_to_rest` holds until the tool is at rest.
"""

from __future__ import annotations

import numpy as np

from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

BRAKE_AT_REST = (5e-3, 0.05, 0.5)
"""The tool is at rest under this speed [m/s] and angular speed [rad/s]; a brake holds it at
most this long [s]."""


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


def brake_to_rest(runtime: Runtime) -> None:
    """Hold the measured pose until the tool is at rest (:data:`BRAKE_AT_REST`).

    A statement its UNTIL stopped leaves the tool moving (at its SPEED, or faster on a
    DISTANCE); the next statement would turn that momentum round, and the wrist reads the
    tool's inertia (about 0.7 kg) as a push: after ``MOVE BY (0, 0, 100 mm) SPEED 0.2 m/s
    UNTIL DISTANCE > 50 mm``, a CONTACT DOWN "touched" 12 N 80 mm above the table. The
    statement stopped, so the arm stops.
    """
    hold_pose(runtime)
    twist = runtime.servo.last_velocity
    speed, angular, longest = BRAKE_AT_REST
    end = runtime.time_s + longest
    while runtime.time_s < end - 1e-9 and (
        float(np.linalg.norm(twist[:3])) > speed or float(np.linalg.norm(twist[3:])) > angular
    ):
        runtime.tick()
