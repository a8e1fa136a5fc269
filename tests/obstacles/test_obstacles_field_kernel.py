"""The compiled field kernel (cosmos.obstacles.kernels.field) against Pinocchio and the Python field maths.

Seeded random states; the kinematics are compared with Pinocchio's
``computeJointJacobians``, the torques with the point Jacobians taken by
finite differences of Pinocchio's placements, the magnitudes with the Python
:func:`cosmos.osc.firas.repulsion_magnitude`.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from cosmos.obstacles import arm_capsules
from cosmos.obstacles.capsules import joint_reach_m
from cosmos.obstacles.field import FieldParameters, chain_table
from cosmos.obstacles.kernels import field as fk
from cosmos.osc.firas import repulsion_magnitude
from tests.obstacles.obstacle_scenes import robot


def _chain() -> np.ndarray:
    return chain_table(robot(), joint_reach_m(robot(), arm_capsules(robot())))


def _state(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    return rng.uniform(robot().q_lower_rad, robot().q_upper_rad), rng.normal(size=6)


def test_chain_kinematics_match_pinocchio() -> None:
    """Frames, Jacobian columns, twists and the speed bound equal Pinocchio's at random states.

    Catches a wrong joint axis (the PUMA's two unaligned joints), a transposed
    placement rotation, ``w x p`` for ``p x w`` in a column, or a twist summed
    over the wrong joints.
    """
    model, data = robot().model, robot().model.createData()
    chain, frames = _chain(), np.zeros((6, fk.FRAMES))
    reach = joint_reach_m(robot(), arm_capsules(robot()))
    rng = np.random.default_rng(1)
    for _ in range(20):
        q, qd = _state(rng)
        speed = fk.chain_kinematics_into(frames, chain, q, qd)
        pin.computeJointJacobians(model, data, q)
        for k in range(6):
            rotation = frames[k, fk.FRAME_ROTATION : fk.FRAME_ROTATION + 9].reshape(3, 3)
            np.testing.assert_allclose(rotation, data.oMi[k + 1].rotation, atol=1e-12)
            np.testing.assert_allclose(
                frames[k, fk.FRAME_ORIGIN : fk.FRAME_ORIGIN + 3], data.oMi[k + 1].translation, atol=1e-12
            )
        np.testing.assert_allclose(frames[:, fk.FRAME_COLUMN : fk.FRAME_COLUMN + 6].T, data.J, atol=1e-12)
        twists = np.array([data.J[:, : k + 1].dot(qd[: k + 1]) for k in range(6)])
        np.testing.assert_allclose(frames[:, fk.FRAME_TWIST :], twists, atol=1e-12)
        assert speed == pytest.approx(float(np.abs(qd).dot(reach)), rel=1e-12)


def test_compiled_magnitude_is_the_python_one() -> None:
    """The compiled FIRAS + damping magnitude equals the readable Python one, edges included.

    Catches a lost cap, damping applied while receding, or force beyond rho_0.
    """
    rng = np.random.default_rng(2)
    cases = [
        (0.1, 0.1, 1e-3, 300.0, 400.0, 1.0),
        (0.0, 0.1, 1e-3, 300.0, 400.0, 0.5),
        (-0.01, 0.1, 1e-3, 0, 400, 0),
    ]
    for _ in range(300):
        rho_0 = float(rng.uniform(0.02, 0.2))
        cases.append(
            (
                float(rng.uniform(-0.01, 1.2 * rho_0)),
                rho_0,
                float(rng.uniform(1e-4, 1e-2)),
                float(rng.uniform(0.0, 500.0)),
                float(rng.uniform(10.0, 500.0)),
                float(rng.normal()),
            )
        )
    for case in cases:
        assert fk.repulsion_magnitude(*case) == pytest.approx(
            repulsion_magnitude(*case), rel=1e-12, abs=1e-12
        )


def _point_jacobian(q: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
    """d(point fixed to link)/dq by central differences of Pinocchio's placements. # (3, 6)"""
    model, data = robot().model, robot().model.createData()
    pin.forwardKinematics(model, data, q)
    local = data.oMi[link + 1].actInv(point)
    step, columns = 1e-6, []
    for e in np.eye(6):
        ends = []
        for sign in (1.0, -1.0):
            pin.forwardKinematics(model, data, q + sign * step * e)
            ends.append(data.oMi[link + 1].act(local))
        columns.append((ends[0] - ends[1]) / (2 * step))
    return np.array(columns).T


def test_torque_is_the_sum_of_point_jacobians_transposed_times_the_forces() -> None:
    """Gamma = sum_a J_a^T F_a, with J_a the point Jacobian and F_a from the Python magnitude.

    Catches a force applied on the wrong joints (a link's wrench carried by
    joints beyond it), a wrong moment arm, the approach speed taken with the
    wrong sign or without the obstacle's velocity, the gain factor or rho_0 of
    the wrong obstacle, and the acting table's nearest link or strongest force; and
    the links' part (every link but the tool's, which the servo projects into the
    null space) with the tool's forces in it, or the nearest of those links wrong.
    """
    par = FieldParameters()
    chain, frames = _chain(), np.zeros((6, fk.FRAMES))
    rng = np.random.default_rng(3)
    obstacles = np.zeros((3, fk.OBSTACLE))
    obstacles[:, fk.OBSTACLE_VELOCITY : fk.OBSTACLE_VELOCITY + 3] = rng.normal(scale=0.2, size=(3, 3))
    obstacles[:, fk.OBSTACLE_RHO_0] = (0.1, 0.05, 0.12)
    obstacles[:, fk.OBSTACLE_GAIN] = (1.0, 2.0, 0.5)
    parameters = np.array((par.eta, par.damping_ns_per_m, par.force_cap_n, 1.0))
    for _ in range(10):
        q, qd = _state(rng)
        fk.chain_kinematics_into(frames, chain, q, qd)
        count = 7
        approaches = np.zeros((count + 2, fk.APPROACH))
        approaches[:count, fk.APPROACH_LINK] = rng.integers(0, 6, count)
        approaches[:count, fk.APPROACH_OBSTACLE] = rng.integers(0, 3, count)
        origins = frames[approaches[:count, 0].astype(int), fk.FRAME_ORIGIN : fk.FRAME_ORIGIN + 3]
        approaches[:count, fk.APPROACH_POINT : fk.APPROACH_POINT + 3] = origins + rng.normal(
            scale=0.1, size=(count, 3)
        )
        normals = rng.normal(size=(count, 3))
        approaches[:count, fk.APPROACH_NORMAL :] = normals / np.linalg.norm(normals, axis=1)[:, None]
        approaches[:count, fk.APPROACH_DISTANCE] = rng.uniform(0.005, 0.1, count)
        approaches[count:] = 99.0  # rows past the count are not read
        torque, acting = np.zeros(6), np.full((3, fk.ACTING), 7.0)
        link_torque, nearest = np.zeros(6), np.zeros(fk.NEAREST)
        fk.field_torque_into(
            torque, link_torque, nearest, acting, approaches, count, frames, obstacles, parameters
        )
        expected, expected_links = np.zeros(6), np.zeros(6)
        nearest_expected = [np.inf, -1.0, -1.0]
        strongest: dict[int, list[float]] = {}
        for link, j, distance, *rest in approaches[:count].tolist():
            k, o = int(link), int(j)
            point, normal = np.array(rest[:3]), np.array(rest[3:])
            jacobian = _point_jacobian(q, k, point)  # (3, 6)
            closing = -normal.dot(
                jacobian.dot(qd) - obstacles[o, fk.OBSTACLE_VELOCITY : fk.OBSTACLE_VELOCITY + 3]
            )
            scale = obstacles[o, fk.OBSTACLE_GAIN]
            magnitude = repulsion_magnitude(
                distance,
                obstacles[o, fk.OBSTACLE_RHO_0],
                scale * par.eta,
                scale * par.damping_ns_per_m,
                par.force_cap_n,
                float(closing),
            )
            expected += jacobian.T.dot(magnitude * normal)
            if k < 5:  # every link but the tool's
                expected_links += jacobian.T.dot(magnitude * normal)
                if distance < nearest_expected[0]:
                    nearest_expected = [distance, k, o]
            seen = strongest.setdefault(o, [distance, k, magnitude])
            if distance < seen[0]:
                seen[:2] = [distance, k]
            seen[2] = max(seen[2], magnitude)
        np.testing.assert_allclose(torque, expected, rtol=1e-6, atol=1e-6 * np.abs(expected).max())
        np.testing.assert_allclose(link_torque, expected_links, atol=1e-6 * np.abs(expected).max())
        np.testing.assert_array_equal(nearest, nearest_expected)
        for o in range(3):
            if o in strongest:
                np.testing.assert_allclose(acting[o, 1:], strongest[o], rtol=1e-6)
                assert acting[o, fk.ACTING_FLAG] == 1.0
            else:
                assert acting[o, fk.ACTING_FLAG] == 0.0
        parameters[fk.PARAMETER_ENABLED] = 0.0
        off = np.zeros(6)
        fk.field_torque_into(
            off, np.zeros(6), nearest, acting, approaches, count, frames, obstacles, parameters
        )
        parameters[fk.PARAMETER_ENABLED] = 1.0
        assert not np.any(off)
        assert acting[:, fk.ACTING_FLAG].sum() == len(strongest)
