"""What a segment's judges look at in one tick: the measured tool, the wrist, the time (live views)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

FloatArray = np.ndarray


@dataclass(slots=True)
class Snapshot:
    """What the monitor looks at in one tick (world axes).

    Made once per segment: the arrays are live views of the runtime's and the
    plant's buffers (rewritten in place every tick), and the executor sets
    ``t_s`` each tick, so a tick allocates nothing to be judged.

    Attributes:
        t_s: Simulated time, in [s].
        position: Measured tool point, in [m]. # (3,)
        rotation: Measured tool orientation, tool to world. # (3, 3)
        velocity: Tool twist ``J qd`` from the encoders, in [m/s, rad/s]. # (6,)
        wrench: Wrench the tool applies to the environment (wrist sensor), in [N, N m]. # (6,)
        grip: Reads the gripper's pads now: the smaller of their forces [N] (FINGER FORCE);
            called only by a segment whose UNTIL reads it.
    """

    t_s: float
    position: FloatArray
    rotation: FloatArray
    velocity: FloatArray
    wrench: FloatArray
    grip: Callable[[], float] = lambda: 0.0
