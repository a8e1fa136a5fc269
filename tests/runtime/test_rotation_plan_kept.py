"""The rotation plan's kept Pinocchio work space: plans made with it are plans made afresh."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from cosmos.osc.orientation import so3_exp
from cosmos.runtime import rotation_plan
from cosmos.runtime.rotation_plan import RotationPlan, kinematics_data, plan_rotation
from tests.runtime.runtime_helpers import Q_NEAR, ROBOT, tool_pose


def _assert_same(kept: RotationPlan, fresh: RotationPlan) -> None:
    np.testing.assert_array_equal(kept.rotation_vector, fresh.rotation_vector)
    np.testing.assert_array_equal(kept.goal_q, fresh.goal_q)
    assert kept.long_way == fresh.long_way
    assert kept.blocked_by == fresh.blocked_by


def test_a_kept_work_space_plans_as_a_fresh_one(monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a plan that reads what the kept Pinocchio data held from the plan before it (a frame
    placed for another configuration, a Jacobian of another path): plans made one after another,
    from configurations all round the start, toward goals of up to 0.2 m and 2 rad (some blocked,
    some the long way round), equal to the bit the plans each made with data created for it alone."""
    rng = np.random.default_rng(3)
    cases = []
    for _ in range(10):
        q = Q_NEAR + rng.normal(0.0, 0.2, 6)
        position, rotation = tool_pose(q)
        goal_position = position + rng.normal(0.0, 0.07, 3)
        goal_rotation = so3_exp(rng.normal(0.0, 1.2, 3)).dot(rotation)
        cases.append((ROBOT, q, position, rotation, goal_position, goal_rotation))
    kept = [plan_rotation(*case) for case in cases]
    assert kinematics_data(ROBOT.model) is kinematics_data(ROBOT.model)  # one, kept

    def fresh_data(model: pin.Model) -> pin.Data:
        return model.createData()

    monkeypatch.setattr(rotation_plan, "kinematics_data", fresh_data)
    for case, plan in zip(cases, kept, strict=True):
        _assert_same(plan, plan_rotation(*case))


def test_only_a_few_models_are_kept() -> None:
    """Catches the kept work spaces growing with every model a run makes (each GRASP and RELEASE
    builds the controller's model again): the oldest goes once more than a few are kept."""
    models = [pin.buildSampleModelManipulator() for _ in range(rotation_plan.KINEMATICS_DATA_KEPT + 2)]
    for model in models:
        kinematics_data(model)
    held = [kept_model for kept_model, _ in rotation_plan._KINEMATICS_DATA.values()]
    assert len(held) <= rotation_plan.KINEMATICS_DATA_KEPT
    assert any(kept is models[-1] for kept in held)  # by identity: equal models compare equal
    assert not any(kept is models[0] for kept in held)
