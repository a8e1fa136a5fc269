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
