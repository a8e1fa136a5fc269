"""The realistic plant's arm differs from the controller's model by the documented amounts.

The plant is read from MuJoCo's compiled model, the controller's from Pinocchio; the
published Coulomb friction from the drive table (shared/reference/puma560.md).
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from cosmos.plant import Plant
from cosmos.realism import PlantRealism
from cosmos.realism.arm_error import FRICTION_SCALE
from cosmos.robot_model import build_robot_model
from cosmos.robots import PUMA560
from cosmos.workcell import ARM_XML, JOINT_NAMES

ROBOT = build_robot_model()
BARE_ARM = pin.buildModelFromMJCF(str(ARM_XML))

MOTOR_COULOMB = (
    (0.395, -0.435),
    (0.126, -0.071),
    (0.132, -0.105),
    (11.2e-3, -16.9e-3),
    (9.26e-3, -14.5e-3),
    (3.96e-3, -10.5e-3),
)
"""Tc+ / Tc- at the motor [N m], the drive table."""
GEAR_RATIOS = (-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686)


def link_bodies(model: mujoco.MjModel) -> list[int]:
    return [int(model.jnt_bodyid[model.joint(name).id]) for name in JOINT_NAMES]


def controller_link(joint: int) -> tuple[float, np.ndarray]:
    """Mass and principal inertias (about the centre of mass) of the link ``joint`` moves, in the
    controller's Pinocchio model of the bare arm (link 6 there also carries the tool)."""
    inertia = BARE_ARM.inertias[joint + 1]
    return float(inertia.mass), np.linalg.eigvalsh(inertia.inertia)


@pytest.mark.parametrize("seed", [0, 11])
def test_plant_links_differ_from_the_controller_s_by_the_drawn_factors_within_the_scale(seed: int) -> None:
    """Catches a plant built from the controller's numbers (no model error), factors applied to the
    wrong link or twice, and draws outside the documented +-5 % (masses, inertias, rotor inertias)
    and +-10 % (friction)."""
    realism = PlantRealism.drawn(seed, PUMA560)
    arm, scale = realism.arm, realism.model_error
    model = Plant(realism=realism).model
    for joint, body in enumerate(link_bodies(model)):
        mass, principal = controller_link(joint)
        assert model.body_mass[body] == pytest.approx(mass * arm.mass[joint], rel=1e-9)
        np.testing.assert_allclose(
            np.sort(model.body_inertia[body]), principal * arm.inertia[joint], rtol=1e-9
        )
        dof = model.jnt_dofadr[model.joint(JOINT_NAMES[joint]).id]
        assert model.dof_armature[dof] == pytest.approx(
            ROBOT.armature_kgm2[joint] * arm.armature[joint], rel=1e-9
        )
        assert model.dof_damping[dof] == pytest.approx(
            ROBOT.viscous_nms_per_rad[joint] * arm.viscous[joint], rel=1e-9
        )
        # Coulomb: the published mean |G| (Tc+ + |Tc-|) / 2 (the controller's) times the factor.
        positive, negative = MOTOR_COULOMB[joint]
        mean = abs(GEAR_RATIOS[joint]) * (positive - negative) / 2
        assert ROBOT.coulomb_nm[joint] == pytest.approx(mean, rel=1e-5)
        assert model.dof_frictionloss[dof] == pytest.approx(mean * arm.coulomb[joint], rel=1e-5)
    for factors, spread in (
        (arm.mass, scale),
        (arm.inertia, scale),
        (arm.armature, scale),
        (arm.viscous, FRICTION_SCALE * scale),
        (arm.coulomb, FRICTION_SCALE * scale),
    ):
        deviation = np.abs(np.array(factors) - 1.0)
        assert deviation.max() <= spread
        assert deviation.max() > 0.3 * spread  # drawn, not all nominal


def test_friction_is_the_published_asymmetric_one_in_each_direction() -> None:
    """Catches the plant dropping the published asymmetry (MuJoCo's frictionloss alone is their
    mean), and Tc+ / Tc- taken by the motor's direction instead of the joint's (gears 1 and 3
    are negative): moving, the joint's friction is -|G| Tc+ turning positively, +|G| |Tc-|
    negatively (times the drawn factor), read from MuJoCo's constraint and applied forces."""
    realism = PlantRealism.drawn(3, PUMA560)
    plant = Plant(realism=realism)
    model, data = plant.model, plant.data
    for direction in (1.0, -1.0):
        plant.reset()
        data.qvel[:] = direction * 0.2
        plant.advance()  # the sensing step sets the asymmetric part for this velocity
        data.qvel[:] = direction * 0.2  # exactly, for the next forward pass
        mujoco.mj_forward(model, data)
        friction = data.qfrc_constraint + data.qfrc_applied  # no contact and no joint limit here
        assert data.ncon == 0
        for joint in range(6):
            positive, negative = MOTOR_COULOMB[joint]
            g = abs(GEAR_RATIOS[joint])
            expected = -g * positive if direction > 0 else -g * negative
            assert friction[joint] == pytest.approx(expected * realism.arm.coulomb[joint], rel=2e-3), joint


def test_same_seed_same_arm_other_seed_other_arm() -> None:
    """Catches a plant that is not reproducible from the run's seed (replay --verify would fail),
    or one that does not change with it (every run of a sweep the same arm)."""
    a, b, c = (PlantRealism.drawn(s, PUMA560) for s in (5, 5, 6))
    assert a == b
    assert a.arm.mass != c.arm.mass and a.wrist_bias != c.wrist_bias
    zero = PlantRealism.drawn(5, PUMA560, model_error=0.0)
    assert set(zero.arm.mass) == {1.0} and set(zero.arm.coulomb) == {1.0}
    with pytest.raises(ValueError, match="model_error"):
        PlantRealism.drawn(5, PUMA560, model_error=-0.1)
