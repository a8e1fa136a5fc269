"""The rotation plan's compiled step against NumPy's (LAPACK's solve), and the plans they make."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from cosmos.osc.orientation import so3_exp
from cosmos.runtime.kernels.path_step import path_step_into
from cosmos.runtime.rotation_plan import DAMPING, _numpy_step, plan_rotation
from tests.runtime.runtime_helpers import Q_NEAR, ROBOT, tool_pose


def test_the_compiled_step_is_numpys() -> None:
    """Catches the compiled step's pose on the path, its rotation error's sign or order, a row of
    J J^T or the Cholesky solve gone wrong: from 40 configurations, a step toward points of paths
    of up to 0.2 m and 1.5 rad must move the joints as NumPy's step (LAPACK's solve) does."""
    rng = np.random.default_rng(7)
    model, data, frame = ROBOT.model, ROBOT.model.createData(), ROBOT.tool_frame
    for _ in range(40):
        q = Q_NEAR + rng.normal(0.0, 0.3, 6)
        position, rotation = tool_pose(Q_NEAR)
        displacement, turn = rng.normal(0.0, 0.1, 3), rng.normal(0.0, 0.8, 3)
        s = float(rng.uniform(0.0, 1.0))
        jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
        pose = data.oMf[frame].homogeneous
        compiled, numpy = q.copy(), q.copy()
        path_step_into(jacobian, pose, s, position, displacement, turn, rotation, compiled, DAMPING)
        _numpy_step(jacobian, pose, s, position, displacement, turn, rotation, numpy, DAMPING)
        assert np.abs(compiled - q).max() > 1e-6  # it moved
        np.testing.assert_allclose(compiled, numpy, rtol=0.0, atol=1e-10)


def test_compiled_and_numpy_plans_agree() -> None:
    """Catches the runtime's plan (compiled) and the checker's (NumPy) choosing differently: the
    way round, the joint that stops it, and the goal configuration for goals all round the start."""
    rng = np.random.default_rng(11)
    position, rotation = tool_pose(Q_NEAR)
    for _ in range(12):
        goal_position = position + rng.normal(0.0, 0.08, 3)
        goal_rotation = so3_exp(rng.normal(0.0, 1.2, 3)).dot(rotation)
        args = (ROBOT, Q_NEAR, position, rotation, goal_position, goal_rotation)
        compiled, numpy = plan_rotation(*args), plan_rotation(*args, compiled=False)
        assert compiled.long_way == numpy.long_way
        assert (compiled.blocked_by is None) == (numpy.blocked_by is None)
        if compiled.blocked_by is not None and numpy.blocked_by is not None:
            assert compiled.blocked_by.joint == numpy.blocked_by.joint
        np.testing.assert_allclose(compiled.goal_q, numpy.goal_q, rtol=0.0, atol=1e-9)
