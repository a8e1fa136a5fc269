"""The obstacle field's compiled kernels on the seven-joint Panda, against Pinocchio.

The field is written for n joints (issue 16): its chain kinematics must equal Pinocchio's
joint frames, Jacobian and link twists for the Panda, and its torque for a push on a link
must be ``J_p^T F`` with the point Jacobian of Pinocchio's Panda model. Catches a
six-joint loop or array left in the chain, the torque or the capsules' links.
"""

from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin

from cosmos.obstacles import arm_capsules
from cosmos.obstacles.capsules import joint_reach_m
from cosmos.obstacles.field import FieldParameters, chain_table
from cosmos.obstacles.kernels import field as fk
from cosmos.osc.firas import repulsion_magnitude
from cosmos.robot_model import RobotModel, build_robot_model
from cosmos.robots import PANDA


@functools.cache
def panda() -> RobotModel:
    return build_robot_model(PANDA)


def test_capsules_cover_the_seven_links() -> None:
    capsules = arm_capsules(panda())
    assert sorted(set(capsules.links)) == [f"link{k}" for k in range(1, 8)]
    assert set(capsules.joint.tolist()) == set(range(7))


def test_chain_kinematics_and_field_torque_match_pinocchio() -> None:
    robot = panda()
    model, data = robot.model, robot.model.createData()
    capsules = arm_capsules(robot)
    chain, frames = chain_table(robot, joint_reach_m(robot, capsules)), np.zeros((7, fk.FRAMES))
    par = FieldParameters()
    parameters = np.array((par.eta, par.damping_ns_per_m, par.force_cap_n, 1.0))
    obstacles = np.zeros((1, fk.OBSTACLE))
    obstacles[0, fk.OBSTACLE_RHO_0], obstacles[0, fk.OBSTACLE_GAIN] = 0.1, 1.0
    rng = np.random.default_rng(16)
    for _ in range(10):
        q, qd = rng.uniform(robot.q_lower_rad, robot.q_upper_rad), rng.normal(size=7)
        fk.chain_kinematics_into(frames, chain, q, qd)
        pin.computeJointJacobians(model, data, q)
        for k in range(7):
            rotation = frames[k, fk.FRAME_ROTATION : fk.FRAME_ROTATION + 9].reshape(3, 3)
            np.testing.assert_allclose(rotation, data.oMi[k + 1].rotation, atol=1e-12)
        np.testing.assert_allclose(frames[:, fk.FRAME_COLUMN : fk.FRAME_COLUMN + 6].T, data.J, atol=1e-12)
        twists = np.array([data.J[:, : k + 1].dot(qd[: k + 1]) for k in range(7)])
        np.testing.assert_allclose(frames[:, fk.FRAME_TWIST :], twists, atol=1e-12)
        # One push on link k at a point near its origin.
        k = int(rng.integers(0, 7))
        point = data.oMi[k + 1].translation + rng.normal(scale=0.05, size=3)
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        approach = np.zeros((1, fk.APPROACH))
        approach[0, fk.APPROACH_LINK], approach[0, fk.APPROACH_DISTANCE] = k, 0.03
        approach[0, fk.APPROACH_POINT : fk.APPROACH_POINT + 3] = point
        approach[0, fk.APPROACH_NORMAL :] = normal
        torque, links, acting = np.zeros(7), np.zeros(7), np.zeros((1, fk.ACTING))
        nearest = np.zeros(fk.NEAREST)
        fk.field_torque_into(torque, links, nearest, acting, approach, 1, frames, obstacles, parameters)
        # The tool's link (the last) acts whole; the others' share is what the null space may take.
        np.testing.assert_allclose(links, 0.0 if k == 6 else torque, atol=1e-12)
        # Point Jacobian of the point on link k: J_v - p x J_w over joints 0..k, zero beyond.
        jacobian = np.zeros((3, 7))
        linear, angular = data.J[:3, : k + 1], data.J[3:, : k + 1]
        jacobian[:, : k + 1] = linear + np.cross(angular.T, point).T
        closing = -normal.dot(jacobian.dot(qd))
        magnitude = repulsion_magnitude(0.03, 0.1, par.eta, par.damping_ns_per_m, par.force_cap_n, closing)
        np.testing.assert_allclose(torque, jacobian.T.dot(magnitude * normal), rtol=1e-9, atol=1e-9)
