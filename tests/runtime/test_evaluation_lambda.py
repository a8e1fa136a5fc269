"""An evaluation's Lambda asked for alone (:attr:`cosmos.runtime.parameters.Evaluation.lambda_`)."""

from __future__ import annotations

import math

import numpy as np

from cosmos.robot_model import build_robot_model
from cosmos.runtime.parameters import ParameterLevel

DEG = math.pi / 180.0


def test_lambda_alone_is_the_operational_dynamics_lambda_to_the_last_bit() -> None:
    """Catches the Lambda a segment's start reads (its effective masses, a landing's mass: they
    feed the servo's spring masses and gains, and the log) differing from the one the whole
    operational dynamics gave it before (eq. 27, section 5's blend), in any bit: at 40 random
    configurations and 10 within a few degrees of the PUMA's wrist singularity (the blended
    inverse), against ``dynamics.lambda_`` and, away from it, the plain inverse of ``J A^-1 J^T``."""
    robot = build_robot_model()
    level = ParameterLevel(robot)
    rng = np.random.default_rng(11)
    blended = 0
    for k in range(50):
        q = rng.uniform(robot.q_lower_rad, robot.q_upper_rad) * 0.8
        if k >= 40:  # q2 + q3 + q5 = -pi: the wrist's axes 4 and 6 nearly aligned
            q5 = (k - 39) * 0.3 * DEG
            q = np.array((0.1, 30.0 * DEG, -math.pi - 30.0 * DEG - q5, 0.0, q5, 0.3))
        evaluation = level.evaluate(q, rng.normal(size=6))
        alone = evaluation.lambda_
        whole = evaluation.dynamics
        assert np.array_equal(alone, whole.lambda_)
        if whole.singular.any():
            blended += 1
        else:
            jacobian = evaluation.jacobian
            assert np.array_equal(alone, np.linalg.inv(jacobian.dot(evaluation.inertia_inv.dot(jacobian.T))))
    assert blended >= 3  # the blended inverse was reached
