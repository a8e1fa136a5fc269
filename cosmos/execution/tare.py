"""The wrist sensor tared in free air before a contact approach, when it reads a push there.

The cell tares its wrist sensor once, at home, before the run (:mod:`cosmos.realism.tare`).
A sensor that has drifted since (a sweep's ``bias.*``), or a load the controller's tool model
does not hold, then reads at rest in free air what a CONTACT's touch (2 N, or half its FORCE)
takes for a push: with ``bias.fz`` 2 N, ``CONTACT DOWN FORCE 10 N`` from 40 mm above the table
"touched" 8 ms after it started, pushed the air, and failed "force did not settle within 3 s";
with 1.5 N it touched in the air, fell onto the table and held 6.3 N for its 10 N. Industrial
practice zeroes the sensor in free air before force control (UR's ``zero_ftsensor``, an ATI
controller's bias command). So a contact approach (CONTACT's, INSERT's) that starts at rest
in free air (after a free motion that ended done: the protective stop holds a free motion to
touching nothing) and reads a push there of more than :data:`TARE_ABOVE_N` holds the pose
:data:`TARE_S`, averages the sensed wrench, and zeroes the sensor by it; a ``warning`` event says
what it read. Below that (a tared sensor's noise is 0.05 N) nothing changes.

The zero is the reading error, in sensor axes, that explains what was sensed
(:func:`cosmos.runtime.wrench.reading_error`). The next segment senses the tared sensor afresh.
"""

from __future__ import annotations

import numpy as np

from cosmos.execution.holding import hold_pose
from cosmos.execution.monitor import Verdict
from cosmos.osc._types import FloatArray
from cosmos.plan import Segment, SegmentKind
from cosmos.runtime.loop import Runtime
from cosmos.runtime.wrench import reading_error

TARE_ABOVE_N = 0.5
"""A push sensed at rest in free air above this is tared away [N] (ten times the sensor's noise)."""
TARE_S = 0.05
"""The tare's average: the pose held this long [s] (50 readings at 1 kHz)."""
AT_REST_MPS = 0.005
"""The tool must be slower than this for its reading to be its bias, not its inertia [m/s]."""


def tare_in_free_air(runtime: Runtime) -> str:
    """Zero the wrist sensor if it reads a push at rest in free air; what it read, or "" if not.

    Args:
        runtime: The runtime, its tool at rest in free air (the caller knows it is in free air).
    """
    runtime.reset_clocks()
    speed = float(np.linalg.norm(runtime.servo.last_velocity[:3]))
    push = float(np.linalg.norm(runtime.wrench[:3]))
    if push <= TARE_ABOVE_N or speed > AT_REST_MPS:
        return ""
    total, ticks = np.zeros(6), 0
    hold_pose(runtime)
    end = runtime.time_s + TARE_S
    while runtime.time_s < end - 1e-9:
        runtime.tick()
        total += runtime.wrench
        ticks += 1
    sensed = total / ticks
    ev = runtime.evaluation
    runtime.plant.zero_wrist_sensor(reading_error(sensed, ev.rotation_sensor_to_world, ev.sensor_to_tool_m))
    force, moment = sensed[:3], sensed[3:]
    return (
        f"tared the wrist sensor: it read {np.linalg.norm(force):.2f} N and "
        f"{np.linalg.norm(moment):.3f} N m at rest in free air"
    )


LIFT_OFF_M = 0.05
"""A free motion that ends this far from where it started has left any contact it began in:
the protective stop allows such a contact only until then (cosmos.execution.expected) [m]."""


class FreeAir:
    """Whether the tool is, as far as the controller knows, at rest in free air.

    A program starts at home in free air. A free motion (MOVE or WAIT with every axis
    motion-controlled and no spring) that ends done keeps it there, or puts it there if it
    ended :data:`LIFT_OFF_M` from where it started; anything else (a contact, a spring, a
    guarded stop, a hand step, a failure) may leave the tool touching something.
    """

    def __init__(self) -> None:
        self.now = True

    def after(self, segment: Segment, verdict: Verdict, travelled: FloatArray) -> None:
        """Follow a statement that ended with ``segment``.

        Args:
            segment: Its last segment.
            verdict: How it ended (done, or stopped by its UNTIL).
            travelled: Where the tool is minus where the statement started, world [m]. # (3,)
        """
        free = (
            verdict is Verdict.DONE
            and segment.kind in (SegmentKind.MOVE, SegmentKind.WAIT)
            and all(segment.motion_axes)
            and not any(segment.stiffness)
        )
        self.now = free and (self.now or float(np.linalg.norm(travelled)) >= LIFT_OFF_M)

    def tare_before(self, segment: Segment, runtime: Runtime) -> str:
        """Tare the sensor before a contact approach that starts in free air; what it read, or ""."""
        free, self.now = self.now, False  # until the statement ends in free air (a failure does not)
        if segment.kind is not SegmentKind.CONTACT_APPROACH or not free:
            return ""
        return tare_in_free_air(runtime)
