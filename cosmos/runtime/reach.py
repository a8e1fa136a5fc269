"""Whether a goal lies within the arm's reach: its flange's distance from the shoulder.

The run (:func:`cosmos.execution.arrival.out_of_reach`, before the arm moves) and the
checker's foresight (:mod:`cosmos.runtime.foresight`) judge a goal by this one rule.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.robots import Robot


def beyond_reach(flange_position: np.ndarray, arm: Robot) -> str | None:
    """Why a flange (the PUMA's wrist centre) at ``flange_position`` (world [m]) is out of reach, or None."""
    reach_m = arm.capability.reach_m
    x, y, z = (float(a - b) for a, b in zip(flange_position, arm.shoulder_m, strict=True))
    reach = math.sqrt(x * x + y * y + z * z)
    if reach <= reach_m:
        return None
    beyond = (reach - reach_m) * 1e3
    return (
        f"the pose is out of the arm's reach: its wrist centre would be {beyond:.0f} mm beyond "
        f"the arm's {reach_m * 1e3:.0f} mm"
    )
