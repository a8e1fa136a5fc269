"""Helpers shared by the model, workcell and plant tests (not a test module)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from cosmos.robot_model import RobotModel


def solve_ik(robot: RobotModel, target: pin.SE3, q0: np.ndarray) -> np.ndarray:
    """Joint angles that put the tool frame at ``target`` (world), by Newton steps from ``q0``."""
    model, data = robot.model, robot.data
    q = np.array(q0, dtype=float)
    for _ in range(100):
        pin.framesForwardKinematics(model, data, q)
        error = pin.log6(data.oMf[robot.tool_frame].actInv(target)).vector  # in the tool frame
        if np.linalg.norm(error) < 1e-12:
            return q
        jacobian = pin.computeFrameJacobian(model, data, q, robot.tool_frame, pin.LOCAL)
        q = q + np.linalg.solve(jacobian, error)
    raise AssertionError(f"IK did not converge to {target}")


def tool_pose(robot: RobotModel, q: np.ndarray) -> pin.SE3:
    """World pose of the tool frame at ``q``."""
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return robot.data.oMf[robot.tool_frame].copy()


def tool_jacobian(robot: RobotModel, q: np.ndarray) -> np.ndarray:
    """Tool-point Jacobian, world axes (linear rows first), ``(6, 6)``."""
    return pin.computeFrameJacobian(
        robot.model, robot.data, q, robot.tool_frame, pin.LOCAL_WORLD_ALIGNED
    ).copy()
