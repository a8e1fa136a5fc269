"""Which way a goal motion turns: the shortest rotation unless the joints' ranges forbid it.

Eq. 20-21 applied to orientation turns the tool about a fixed axis, the
rotation vector ``phi = log(R_d R^T)`` (angle up to pi), at the angular speed
limit. Whether the arm can follow that geodesic depends on its joints: the
PUMA's wrist joints have finite ranges (joint 6: +-266 deg), so a half turn
about the tool axis may be possible only one way round. Before a goal motion
starts, the runtime follows the tool's path (straight line, rotation about the
fixed axis) with the kinematic model, in small steps of closed-loop inverse
kinematics from the measured configuration, for the short way and for the long
way round (``phi (1 - 2 pi / |phi|)``, the same end orientation). The first
that keeps every joint inside its range by ``margin_rad`` is used; the servo
keeps to it (its orientation error is unwrapped evaluation by evaluation,
:func:`cosmos.osc.orientation.unwrap_rotation_vector`). If neither does, the
shortest is kept and the plan says which joint stops it.
"""

from __future__ import annotations

import math
import operator
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import pinocchio as pin

from cosmos.osc.orientation import so3_exp, so3_log

FloatArray = np.ndarray


class Kinematics(Protocol):
    """What this module reads of the arm.

    A :class:`cosmos.robot_model.RobotModel`, or the checker's
    :class:`cosmos.runtime.foresight_cache.ArmKinematics` (no MuJoCo to load).
    """

    @property
    def model(self) -> pin.Model: ...  # noqa: D102
    @property
    def tool_frame(self) -> int: ...  # noqa: D102
    @property
    def q_lower_rad(self) -> FloatArray: ...  # noqa: D102
    @property
    def q_upper_rad(self) -> FloatArray: ...  # noqa: D102


STEP_RAD = 0.03
"""Largest rotation between two points of the predicted path [rad]."""
STEP_M = 0.005
"""Largest translation between two points of the predicted path [m]."""
LIMIT_MARGIN_RAD = math.radians(3.0)
"""A predicted joint closer than this to a limit counts as stopped by it [rad]."""
DAMPING = 1e-4
"""Damping of the least-squares inverse kinematics step (near a singularity) [1]."""


@dataclass(frozen=True)
class JointAtLimit:
    """A joint that stops a motion at (or predicted at) one end of its range.

    Attributes:
        joint: Joint number, 1-based (as the PUMA's documentation counts).
        limit_rad: The limit it reaches, in [rad].
        other_wrist_rad: Joints 4, 5 and 6 of another configuration of the wrist in which the
            goal's tool pose is within every range (:func:`other_wrists`), in [rad]; None if
            there is none. # (3,)
    """

    joint: int
    limit_rad: float
    other_wrist_rad: tuple[float, float, float] | None = None

    @property
    def message(self) -> str:
        """``joint 6 at its limit of 266 deg``, and the wrist configuration the goal needs."""
        said = f"joint {self.joint} at its limit of {math.degrees(self.limit_rad):.0f} deg"
        if self.other_wrist_rad is None:
            return said
        q4, q5, q6 = (math.degrees(value) for value in self.other_wrist_rad)
        return (
            f"{said}; the goal is within range in another configuration of the wrist (joints 4, 5, 6 "
            f"at {q4:.0f}, {q5:.0f}, {q6:.0f} deg there), which a motion does not turn into"
        )


@dataclass(frozen=True)
class RotationPlan:
    """The rotation a goal motion will make.

    Attributes:
        rotation_vector: Axis times angle taking the start orientation to the goal,
            world axes, in [rad]; its norm may exceed pi (the long way round). # (3,)
        blocked_by: The joint that stops the shortest rotation when no way round
            keeps the joints in range, else None.
        long_way: True when the long way round was chosen.
        goal_q: The configuration the followed path ends in (the goal's, by the arm's
            kinematic model), in [rad]. # (n,)
    """

    rotation_vector: FloatArray
    blocked_by: JointAtLimit | None
    long_way: bool
    goal_q: FloatArray


def first_joint_past_limits(robot: Kinematics, q: FloatArray, margin_rad: float = 0.0) -> JointAtLimit | None:
    """The first joint within ``margin_rad`` of (or past) a limit at ``q``, else None.

    Compared as arrays (the plan asks at every point of its path): a joint is named only
    when one is out of range.
    """
    below = q < robot.q_lower_rad + margin_rad
    above = q > robot.q_upper_rad - margin_rad
    out = below | above
    if not out.any():
        return None
    i = int(np.argmax(out))
    return JointAtLimit(i + 1, float(robot.q_lower_rad[i] if below[i] else robot.q_upper_rad[i]))


def other_wrists(robot: Kinematics, q: FloatArray, margin_rad: float = LIMIT_MARGIN_RAD) -> list[FloatArray]:
    """The wrist's other configurations for the tool pose at ``q``, ``margin_rad`` inside the ranges.

    A spherical wrist reaches every orientation twice, ``(q4 + pi, -q5, q6 + pi)``, and a
    joint whose range exceeds a turn (the PUMA's joint 6, +-266 deg) at ``q6 +- 2 pi`` too.
    Each is checked with the kinematic model (the same tool pose within 1e-9): an arm
    without such a wrist (the Panda's is offset) has none.

    Returns:
        The configurations, in [rad]. # list of (n,)
    """
    if len(q) != 6:
        return []
    model, data, frame = robot.model, robot.model.createData(), robot.tool_frame
    pin.framesForwardKinematics(model, data, np.asarray(q, dtype=float))
    pose = data.oMf[frame].homogeneous.copy()
    found = []
    for flip, turns_6 in ((False, (2.0, -2.0)), (True, (1.0, -1.0, 3.0, -3.0))):
        for turn_4 in (math.pi, -math.pi) if flip else (0.0,):
            for turn_6 in turns_6:
                other = np.array(q, dtype=float)
                other[3], other[5] = q[3] + turn_4, q[5] + turn_6 * math.pi
                other[4] = -q[4] if flip else q[4]
                if first_joint_past_limits(robot, other, margin_rad) is not None:
                    continue
                pin.framesForwardKinematics(model, data, other)
                if np.allclose(data.oMf[frame].homogeneous, pose, atol=1e-9):
                    found.append(other)
    return found


def _in_range(q: list[float], lowest: list[float], highest: list[float]) -> bool:
    """Whether every joint of ``q`` is within ``[lowest, highest]`` (as floats: once a point of the path).

    Two comparisons of the lists (``map``): half the time of a generator over the joints.
    """
    return all(map(operator.le, lowest, q)) and all(map(operator.le, q, highest))


_KINEMATICS_DATA: dict[int, tuple[pin.Model, pin.Data]] = {}
"""Pinocchio's work space for a model, by the model's identity (the model kept with it, so the
identity cannot be reused): made once, not at every path followed (30 us each, of a 60-180 us plan)."""

KINEMATICS_DATA_KEPT = 4
"""Models whose work space is kept (a GRASP and its RELEASE change the model; the oldest goes)."""


def kinematics_data(model: pin.Model) -> pin.Data:
    """A Pinocchio data for ``model``, made at its first use and kept.

    Each use computes from the configuration it gives (:func:`pin.computeFrameJacobian` places
    the joints and the frame before its Jacobian), so nothing of a former use is read.
    """
    kept = _KINEMATICS_DATA.get(id(model))
    if kept is not None and kept[0] is model:
        return kept[1]
    if len(_KINEMATICS_DATA) >= KINEMATICS_DATA_KEPT:
        del _KINEMATICS_DATA[next(iter(_KINEMATICS_DATA))]
    data = model.createData()
    _KINEMATICS_DATA[id(model)] = (model, data)
    return data


def _numpy_step(
    jacobian: FloatArray,
    pose: FloatArray,
    s: float,
    position: FloatArray,
    displacement: FloatArray,
    rotation_vector: FloatArray,
    rotation: FloatArray,
    q: FloatArray,
    damping: float,
) -> None:
    """:func:`cosmos.runtime.kernels.path_step.path_step_into` in NumPy (the checker: no numba to load)."""
    target_p = position + s * displacement
    target_r = so3_exp(s * rotation_vector).dot(rotation)
    error = np.concatenate((target_p - pose[:3, 3], so3_log(target_r.dot(pose[:3, :3].T))))
    jjt = jacobian.dot(jacobian.T) + damping * np.eye(6)
    q += jacobian.T.dot(np.linalg.solve(jjt, error))


def _follow(
    robot: Kinematics,
    q_start: FloatArray,
    position: FloatArray,
    rotation: FloatArray,
    displacement: FloatArray,
    rotation_vector: FloatArray,
    margin_rad: float,
    compiled: bool = True,
) -> tuple[JointAtLimit | None, FloatArray]:
    """Follow the path with closed-loop IK (each step compiled, or in NumPy).

    Returns:
        The joint it would push past a limit (or None), and the configuration where it
        stopped (the path's end if none). # (n,)
    """
    if compiled:  # numba is loaded here, not by what imports this module for its JointAtLimit
        from cosmos.runtime.kernels.path_step import path_step_into as step
    else:
        step = _numpy_step

    model, data, frame = robot.model, kinematics_data(robot.model), robot.tool_frame
    steps = max(
        1,
        math.ceil(float(np.linalg.norm(rotation_vector)) / STEP_RAD),
        math.ceil(float(np.linalg.norm(displacement)) / STEP_M),
    )
    q = np.array(q_start, dtype=float)
    already = first_joint_past_limits(robot, q, margin_rad)  # a joint starting in the margin may stay
    # The same bounds as first_joint_past_limits's, as floats: it is asked only of a point outside them.
    lowest, highest = (robot.q_lower_rad + margin_rad).tolist(), (robot.q_upper_rad - margin_rad).tolist()
    start, line, turn, start_rotation = (
        np.ascontiguousarray(v, dtype=float) for v in (position, displacement, rotation_vector, rotation)
    )
    oMf = data.oMf
    for k in range(1, steps + 1):
        s = k / steps
        for _ in range(2):  # two Newton steps per path point
            # The LOCAL_WORLD_ALIGNED Jacobian places the frame first (data.oMf), by the same
            # products as pin.framesForwardKinematics: one pass of the kinematics, not two.
            jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
            step(jacobian, oMf[frame].homogeneous, s, start, line, turn, start_rotation, q, DAMPING)
        if _in_range(q.tolist(), lowest, highest):
            continue
        hit = first_joint_past_limits(robot, q, margin_rad)
        if hit is not None and (already is None or hit.joint != already.joint):
            return hit, q
    return None, q


def ranges_for_goal(
    lower: FloatArray, upper: FloatArray, goal_q: FloatArray | None, margin_rad: float
) -> tuple[FloatArray, FloatArray]:
    """The joint ranges widened so that the goal's configuration keeps ``margin_rad`` from each end.

    A protective zone near a limit (the task's joint-limit projection, the joint-limit potential)
    that reaches the goal itself stops the motion short of it: a MOVE TO whose goal had joint 3
    7 deg from its limit stopped 1-2 mm short. Widened, the zone starts at the goal and still
    guards the range beyond it. None: the arm's ranges.

    Returns:
        ``(min(lower, q_g - m), max(upper, q_g + m))``, in [rad]. # 2 x (n,)
    """
    if goal_q is None:
        return lower, upper
    return np.minimum(lower, goal_q - margin_rad), np.maximum(upper, goal_q + margin_rad)


def plan_rotation(
    robot: Kinematics,
    q: FloatArray,
    position: FloatArray,
    rotation: FloatArray,
    goal_position: FloatArray,
    goal_rotation: FloatArray,
    margin_rad: float = LIMIT_MARGIN_RAD,
    compiled: bool = True,
) -> RotationPlan:
    """The way round a goal motion from ``(position, rotation)`` to the goal turns.

    Args:
        robot: The controller's model (joint ranges, kinematics).
        q: The measured configuration, in [rad]. # (6,)
        position: The tool point now, world, in [m]. # (3,)
        rotation: The tool orientation now. # (3, 3)
        goal_position: The goal tool point, in [m]. # (3,)
        goal_rotation: The goal orientation. # (3, 3)
        margin_rad: How near a limit a predicted joint may come, in [rad].
        compiled: Each step of the path compiled (the runtime: 2-3 times faster); False in NumPy,
            where loading numba would cost more than it saves (the checker's foresight).

    Returns:
        The rotation to make and, if every way is stopped, the joint that stops the shortest.
    """
    shortest = so3_log(goal_rotation.dot(rotation.T))
    displacement = np.asarray(goal_position, dtype=float) - position
    blocked, end = _follow(robot, q, position, rotation, displacement, shortest, margin_rad, compiled)
    if blocked is None:
        return RotationPlan(shortest, None, False, end)
    angle = float(np.linalg.norm(shortest))
    if angle > math.radians(1.0):
        long_way = shortest * (1.0 - 2.0 * math.pi / angle)
        stopped, long_end = _follow(
            robot, q, position, rotation, displacement, long_way, margin_rad, compiled
        )
        if stopped is None:
            return RotationPlan(long_way, None, True, long_end)
    # The goal may lie within the ranges in another configuration of the wrist, which no MOVE
    # turns into (the flip passes the wrist singularity, q5 = 0): the message says which.
    _, unbounded = _follow(robot, q, position, rotation, displacement, shortest, -math.inf, compiled)
    for other in other_wrists(robot, unbounded, margin_rad):
        blocked = JointAtLimit(blocked.joint, blocked.limit_rad, (other[3], other[4], other[5]))
        break
    return RotationPlan(shortest, blocked, False, end)
