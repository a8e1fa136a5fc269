"""The compiled orientation log and the evaluation's hand-over to the servo, against the NumPy maths."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.orientation import pose_error, so3_exp, so3_log
from cosmos.robot_model import build_robot_model
from cosmos.runtime import servo_kernel as sk
from cosmos.runtime.parameter_kernel import complete_evaluation, refold, rotation_log
from cosmos.runtime.parameters import ParameterLevel

RNG = np.random.default_rng(7)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("angle", [0.0, 1e-6, 3e-5, 0.3, 1.5, 3.0, np.pi - 1e-3, np.pi - 1e-7])
def test_rotation_log_matches_so3_log_over_the_whole_range(angle: float) -> None:
    """Catches a wrong branch of the compiled log: small-angle series, generic, or the near-pi axis."""
    for _ in range(5):
        rotation = so3_exp(angle * _unit(RNG.normal(size=3)))
        expected = so3_log(rotation)
        got = rotation_log(np.ascontiguousarray(rotation))
        if angle > np.pi - 1e-2:  # at pi, +n and -n are the same rotation
            assert np.allclose(so3_exp(got), rotation, atol=1e-9)
            assert np.linalg.norm(got) == pytest.approx(np.linalg.norm(expected), abs=1e-9)
        else:
            assert np.allclose(got, expected, atol=1e-12)


def test_refold_writes_the_evaluation_and_the_reference_error_into_the_servo_blocks() -> None:
    """Catches a block written to the wrong row, or x_e - x_d with the wrong sign or frame."""
    robot = build_robot_model()
    level = ParameterLevel(robot)
    q = np.array((0.2, 0.6, -2.9, 0.3, -0.7, 2.8))
    ev = level.evaluate(q, RNG.normal(scale=0.2, size=6))
    goal_position = ev.position + np.array((0.03, -0.02, 0.05))
    goal_rotation = so3_exp(np.array((0.2, -0.1, 0.4))).dot(ev.rotation_tool_to_world)
    omega = np.diag((1.0, 1.0, 0.0, 1.0, 1.0, 1.0))
    stacked, vectors = np.zeros((6, 25)), np.zeros((sk.VECTORS, 6))
    matrices = np.zeros((sk.MATRICES, 6, 6))
    refold(
        ev.q,
        ev.position,
        ev.rotation_tool_to_world,
        ev.rotation_sensor_to_world,
        ev.sensor_to_tool_m,
        ev.sensor_to_com_m,
        ev.inertia,
        ev.inertia_inv,
        ev.jacobian,
        ev.bias,
        ev.gravity,
        ev.jdot_qdot,
        np.zeros(6),
        omega,
        np.eye(6) - omega,
        goal_position,
        goal_rotation,
        np.array((30.0, 20.0, 0.02, 2000.0, 1.0, 0.5)),
        np.zeros(6),
        stacked,
        vectors,
        matrices,
    )
    expected_error = pose_error(ev.position, ev.rotation_tool_to_world, goal_position, goal_rotation)
    assert np.allclose(vectors[sk.REFERENCE_ERROR], expected_error, atol=1e-12)
    assert np.array_equal(vectors[sk.EVALUATION_Q], ev.q)
    assert np.array_equal(vectors[sk.GRAVITY], ev.gravity)
    assert np.array_equal(
        vectors[sk.SENSOR_OFFSETS], np.concatenate((ev.sensor_to_tool_m, ev.sensor_to_com_m))
    )
    assert np.array_equal(matrices[sk.JACOBIAN], ev.jacobian)
    assert np.array_equal(matrices[sk.OMEGA_BAR], np.eye(6) - omega)
    assert np.array_equal(matrices[sk.ROTATION_SENSOR, :3, :3], ev.rotation_sensor_to_world)


def test_complete_evaluation_matches_pinocchio() -> None:
    """Catches a triangle copied the wrong way, b = nle - g with the wrong sign, or h not Jdot qd."""
    import pinocchio as pin

    robot = build_robot_model()
    model, data = robot.model, robot.model.createData()
    q, qd = RNG.uniform(-1.0, 1.0, size=6), RNG.normal(size=6)
    pin.computeAllTerms(model, data, q, qd)
    frame = robot.tool_frame
    tool = pin.updateFramePlacement(model, data, frame)
    jdot = pin.getFrameJacobianTimeVariation(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
    minv = pin.computeMinverse(model, data, q).copy()
    gravity = pin.computeGeneralizedGravity(model, data, q).copy()
    inertia, inertia_inv, bias, h, *_ = complete_evaluation(
        data.M,
        minv,
        data.nle,
        gravity,
        jdot,
        qd,
        np.ascontiguousarray(tool.rotation),
        np.eye(3),
        np.zeros(3),
        np.zeros(3),
    )
    upper = np.triu(pin.crba(model, model.createData(), q))
    assert np.allclose(inertia, upper + np.triu(upper, 1).T, atol=1e-12)
    assert np.allclose(inertia, inertia.T) and np.allclose(inertia.dot(inertia_inv), np.eye(6), atol=1e-9)
    coriolis = pin.rnea(model, model.createData(), q, qd, np.zeros(6)) - gravity
    assert np.allclose(bias, coriolis, atol=1e-10)
    assert np.allclose(h, jdot.dot(qd), atol=1e-12)
