"""What stops a goal motion, measured on the running controller: a joint limit or a singularity.

Ask when a goal motion stalls (:func:`progress_blockers`); each answer names its
cause in words a failure message can carry:

* a joint at (within ``LIMIT_NEAR_RAD`` of) one end of its range, where the task
  gives up what needs it (:func:`cosmos.osc.limits.joint_limit_task_projection`):
  ``joint 6 at its limit of 266 deg``; and, before the motion, the joint that the
  way round chosen for the rotation would run into
  (:attr:`Runtime.rotation_plan`, :mod:`cosmos.runtime.rotation_plan`);
* a singular direction that the task projection of section 5 holds back
  (:func:`cosmos.osc.dynamics.singular_task_projection`): the part of the pose
  error the arm cannot reduce there, named by where it is: ``the wrist
  singularity (joints 4 and 6 aligned, q5 = 0.8 deg) holds back 14.2 deg of
  rotation``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np

from cosmos.runtime.loop import Runtime
from cosmos.runtime.rotation_plan import JointAtLimit
from cosmos.runtime.servo_gains import LIMIT_PROJECTION_MARGIN_RAD

FloatArray = np.ndarray

LIMIT_NEAR_RAD = LIMIT_PROJECTION_MARGIN_RAD
"""A joint this close to a limit counts as at it [rad]: the task gives up what needs it there."""
BLOCKED_ROTATION_RAD = math.radians(1.0)
"""A singular direction holding back more rotation than this blocks the goal [rad]."""
BLOCKED_TRANSLATION_M = 0.001
"""... or more translation than this [m]."""
WRIST_Q5_RAD = math.radians(10.0)
"""With |q5| below this, a rotational singular direction is the wrist's (joints 4 and 6 aligned)."""


class BlockerKind(Enum):
    """What kind of thing stops a motion."""

    JOINT_LIMIT = "joint limit"
    SINGULARITY = "singularity"


@dataclass(frozen=True)
class Blocker:
    """One cause that stops a goal motion.

    Attributes:
        kind: Joint limit or singularity.
        message: What to say, e.g. ``joint 6 at its limit of 266 deg``.
        joint: The joint at its limit (1-based), or None for a singularity.
    """

    kind: BlockerKind
    message: str
    joint: int | None = None


def _joint_blocker(hit: JointAtLimit) -> Blocker:
    return Blocker(BlockerKind.JOINT_LIMIT, hit.message, hit.joint)


def singular_hold_back(runtime: Runtime) -> FloatArray:
    """The part of the current pose error section 5's projection holds back, world [m, rad]. # (6,)."""
    projection = runtime.servo.singular_projection
    return (np.eye(6) - projection).dot(runtime.servo.last_error)


def progress_blockers(runtime: Runtime) -> tuple[Blocker, ...]:
    """Why the running goal motion makes no progress, as measured now (empty if nothing blocks).

    Joint limits: each joint within LIMIT_NEAR_RAD of a limit (the arm's own
    encoders), and the joint the rotation plan predicted, if any. Singularity:
    the pose error held back by the task projection, when above
    BLOCKED_ROTATION_RAD or BLOCKED_TRANSLATION_M.
    """
    robot, q = runtime.robot, runtime.q
    found: list[Blocker] = []
    for i in range(q.shape[0]):
        lower, upper = robot.q_lower_rad[i], robot.q_upper_rad[i]
        if q[i] < lower + LIMIT_NEAR_RAD:
            found.append(_joint_blocker(JointAtLimit(i + 1, float(lower))))
        elif q[i] > upper - LIMIT_NEAR_RAD:
            found.append(_joint_blocker(JointAtLimit(i + 1, float(upper))))
    plan = runtime.rotation_plan
    if plan is not None and plan.blocked_by is not None:
        if all(b.joint != plan.blocked_by.joint for b in found):
            found.append(_joint_blocker(plan.blocked_by))
    held = singular_hold_back(runtime)
    rotation, translation = float(np.linalg.norm(held[3:])), float(np.linalg.norm(held[:3]))
    if rotation > BLOCKED_ROTATION_RAD or translation > BLOCKED_TRANSLATION_M:
        q5 = float(q[4])
        if rotation > BLOCKED_ROTATION_RAD and abs(q5) < WRIST_Q5_RAD:
            where = f"the wrist singularity (joints 4 and 6 aligned, q5 = {math.degrees(q5):.1f} deg)"
        else:
            where = "a singular configuration of the arm"
        amount = (
            f"{math.degrees(rotation):.1f} deg of rotation"
            if rotation > BLOCKED_ROTATION_RAD
            else f"{translation * 1e3:.1f} mm of translation"
        )
        found.append(Blocker(BlockerKind.SINGULARITY, f"{where} holds back {amount}"))
    return tuple(found)
