"""Redundancy (seed section 4): a position-only task, 3 of the arm's 6 dimensions.

The end-effector command (eq. 26-29, with Lambda_r and the dynamically
consistent inverse of eq. 28) leaves a three-dimensional self-motion (the
wrist) that eq. 31's dissipation does not reach (eq. 33). The null-space
damping of eq. 34 makes the closed loop asymptotically stable (eq. 38): the
joint velocities decay. The drives' friction is switched off in the plant so
that only the controller can dissipate the self-motion.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from cosmos.osc.dynamics import null_space_damping, operational_dynamics
from cosmos.osc.motion import goal_command
from cosmos.plant import Plant
from tests.runtime.runtime_helpers import ROBOT

KP, KV = 400.0, 40.0


def run_position_task(xi_q: float, duration_s: float = 3.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drive the tool point to a goal 5 cm away with the wrist spinning; return |qd|, t and error."""
    plant = Plant()
    plant.model.dof_damping[:] = 0.0
    plant.model.dof_frictionloss[:] = 0.0
    plant.reset()
    plant.data.qvel[3:] = (0.8, -0.6, 0.8)  # set the wrist's self-motion going
    model, data = ROBOT.model, ROBOT.model.createData()
    q, _ = plant.read_encoders()
    pin.framesForwardKinematics(model, data, q)
    goal = data.oMf[ROBOT.tool_frame].translation + np.array((0.03, -0.04, 0.0))
    speeds, times, errors = [], [], []
    while plant.time_s < duration_s:
        q, qd = plant.read_encoders()
        pin.computeAllTerms(model, data, q, qd)
        pin.updateFramePlacements(model, data)
        inertia = np.triu(data.M) + np.triu(data.M, 1).T
        jacobian = pin.getFrameJacobian(model, data, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)[:3]
        jdot = pin.getFrameJacobianTimeVariation(model, data, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)[:3]
        gravity = pin.computeGeneralizedGravity(model, data, q)
        dynamics = operational_dynamics(inertia, jacobian, data.nle - gravity, gravity, jdot @ qd)
        error = data.oMf[ROBOT.tool_frame].translation - goal
        command = goal_command(
            np.concatenate((error, np.zeros(3))),
            np.concatenate((jacobian @ qd, np.zeros(3))),
            KP,
            KV,
            0.25,
            1.0,
        )[:3]
        torque = jacobian.T @ (dynamics.lambda_ @ command) + dynamics.compensation_torque  # eq. 29
        torque += null_space_damping(dynamics, inertia, qd, xi_q)  # eq. 34
        plant.step(torque)
        speeds.append(np.abs(qd).max())
        times.append(plant.time_s)
        errors.append(np.linalg.norm(error))
    return np.array(speeds), np.array(times), np.array(errors)


def test_null_space_damping_makes_the_self_motion_decay() -> None:
    speeds, times, errors = run_position_task(xi_q=20.0)
    assert errors[-1] < 1e-3, f"position error {errors[-1] * 1e3:.2f} mm"
    assert speeds[times > 2.9].max() < 1e-3, f"joint speed {speeds[-1]:.2e} rad/s at 3 s"


def test_without_it_the_self_motion_goes_on() -> None:
    """Eq. 33: the task's own damping cannot reach the self-motion (so the test above is not trivial)."""
    speeds, times, errors = run_position_task(xi_q=0.0)
    assert errors[-1] < 1e-3
    assert speeds[times > 2.9].max() > 0.05
