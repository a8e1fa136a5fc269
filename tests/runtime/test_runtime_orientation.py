"""Reorientation by goal motion (eq. 20-21 applied to orientation) within the joints' ranges.

Judged on MuJoCo's own tool site (the plant), not on the controller's estimate.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from cosmos.osc.orientation import rpy_to_matrix, so3_exp, so3_log, unwrap_rotation_vector
from cosmos.runtime.blockers import BlockerKind, progress_blockers
from cosmos.runtime.kernels.parameter import unwrapped_rotation_error
from cosmos.runtime.rotation_plan import _follow, plan_rotation
from cosmos.runtime.servo_gains import LIMIT_PROJECTION_MARGIN_RAD
from cosmos.runtime.setpoint import DEFAULT_MAX_ANGULAR_SPEED, MotionMode, ServoSetpoint
from tests.runtime.runtime_helpers import ROBOT, run_for, runtime_at

DEG = math.pi / 180.0
POINT = np.array((0.60, -0.15, 0.35))
Q_NEAR = np.radians((0.0, 33.5, -177.1, 0.0, -36.4, 180.0))  # tool down at POINT


def _goal(runtime, rotation: np.ndarray) -> None:  # type: ignore[no-untyped-def]
    runtime.reset_clocks()
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.GOAL, position=POINT, rotation_to_world=rotation, start_s=runtime.time_s
        )
    )


def test_half_turn_about_the_tool_axis_turns_the_way_joint_6_allows() -> None:
    """Tool down, yaw +90 deg (q6 near 90 deg), then yaw -90 deg: the shortest rotation (179 deg)
    would take joint 6 to 270 deg, past its 266 deg limit; the long way (181 deg) is free. Catches
    the goal motion turning the short way into the limit (it stalled 66 deg off, and was called
    done), or reversing where the shortest way flips at 180 deg."""
    runtime = runtime_at(Q_NEAR)
    site = runtime.plant.data.site("tool")
    _goal(runtime, rpy_to_matrix(math.pi, 0.0, 90.0 * DEG))
    run_for(runtime, 2.5)
    goal = rpy_to_matrix(math.pi, 0.0, -90.0 * DEG)
    _goal(runtime, goal)
    assert runtime.rotation_plan is not None and runtime.rotation_plan.long_way
    worst_m, fastest = 0.0, 0.0
    for _ in range(4500):
        runtime.tick()
        worst_m = max(worst_m, float(np.linalg.norm(site.xpos - POINT)))
        fastest = max(fastest, float(np.linalg.norm(runtime.servo.last_velocity[3:])))
    angle = float(np.linalg.norm(so3_log(site.xmat.reshape(3, 3) @ goal.T)))
    assert angle < 1.0 * DEG, f"{math.degrees(angle):.1f} deg from the goal orientation"
    assert worst_m < 0.002, f"tool point {worst_m * 1e3:.1f} mm off its point"
    assert fastest < 1.05 * DEFAULT_MAX_ANGULAR_SPEED
    assert ROBOT.q_lower_rad[5] < runtime.q[5] < ROBOT.q_upper_rad[5]


def test_a_goal_blocked_by_joint_6_is_named() -> None:
    """RPY (165, -30, 0) from tool down with q6 at 180 deg: both ways round run joint 6 into its
    limit (the goal needs the other wrist configuration). The plan names joint 6 and the run
    stalls with joint 6 at its limit, as the plant shows. Catches a blocked goal reported as
    "out of reach" (the plan naming no joint, or the wrong one)."""
    runtime = runtime_at(Q_NEAR)
    _goal(runtime, rpy_to_matrix(math.pi, 0.0, 0.0))
    run_for(runtime, 1.0)
    _goal(runtime, rpy_to_matrix(165.0 * DEG, -30.0 * DEG, 0.0))
    plan = runtime.rotation_plan
    assert plan is not None and plan.blocked_by is not None
    assert plan.blocked_by.joint == 6 and plan.blocked_by.message.startswith(
        "joint 6 at its limit of 266 deg; "
    )
    run_for(runtime, 2.0)
    q6 = float(runtime.plant.data.qpos[5])
    assert q6 > ROBOT.q_upper_rad[5] - LIMIT_PROJECTION_MARGIN_RAD, f"joint 6 at {math.degrees(q6):.1f} deg"
    blockers = progress_blockers(runtime)
    assert [b.joint for b in blockers if b.kind is BlockerKind.JOINT_LIMIT] == [6], blockers


def test_unwrapped_rotation_error_kernel_matches_the_reference() -> None:
    """The compiled unwrap against cosmos.osc.orientation.unwrap_rotation_vector, on random
    rotations near and far from pi, and both representatives turn the same rotation. Catches the
    long way computed with the wrong sign or length, or the nearer test inverted."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        log = axis * rng.uniform(0.01, math.pi)
        previous = rng.normal(size=3) * rng.uniform(0.0, 4.0)
        got = unwrapped_rotation_error(log, previous)
        expected = unwrap_rotation_vector(log, previous)
        np.testing.assert_allclose(got, expected, atol=1e-12)
        np.testing.assert_allclose(so3_exp(got), so3_exp(log), atol=1e-9)
        other = log * (1.0 - 2.0 * math.pi / np.linalg.norm(log))
        nearer = min((log, other), key=lambda v: float(np.sum((v - previous) ** 2)))
        np.testing.assert_allclose(expected, nearer, atol=1e-12)


def test_a_goal_blocked_in_one_wrist_configuration_names_the_other() -> None:
    """RPY (165, -30, 0) from tool down: both ways round run joint 6 into its limit, and the
    message names the wrist configuration in which the goal is within every range. Checked
    with MuJoCo's own kinematics (not the controller's Pinocchio model): joints 1-3 where the
    unbounded path ends and joints 4-6 as named put the tool at the goal pose, each joint inside
    its range. Catches a blocked goal named only by the joint it hits (the user cannot tell
    which configuration would do), and a configuration named that is not the goal's."""
    runtime = runtime_at(Q_NEAR)
    _goal(runtime, rpy_to_matrix(math.pi, 0.0, 0.0))
    run_for(runtime, 1.0)
    goal = rpy_to_matrix(165.0 * DEG, -30.0 * DEG, 0.0)
    ev = runtime.evaluation
    plan = plan_rotation(ROBOT, ev.q, ev.position, ev.rotation_tool_to_world, POINT, goal)
    blocked = plan.blocked_by
    assert blocked is not None and blocked.other_wrist_rad is not None, plan
    q4, q5, q6 = (round(math.degrees(v)) for v in blocked.other_wrist_rad)
    assert blocked.message.endswith(
        f"in another configuration of the wrist (joints 4, 5, 6 at {q4}, {q5}, {q6} deg there), "
        "which a motion does not turn into"
    ), blocked.message
    shortest = so3_log(goal @ ev.rotation_tool_to_world.T)
    _, unbounded = _follow(
        ROBOT, ev.q, ev.position, ev.rotation_tool_to_world, POINT - ev.position, shortest, -math.inf
    )
    q = np.concatenate((unbounded[:3], blocked.other_wrist_rad))
    assert np.all(ROBOT.q_lower_rad < q) and np.all(q < ROBOT.q_upper_rad), np.degrees(q)
    plant = runtime.plant
    data = mujoco.MjData(plant.model)
    data.qpos[:6] = q
    mujoco.mj_kinematics(plant.model, data)
    site = data.site("tool")
    assert np.linalg.norm(site.xpos - POINT) < 1e-3, site.xpos
    angle = float(np.linalg.norm(so3_log(site.xmat.reshape(3, 3) @ goal.T)))
    assert angle < 0.5 * DEG, f"{math.degrees(angle):.2f} deg from the goal orientation"


def test_the_frame_jacobian_places_the_tool_as_the_forward_kinematics_do() -> None:
    """The plan's one kinematics pass per Newton step reads the tool's pose the Jacobian left.

    Catches a Pinocchio whose LOCAL_WORLD_ALIGNED ``computeFrameJacobian`` stops placing
    the frame (``data.oMf``), or places it by other products than
    ``framesForwardKinematics``: the plan's predicted path and goal configuration would move.
    """
    import pinocchio as pin

    model, frame = ROBOT.model, ROBOT.tool_frame
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = rng.uniform(ROBOT.q_lower_rad, ROBOT.q_upper_rad)
        by_jacobian, by_kinematics = model.createData(), model.createData()
        pin.computeFrameJacobian(model, by_jacobian, q, frame, pin.LOCAL_WORLD_ALIGNED)
        pin.framesForwardKinematics(model, by_kinematics, q)
        assert np.array_equal(by_jacobian.oMf[frame].homogeneous, by_kinematics.oMf[frame].homogeneous)
