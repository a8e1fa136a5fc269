"""The PUMA 560 models against independent references.

References: the published parameters (shared/reference/puma560.md) typed in
below, a Pinocchio model built here directly from the DH table with the
published inertias (no MJCF involved), and MuJoCo itself for the controller's
Pinocchio model.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from cosmos.robot_model import GRAVITY, build_robot_model
from cosmos.workcell import ARM_XML, SCENE_XML

# --- published parameters (Corke & Armstrong-Helouvry 1994, Corke's toolbox) ---
DH = [  # d [m], a [m], alpha [rad]
    (0.67183, 0.0, np.pi / 2),
    (0.0, 0.4318, 0.0),
    (0.15005, 0.0203, -np.pi / 2),
    (0.4318, 0.0, np.pi / 2),
    (0.0, 0.0, -np.pi / 2),
    (0.0, 0.0, 0.0),
]
MASS = [0.0, 17.4, 4.8, 0.82, 0.34, 0.09]
COM = [
    (0, 0, 0),
    (-0.3638, 0.006, 0.2275),
    (-0.0203, -0.0141, 0.070),
    (0, 0.019, 0),
    (0, 0, 0),
    (0, 0, 0.032),
]
INERTIA = [  # principal, about the COM, DH link frame
    (0, 0.35, 0),
    (0.13, 0.524, 0.539),
    (0.066, 0.086, 0.0125),
    (1.8e-3, 1.3e-3, 1.8e-3),
    (0.3e-3, 0.4e-3, 0.3e-3),
    (0.15e-3, 0.15e-3, 0.04e-3),
]
GEAR = np.array([-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686])
JM = np.array([200e-6, 200e-6, 200e-6, 33e-6, 33e-6, 33e-6])
VISCOUS_MOTOR = np.array([1.48e-3, 0.817e-3, 1.38e-3, 71.2e-6, 82.6e-6, 36.7e-6])
COULOMB_PLUS = np.array([0.395, 0.126, 0.132, 11.2e-3, 9.26e-3, 3.96e-3])
COULOMB_MINUS = np.array([-0.435, -0.071, -0.105, -16.9e-3, -14.5e-3, -10.5e-3])
LIMITS_DEG = [(-160, 160), (-45, 225), (-225, 45), (-110, 170), (-100, 100), (-266, 266)]
PEAK_TORQUE = np.array([97.6, 186.4, 89.4, 24.2, 20.1, 21.3])
QZ = np.zeros(6)
QR = np.array([0, np.pi / 2, -np.pi / 2, 0, 0, 0])
QS = np.array([0, 0, -np.pi / 2, 0, 0, 0])
QN = np.array([0, np.pi / 4, -np.pi, 0, np.pi / 4, 0])
G_QZ = np.array([0, 37.4837, 0.248929, 0, 0, 0])
G_QR = np.array([0, -0.775235, 0.248929, 0, 0, 0])
ROTOR_INERTIA = GEAR**2 * JM


def dh_reference_model() -> pin.Model:
    """Pinocchio model straight from the DH table, published (unmodified) inertias.

    Joint i is a z rotation at DH frame i-1; link i's inertia is given in frame i,
    which is A_i = Tz(d) Tx(a) Rx(alpha) from joint i's frame. Frame ``flange`` = DH 6.
    """
    model = pin.Model()
    parent, placement = 0, pin.SE3.Identity()
    for i, (d, a, alpha) in enumerate(DH):
        joint = model.addJoint(parent, pin.JointModelRZ(), placement, f"joint{i + 1}")
        link_in_joint = pin.SE3(pin.utils.rotate("x", alpha), np.array([a, 0.0, d]))
        inertia = pin.Inertia(MASS[i], np.array(COM[i], float), np.diag(INERTIA[i]))
        model.appendBodyToJoint(joint, link_in_joint.act(inertia), pin.SE3.Identity())
        parent, placement = joint, link_in_joint
    model.addFrame(pin.Frame("flange", parent, 0, placement, pin.OP_FRAME))
    model.gravity = pin.Motion(np.array([0, 0, -9.81]), np.zeros(3))
    return model


@pytest.fixture(scope="module")
def arm() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(ARM_XML))


@pytest.fixture(scope="module")
def scene() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(SCENE_XML))


def random_configurations(count: int, seed: int) -> np.ndarray:
    lower, upper = np.radians(LIMITS_DEG).T
    return np.random.default_rng(seed).uniform(lower, upper, size=(count, 6))


def mujoco_terms(model: mujoco.MjModel, q: np.ndarray, qd: np.ndarray, site: str):
    """M(q) (with armature), g(q), b(q, qd) and the site Jacobian (6, nv) from MuJoCo."""
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_forward(model, data)
    gravity = data.qfrc_bias.copy()
    inertia = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, inertia)
    jac_linear, jac_angular = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jac_linear, jac_angular, model.site(site).id)
    data.qvel[:] = qd
    mujoco.mj_forward(model, data)
    return inertia, gravity, data.qfrc_bias - gravity, np.vstack((jac_linear, jac_angular))


def mujoco_flange_pose(model: mujoco.MjModel, q: np.ndarray) -> pin.SE3:
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    site = model.site("flange").id
    return pin.SE3(data.site_xmat[site].reshape(3, 3).copy(), data.site_xpos[site].copy())


def full_crba(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    upper = pin.crba(model, data, q)
    return np.triu(upper) + np.triu(upper, 1).T


def test_gravity_torques_match_published_values(arm):
    # Catches wrong masses, COMs, DH offsets or joint directions.
    data = mujoco.MjData(arm)
    for q, published in ((QZ, G_QZ), (QR, G_QR)):
        data.qpos[:] = q
        data.qvel[:] = 0
        mujoco.mj_forward(arm, data)
        np.testing.assert_allclose(data.qfrc_bias, published, rtol=0, atol=1e-4)


def test_dh_reference_reproduces_published_gravity():
    # The reference itself must be right before it judges the MJCF.
    model = dh_reference_model()
    data = model.createData()
    for q, published in ((QZ, G_QZ), (QR, G_QR)):
        np.testing.assert_allclose(
            pin.computeGeneralizedGravity(model, data, q), published, rtol=0, atol=1e-4
        )


def test_mjcf_arm_matches_dh_reference(arm):
    # Same frames, zeros and directions (flange pose), and the link 1 / link 3
    # changes leave M(q) and g(q) as published (1e-6 required, exact to rounding).
    reference = dh_reference_model()
    data = reference.createData()
    flange = reference.getFrameId("flange")
    for q in [QZ, QR, QS, QN, *random_configurations(25, seed=1)]:
        inertia, gravity, _, _ = mujoco_terms(arm, q, np.zeros(6), "flange")
        np.testing.assert_allclose(
            inertia, full_crba(reference, data, q) + np.diag(ROTOR_INERTIA), rtol=0, atol=1e-9
        )
        np.testing.assert_allclose(
            gravity, pin.computeGeneralizedGravity(reference, data, q), rtol=0, atol=1e-9
        )
        pin.framesForwardKinematics(reference, data, q)
        expected = data.oMf[flange]
        pose = mujoco_flange_pose(arm, q)
        np.testing.assert_allclose(pose.translation, expected.translation, atol=1e-12)
        np.testing.assert_allclose(pose.rotation, expected.rotation, atol=1e-12)


def test_named_configurations_by_hand(arm):
    # qr: arm straight up: flange at (a3, -d3, d1 + a2 + d4), z6 up.
    pose = mujoco_flange_pose(arm, QR)
    np.testing.assert_allclose(pose.translation, [0.0203, -0.15005, 1.53543], atol=1e-12)
    np.testing.assert_allclose(pose.rotation[:, 2], [0, 0, 1], atol=1e-12)
    # qs: stretched horizontally along x: flange at (a2 + d4, -d3, d1 - a3).
    pose = mujoco_flange_pose(arm, QS)
    np.testing.assert_allclose(pose.translation, [0.8636, -0.15005, 0.65153], atol=1e-12)
    np.testing.assert_allclose(pose.rotation[:, 2], [1, 0, 0], atol=1e-12)


def test_rotor_inertia_is_added_to_the_diagonal(arm):
    # M(q) with rotor inertia = rigid-body matrix + diag(G^2 Jm), from the drive table.
    rigid = mujoco.MjModel.from_xml_path(str(ARM_XML))
    rigid.dof_armature[:] = 0
    for q in random_configurations(5, seed=2):
        with_rotors, _, _, _ = mujoco_terms(arm, q, np.zeros(6), "flange")
        without, _, _, _ = mujoco_terms(rigid, q, np.zeros(6), "flange")
        np.testing.assert_allclose(with_rotors - without, np.diag(ROTOR_INERTIA), atol=1e-12)


def test_drive_parameters_are_the_published_ones(arm):
    # Catches a mistyped limit, gear-reflected friction or torque limit.
    np.testing.assert_allclose(arm.dof_armature, ROTOR_INERTIA, rtol=1e-12)
    np.testing.assert_allclose(arm.dof_damping, GEAR**2 * VISCOUS_MOTOR, rtol=1e-12)
    mean_coulomb = np.abs(GEAR) * (COULOMB_PLUS - COULOMB_MINUS) / 2
    np.testing.assert_allclose(arm.dof_frictionloss, mean_coulomb, rtol=1e-12)
    np.testing.assert_allclose(arm.jnt_range, np.radians(LIMITS_DEG), rtol=1e-12)
    assert arm.jnt_limited.all()
    np.testing.assert_allclose(arm.actuator_ctrlrange, np.c_[-PEAK_TORQUE, PEAK_TORQUE])
    assert arm.actuator_ctrllimited.all()
    np.testing.assert_array_equal(arm.actuator_gear[:, 0], 1)
    assert [arm.joint(int(j)).name for j in arm.actuator_trnid[:, 0]] == [f"joint{i}" for i in range(1, 7)]


def test_link_inertias_are_physical_and_published_link3_is_not(arm):
    # MuJoCo checks the triangle inequality; the published link 3 fails it,
    # the model's links all pass it (the reason for the README's link 3 change).
    for body in range(1, arm.nbody):
        moments = np.sort(arm.body_inertia[body])
        assert arm.body_mass[body] > 0
        assert moments[0] + moments[1] >= moments[2]
    published = sorted(INERTIA[2])
    assert published[0] + published[1] < published[2]


def test_pinocchio_crba_includes_armature():
    # robot_model relies on crba/rnea/aba adding the armature (Pinocchio >= 3).
    model = pin.buildModelFromMJCF(str(ARM_XML))
    data = model.createData()
    rigid = pin.buildModelFromMJCF(str(ARM_XML))
    rigid.armature[:] = 0
    rigid_data = rigid.createData()
    q = random_configurations(1, seed=3)[0]
    np.testing.assert_allclose(model.armature, ROTOR_INERTIA, rtol=1e-12)
    np.testing.assert_allclose(
        full_crba(model, data, q) - full_crba(rigid, rigid_data, q),
        np.diag(ROTOR_INERTIA),
        atol=1e-12,
    )
    qdd = np.linspace(-1, 1, 6)
    np.testing.assert_allclose(
        pin.rnea(model, data, q, np.zeros(6), qdd) - pin.rnea(rigid, rigid_data, q, np.zeros(6), qdd),
        ROTOR_INERTIA * qdd,
        atol=1e-10,
    )


@pytest.mark.parametrize("with_tool", [False, True], ids=["bare-arm", "scene-with-tool"])
def test_controller_model_matches_mujoco(with_tool, arm, scene):
    # M (with armature), g, Coriolis/centrifugal b and the Jacobian at 25 random
    # states, to 1e-9. Bare arm: Pinocchio's MJCF parse vs MuJoCo; scene: the
    # controller's model (arm + TOOL) vs MuJoCo's scene, whose tool is a body.
    if with_tool:
        robot = build_robot_model()
        model, data, frame, mj_model, site = (
            robot.model,
            robot.data,
            robot.tool_frame,
            scene,
            "tool",
        )
    else:
        model = pin.buildModelFromMJCF(str(ARM_XML))
        data, frame, mj_model, site = model.createData(), model.getFrameId("flange"), arm, "flange"
    rng = np.random.default_rng(4)
    for q in random_configurations(25, seed=5):
        qd = rng.uniform(-3, 3, size=6)
        inertia, gravity, velocity_terms, jacobian = mujoco_terms(mj_model, q, qd, site)
        np.testing.assert_allclose(full_crba(model, data, q), inertia, rtol=0, atol=1e-9)
        pin_gravity = pin.computeGeneralizedGravity(model, data, q)
        np.testing.assert_allclose(pin_gravity, gravity, rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            pin.nle(model, data, q, qd) - pin_gravity, velocity_terms, rtol=0, atol=1e-9
        )
        pin_jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(pin_jacobian, jacobian, rtol=0, atol=1e-9)


def test_controller_model_limits_and_friction(arm, scene):
    robot = build_robot_model()
    np.testing.assert_allclose(robot.model.gravity.linear, GRAVITY)
    np.testing.assert_allclose(scene.opt.gravity, GRAVITY)
    np.testing.assert_allclose(robot.q_lower_rad, np.radians(LIMITS_DEG)[:, 0], rtol=1e-12)
    np.testing.assert_allclose(robot.q_upper_rad, np.radians(LIMITS_DEG)[:, 1], rtol=1e-12)
    np.testing.assert_allclose(robot.tau_lower_nm, -PEAK_TORQUE)
    np.testing.assert_allclose(robot.tau_upper_nm, PEAK_TORQUE)
    np.testing.assert_allclose(robot.armature_kgm2, arm.dof_armature)
    np.testing.assert_allclose(robot.viscous_nms_per_rad, arm.dof_damping)
    np.testing.assert_allclose(robot.coulomb_nm, arm.dof_frictionloss)
    # The controller compensates the published friction by direction (Corke: by the joint's
    # velocity): a swapped pair or the mean would leave up to 3 N m on joint 2 unanswered.
    np.testing.assert_allclose(robot.coulomb_positive_nm, np.abs(GEAR) * COULOMB_PLUS, rtol=1e-5)
    np.testing.assert_allclose(robot.coulomb_negative_nm, np.abs(GEAR * COULOMB_MINUS), rtol=1e-5)
    with pytest.raises(ValueError):
        robot.q_lower_rad[0] = 0.0
