"""Where the tool really is, how far from its goal, and why a motion that stopped short did.

Outcomes are measurements. The executor judges arrival on the *measured* tool
pose: MuJoCo's tool site, the plant's true state. Not on the controller's
estimate ``x_e + J (q - q_e)``, which is the controller's belief: if its model
is wrong (a tool mis-calibrated, a joint off), the estimate says the goal was
reached where the arm is not, and a log of that is a lie. On a real cell the
measurement would be the encoders through a calibrated kinematic model (an
external tracker where accuracy matters); in this simulation the plant's state
is that measurement, and the log's ``/cosmos/state`` pose is the same site, so
the outcome and the log agree.

When a goal motion stops getting closer, :func:`stall_cause` names the real
reason from the measured joints: something in the way, a joint at its limit,
a singularity, or a goal out of the arm's reach, and only then "out of reach".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from cosmos.obstacles.field import Influence
from cosmos.osc.orientation import so3_log
from cosmos.plant import Plant
from cosmos.robots import DEFAULT_ROBOT, Robot
from cosmos.runtime.reach import beyond_reach
from cosmos.runtime.rotation_plan import JointAtLimit
from cosmos.workcell import TOOL_SITE, tool_spec

FloatArray = np.ndarray

JOINT_LIMIT_MARGIN_RAD = 0.15
"""A joint this close to a limit counts as at it: where section 6's joint-limit field
(rho_0 = 0.15 rad, :class:`cosmos.runtime.parameters.JointLimitField`) pushes it back."""
WRIST_SINGULAR_RAD = math.radians(3.0)
"""|q5| below this: the PUMA's wrist singularity (axes 4 and 6 aligned; :attr:`Robot.wrist_joint`)."""
SINGULAR_CONDITION = 0.02
"""Smallest over largest singular value of the (scaled) Jacobian below which the arm is singular."""
LENGTH_SCALE_M = 0.3
"""Makes the Jacobian's rotation rows commensurate with its translation rows [m]."""
REST_ANGULAR_SPEED_RAD_S = 0.05
"""A goal motion's tool turning faster than this (on its controlled rotations) has not arrived
[rad/s] (2.9 deg/s, as a brake's rest, :data:`cosmos.execution.holding.BRAKE_AT_REST`). Arrival
("within tolerance and at rest") judged the tool point's speed only: a reorienting MOVE ended
at 0.8 deg still turning at 11 deg/s, and the WAIT after it held that pose, 0.75-0.80 deg off."""
BLOCKED_N = 2.0
"""A stalled motion pushing harder than this is blocked by something [N]."""


class ToolMeter:
    """The measured tool pose: views of MuJoCo's tool site (valid after each physics step)."""

    def __init__(self, plant: Plant):
        data = plant.data
        site = mujoco.mj_name2id(plant.model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
        self.position: FloatArray = data.site_xpos[site]  # (3,) world [m], a live view
        self._xmat = data.site_xmat[site]  # (9,) row-major, a live view

    @property
    def rotation(self) -> FloatArray:
        """Tool frame to world. # (3, 3)."""
        return self._xmat.reshape(3, 3)


@dataclass(frozen=True)
class GoalError:
    """The measured pose minus the goal, world axes.

    Attributes:
        position_m: Tool point minus goal point [m]. # (3,)
        rotation_rad: Rotation vector of ``R R_goal^T`` [rad]. # (3,)
    """

    position_m: FloatArray
    rotation_rad: FloatArray

    @property
    def distance_m(self) -> float:
        """How far the tool point is from its goal [m]."""
        return float(np.linalg.norm(self.position_m))

    @property
    def angle_rad(self) -> float:
        """How far the tool is turned from its goal orientation [rad]."""
        return float(np.linalg.norm(self.rotation_rad))

    def text(self) -> str:
        """``12 mm and 66.0 deg from its goal``."""
        return f"{self.distance_m * 1e3:.1f} mm and {math.degrees(self.angle_rad):.1f} deg from its goal"


def goal_error(
    position: FloatArray, rotation: FloatArray, goal_position: FloatArray, goal_rotation: FloatArray
) -> GoalError:
    """The measured pose's error from the goal pose (world axes)."""
    return GoalError(position - goal_position, so3_log(rotation @ goal_rotation.T))


def wrist_centre(position: FloatArray, rotation: FloatArray, arm: Robot = DEFAULT_ROBOT) -> FloatArray:
    """Where the flange origin (the PUMA's wrist centre, DH frame 6) is for a tool pose, world [m]."""
    tool = tool_spec(arm)
    rotation_flange = rotation @ tool.tool_rotation_in_flange.T
    return position - rotation_flange @ tool.tool_position_in_flange


def out_of_reach(
    goal_position: FloatArray, goal_rotation: FloatArray, arm: Robot = DEFAULT_ROBOT
) -> str | None:
    """Why a goal pose is out of the arm's reach, or None if its flange is within reach of the shoulder."""
    return beyond_reach(wrist_centre(goal_position, goal_rotation, arm), arm)


def stall_cause(
    q: FloatArray,
    q_lower: FloatArray,
    q_upper: FloatArray,
    jacobian: FloatArray,
    push_n: float,
    goal_position: FloatArray,
    goal_rotation: FloatArray,
    arm: Robot = DEFAULT_ROBOT,
    fields: tuple[Influence, ...] = (),
    planned: JointAtLimit | None = None,
) -> str:
    """Why a goal motion stopped short, from what is measured now.

    Args:
        q: Measured joint angles [rad]. # (n,)
        q_lower: Lower joint limits [rad]. # (n,)
        q_upper: Upper joint limits [rad]. # (n,)
        jacobian: Tool Jacobian at q, rows linear then angular, world. # (6, n)
        push_n: Magnitude of the force the tool applies [N].
        goal_position: The goal tool point, world [m]. # (3,)
        goal_rotation: The goal orientation, tool to world. # (3, 3)
        arm: The arm (its reach and wrist).
        fields: The obstacles whose potential field acts on the arm now (seed section 6).
        planned: The joint the motion's rotation plan found in the way of the shortest rotation
            (:attr:`cosmos.runtime.rotation_plan.RotationPlan.blocked_by`), if any.
    """
    if push_n > BLOCKED_N:
        return f"is blocked, pushing {push_n:.1f} N against something in the way"
    beyond = out_of_reach(goal_position, goal_rotation, arm)
    if beyond is not None:
        return beyond
    near = [
        (abs(q[joint] - limit), joint, limit)
        for joint in range(len(q))
        for limit in (q_lower[joint], q_upper[joint])
        if abs(q[joint] - limit) < JOINT_LIMIT_MARGIN_RAD
    ]
    if near:
        _, joint, limit = min(near)
        return JointAtLimit(joint + 1, float(limit)).message
    singular = singularity(q, jacobian, arm)
    if singular is not None:
        return f"{singular}, which prevents progress"
    if planned is not None:  # held back short of it by the limit's potential (seed section 6)
        return planned.message
    if fields:  # the goal lies where an obstacle's field pushes back: an equilibrium short of it
        nearest = min(fields, key=lambda influence: influence.distance_m)
        return (
            f"the field of obstacle '{nearest.obstacle}' holds it back ({nearest.link} "
            f"{nearest.distance_m * 1e3:.0f} mm from it; INFLUENCE sets how far the field reaches)"
        )
    return "the controller made no progress (nothing in the way, no joint at a limit, no singularity)"


def singularity(q: FloatArray, jacobian: FloatArray, arm: Robot = DEFAULT_ROBOT) -> str | None:
    """The singularity the arm is at, in words, or None (seed section 5).

    Args:
        q: Measured joint angles [rad]. # (n,)
        jacobian: Tool Jacobian at q, rows linear then angular, world. # (6, n)
        arm: The arm (whether its wrist is spherical: :attr:`Robot.wrist_joint`).
    """
    wrist = arm.wrist_joint
    if wrist is not None and abs(math.sin(q[wrist])) < math.sin(WRIST_SINGULAR_RAD):
        angle_deg = math.degrees(q[wrist])
        return (
            f"the wrist is at its singularity (joint {wrist + 1} at {angle_deg:.1f} deg: "
            f"joints {wrist} and {wrist + 2} aligned)"
        )
    scaled = jacobian.copy()
    scaled[3:] *= LENGTH_SCALE_M
    values = np.linalg.svd(scaled, compute_uv=False)
    if values[-1] < SINGULAR_CONDITION * values[0]:
        return "the arm is at a singularity"
    return None
