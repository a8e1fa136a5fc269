"""Through the wrist singularity (seed section 5).

With q4 = 0 and the tool pointing down, q5 = -pi - q2 - q3: a straight,
timed move of the tool between q3 = -204 deg and q3 = -216 deg (q2 = 30 deg)
takes q5 from -6 deg through 0 to +6 deg, where joints 4 and 6 align and
the end effector loses one rotational direction. Treating the arm as
redundant in the orthogonal subspace keeps the torques bounded and the
position controlled all the way.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from cosmos.osc.motion import PoseTrajectory
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint
from tests.runtime.runtime_helpers import ROBOT, run_for, runtime_at

DEG = math.pi / 180.0


def wrist_configuration(q3_deg: float) -> np.ndarray:
    q2, q3 = 30.0 * DEG, q3_deg * DEG
    return np.array((0.0, q2, q3, 0.0, -math.pi - q2 - q3, math.pi))


def tool_pose(q: np.ndarray) -> pin.SE3:
    data = ROBOT.model.createData()
    pin.framesForwardKinematics(ROBOT.model, data, q)
    return data.oMf[ROBOT.tool_frame].copy()


def test_straight_line_through_the_wrist_singularity() -> None:
    q_start, q_end = wrist_configuration(-204.0), wrist_configuration(-216.0)
    start, end = tool_pose(q_start), tool_pose(q_end)
    assert np.allclose(start.rotation[:, 2], (0, 0, -1), atol=1e-9)  # tool down at both ends
    runtime = runtime_at(q_start)
    run_for(runtime, 0.3)
    duration = 2.0
    site = runtime.plant.data.site("tool")
    trajectory = PoseTrajectory.between(
        site.xpos.copy(), site.xmat.reshape(3, 3).copy(), end.translation, end.rotation, duration
    )
    t0 = runtime.time_s
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.TRAJECTORY,
            position=end.translation.copy(),
            rotation_to_world=end.rotation.copy(),
            start_s=t0,
            trajectory=trajectory,
        )
    )
    limits = np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm)
    q5, errors, torques, singular = [], [], [], []
    end_s = t0 + duration + 0.5
    while runtime.time_s < end_s:
        runtime.tick()
        desired = trajectory.sample(runtime.time_s - t0).position
        errors.append(np.linalg.norm(site.xpos - desired))
        torques.append(np.abs(runtime.tau) / limits)
        q5.append(runtime.q[4])
        singular.append(bool(runtime.evaluation.dynamics.singular.any()))
    q5_path = np.array(q5)
    assert q5_path.min() < -0.05 and q5_path.max() > 0.05, "the move did not cross q5 = 0"
    assert any(singular), "section 5's treatment never engaged: not a singular path"
    assert max(errors) < 0.005, f"position error {max(errors) * 1e3:.2f} mm"
    assert np.max(torques) < 1.0, f"torque at {np.max(torques):.0%} of a drive limit"


def test_roll_about_the_singular_direction_keeps_the_tool_point() -> None:
    """q5 = 0.8 deg with the tool tilted (joints 4 and 6 nearly aligned), then a 15 deg roll about
    world x, the direction the wrist has lost: the tool point must stay within 5 mm. Catches the
    singular direction removed orthogonally (it mixes a rotation with a translation of the tool
    point, so the roll error drove the tool 100 mm sideways) and the Coulomb look-ahead pushing
    joint 1 toward the part of the command the arm cannot do."""
    from cosmos.osc.orientation import so3_exp

    runtime = runtime_at(np.radians((0.0, 36.6, -191.4, 0.0, 0.8, 180.0)))
    run_for(runtime, 0.2)
    ev = runtime.evaluation
    start = ev.position.copy()
    goal = so3_exp(np.array((15.0 * DEG, 0.0, 0.0))).dot(ev.rotation_tool_to_world)
    runtime.set_setpoint(
        ServoSetpoint(mode=MotionMode.GOAL, position=start, rotation_to_world=goal, start_s=runtime.time_s)
    )
    samples = run_for(runtime, 2.0)
    assert runtime.evaluation.dynamics.singular.any(), "not at the singularity"
    worst = max(float(np.linalg.norm(position - start)) for _, position, _ in samples)
    assert worst < 0.005, f"tool point moved {worst * 1e3:.1f} mm"
    blocked = (np.eye(6) - runtime.servo.singular_projection) @ runtime.servo.last_error
    assert np.linalg.norm(blocked[3:]) > 5.0 * DEG, "the projection should hold the roll back"
    from cosmos.runtime.blockers import BlockerKind, progress_blockers

    named = [b.message for b in progress_blockers(runtime) if b.kind is BlockerKind.SINGULARITY]
    assert len(named) == 1 and named[0].startswith("the wrist singularity"), named
