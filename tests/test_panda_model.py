"""The Franka Emika Panda's MJCF against its source, and its workcell against the PUMA's.

References: the URDF the model was derived from (``cosmos/models/panda/source/panda.urdf``,
read here with ElementTree, and built into a Pinocchio model of its own: no MJCF
involved), Franka's published datasheet numbers typed in below, and the PUMA
workcell's scene for the fixtures and the tool.
"""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import cosmos

PANDA_DIR = Path(cosmos.__file__).resolve().parent / "models" / "panda"
ARM = PANDA_DIR / "panda.xml"
SCENE = PANDA_DIR / "scene.xml"
URDF = PANDA_DIR / "source" / "panda.urdf"
PUMA_SCENE = PANDA_DIR.parent / "puma560" / "scene.xml"
LINKS = [f"link{k}" for k in range(1, 8)]
BASE_HEIGHT_M = 0.2  # the pedestal: link 0's frame in the world
# Franka's datasheet (Franka Control Interface documentation, "Robot and interface
# specifications"): joint ranges [rad], torque [N m] and speed [rad/s] limits.
DATASHEET_Q_MIN = [-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973]
DATASHEET_Q_MAX = [2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973]
DATASHEET_TORQUE = [87, 87, 87, 87, 12, 12, 12]
DATASHEET_SPEED = [2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100]
# Gaz et al. (2019), IEEE RA-L 4(4): the friction model's amplitude phi_1 per joint [N m].
GAZ_PHI1 = [0.54615, 0.87224, 0.64068, 1.2794, 0.83904, 0.30301, 0.56489]


def _urdf_joint(root: ElementTree.Element, k: int) -> ElementTree.Element:
    joint = root.find(f"joint[@name='panda_joint{k}']")
    assert joint is not None
    return joint


def _urdf_inertial(root: ElementTree.Element, link: str) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, centre of mass and inertia tensor (about the COM, link axes) of a URDF link."""
    inertial = root.find(f"link[@name='{link}']/inertial")
    assert inertial is not None
    mass = float(inertial.find("mass").get("value"))  # type: ignore[union-attr]
    com = np.array([float(x) for x in inertial.find("origin").get("xyz").split()])  # type: ignore[union-attr]
    t = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}  # type: ignore[union-attr]
    tensor = np.array(
        [[t["ixx"], t["ixy"], t["ixz"]], [t["ixy"], t["iyy"], t["iyz"]], [t["ixz"], t["iyz"], t["izz"]]]
    )
    return mass, com, tensor


@pytest.fixture(scope="module")
def urdf() -> ElementTree.Element:
    return ElementTree.parse(URDF).getroot()


@pytest.fixture(scope="module")
def arm() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(ARM))


@pytest.fixture(scope="module")
def urdf_arm(urdf) -> pin.Model:
    """Pinocchio's model of the URDF, fingers locked and the hand taken off link 7."""
    full = pin.buildModelFromUrdf(str(URDF))
    fingers = [full.getJointId(f"panda_finger_joint{k}") for k in (1, 2)]
    model = pin.buildReducedModel(full, fingers, pin.neutral(full))
    mass, com, tensor = _urdf_inertial(urdf, "panda_link7")
    model.inertias[7] = pin.Inertia(mass, com, tensor)  # the reduction merged the hand into link 7
    model.gravity = pin.Motion(np.array([0.0, 0.0, -9.81]), np.zeros(3))
    return model


def test_link_masses_and_inertias_are_the_urdfs(arm, urdf):
    """Catches a mistyped mass, centre of mass or inertia entry (or a swapped off-diagonal)."""
    for k, name in enumerate(LINKS, start=1):
        mass, com, tensor = _urdf_inertial(urdf, f"panda_link{k}")
        body = arm.body(name)
        assert body.mass[0] == pytest.approx(mass, abs=1e-12), name
        np.testing.assert_allclose(body.ipos, com, atol=1e-12, err_msg=name)
        axes = np.empty(9)
        mujoco.mju_quat2Mat(axes, body.iquat)
        rebuilt = axes.reshape(3, 3) @ np.diag(body.inertia) @ axes.reshape(3, 3).T
        np.testing.assert_allclose(rebuilt, tensor, atol=1e-9, err_msg=name)


def test_joint_ranges_and_drive_limits_are_the_datasheets(arm, urdf):
    """Catches a wrong joint range (joint 4 and 6 are not symmetric) or torque limit."""
    np.testing.assert_allclose(arm.jnt_range[:, 0], DATASHEET_Q_MIN)
    np.testing.assert_allclose(arm.jnt_range[:, 1], DATASHEET_Q_MAX)
    np.testing.assert_allclose(arm.actuator_ctrlrange[:, 1], DATASHEET_TORQUE)
    np.testing.assert_allclose(arm.actuator_ctrlrange[:, 0], -np.array(DATASHEET_TORQUE))
    for k in range(1, 8):
        limit = _urdf_joint(urdf, k).find("limit")
        assert limit is not None
        assert float(limit.get("effort")) == DATASHEET_TORQUE[k - 1]  # type: ignore[arg-type]
        assert float(limit.get("velocity")) == DATASHEET_SPEED[k - 1]  # type: ignore[arg-type]
    np.testing.assert_allclose(arm.dof_frictionloss, np.array(GAZ_PHI1) / 2, rtol=1e-5)


def test_forward_kinematics_and_dynamics_match_the_urdf(arm, urdf_arm):
    """MuJoCo on the MJCF against Pinocchio on the URDF at random q: flange pose, A(q) and g(q).

    Catches a joint origin or axis mistranslated from the URDF's rpy/xyz, a lost base
    offset, or an inertia put in the wrong frame; A(q) differs by the armature only.
    """
    data = mujoco.MjData(arm)
    pdata = urdf_arm.createData()
    flange_site = arm.site("flange").id
    flange_frame = urdf_arm.getFrameId("panda_link8")
    base = pin.SE3(np.eye(3), np.array([0.0, 0.0, BASE_HEIGHT_M]))
    rng = np.random.default_rng(16)
    for _ in range(20):
        q = rng.uniform(arm.jnt_range[:, 0], arm.jnt_range[:, 1])
        data.qpos[:] = q
        data.qvel[:] = 0.0
        mujoco.mj_forward(arm, data)
        pin.framesForwardKinematics(urdf_arm, pdata, q)
        flange = base * pdata.oMf[flange_frame]
        np.testing.assert_allclose(data.site_xpos[flange_site], flange.translation, atol=1e-12)
        np.testing.assert_allclose(data.site_xmat[flange_site].reshape(3, 3), flange.rotation, atol=1e-12)
        inertia = np.zeros((arm.nv, arm.nv))
        mujoco.mj_fullM(arm, data, inertia)
        expected = pin.crba(urdf_arm, pdata, q)
        expected = np.triu(expected) + np.triu(expected, 1).T + np.diag(arm.dof_armature)
        np.testing.assert_allclose(inertia, expected, atol=1e-10)
        gravity = pin.computeGeneralizedGravity(urdf_arm, pdata, q)
        np.testing.assert_allclose(data.qfrc_bias, gravity, atol=1e-9)


def _world_geoms(model: mujoco.MjModel) -> dict[str, mujoco._structs._MjModelGeomViews]:
    return {model.geom(g).name: model.geom(g) for g in range(model.ngeom) if model.geom_bodyid[g] == 0}


def test_workcell_fixtures_and_tool_are_the_pumas():
    """The Panda's scene copies the PUMA's fixtures and tool: catches one edited without the other."""
    panda, puma = (mujoco.MjModel.from_xml_path(str(p)) for p in (SCENE, PUMA_SCENE))
    arm_only = {"pedestal", "link0_base"}
    panda_world = {k: v for k, v in _world_geoms(panda).items() if k not in arm_only}
    puma_world = {k: v for k, v in _world_geoms(puma).items() if k not in arm_only}
    assert sorted(panda_world) == sorted(puma_world)
    fields = (
        "type",
        "size",
        "pos",
        "quat",
        "contype",
        "conaffinity",
        "friction",
        "solref",
        "solimp",
        "solmix",
    )
    for name, geom in puma_world.items():
        for field in fields:
            copy = getattr(panda_world[name], field)
            np.testing.assert_array_equal(copy, getattr(geom, field), err_msg=name)
    for site in ("table", "hole", "slope"):
        for field in ("pos", "quat"):
            np.testing.assert_array_equal(getattr(panda.site(site), field), getattr(puma.site(site), field))
    for field in ("mass", "ipos", "iquat", "inertia", "pos", "quat"):
        np.testing.assert_array_equal(getattr(panda.body("tool"), field), getattr(puma.body("tool"), field))
    for site in ("ft_sensor", "tool"):
        for field in ("pos", "quat"):
            np.testing.assert_array_equal(getattr(panda.site(site), field), getattr(puma.site(site), field))
    for field in ("timestep", "integrator", "cone", "impratio", "gravity", "disableflags"):
        np.testing.assert_array_equal(getattr(panda.opt, field), getattr(puma.opt, field), err_msg=field)


def test_scene_arm_is_the_bare_arm(arm):
    """scene.xml carries a copy of panda.xml's arm: catches one edited without the other."""
    scene = mujoco.MjModel.from_xml_path(str(SCENE))
    for name in LINKS:
        for field in ("pos", "quat", "mass", "ipos", "iquat", "inertia"):
            np.testing.assert_array_equal(getattr(arm.body(name), field), getattr(scene.body(name), field))
    for field in ("jnt_range", "jnt_axis", "dof_armature", "dof_damping", "dof_frictionloss"):
        np.testing.assert_array_equal(getattr(arm, field), getattr(scene, field), err_msg=field)
    np.testing.assert_array_equal(arm.actuator_ctrlrange, scene.actuator_ctrlrange)
    for g in range(arm.ngeom):
        a = arm.geom(g)
        for field in ("type", "size", "pos", "quat", "contype", "conaffinity"):
            copy = getattr(scene.geom(a.name), field)
            np.testing.assert_array_equal(getattr(a, field), copy, err_msg=a.name)
    np.testing.assert_array_equal(arm.key("home").qpos, scene.key("home").qpos)


def test_home_puts_the_tool_where_the_pumas_home_does():
    """Programs start from the same tool pose on both arms; catches a home keyframe solved wrong."""
    poses = []
    for path in (SCENE, PUMA_SCENE):
        model = mujoco.MjModel.from_xml_path(str(path))
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
        mujoco.mj_kinematics(model, data)
        site = model.site("tool").id
        poses.append((data.site_xpos[site].copy(), data.site_xmat[site].reshape(3, 3).copy()))
        assert np.all(model.key("home").qpos >= model.jnt_range[:, 0] + 0.1)
        assert np.all(model.key("home").qpos <= model.jnt_range[:, 1] - 0.1)
    np.testing.assert_allclose(poses[0][0], poses[1][0], atol=1e-9)
    np.testing.assert_allclose(poses[0][1], poses[1][1], atol=1e-9)


def test_controller_model_is_the_plant():
    """The controller's Pinocchio model (panda.xml parsed by Pinocchio, plus the tool's datasheet)
    against MuJoCo's scene at random q: A(q) with the rotor inertia, g(q) and the tool point.
    Catches Pinocchio's MJCF parser reading ``fullinertia`` or the armature otherwise than MuJoCo,
    or the tool put on the wrong joint."""
    from cosmos.robot_model import build_robot_model
    from cosmos.robots import PANDA

    robot = build_robot_model(PANDA)
    pdata = robot.model.createData()
    scene = mujoco.MjModel.from_xml_path(str(SCENE))
    data = mujoco.MjData(scene)
    site = scene.site("tool").id
    rng = np.random.default_rng(7)
    for _ in range(10):
        q = rng.uniform(scene.jnt_range[:, 0], scene.jnt_range[:, 1])
        data.qpos[:], data.qvel[:] = q, 0.0
        mujoco.mj_forward(scene, data)
        inertia = np.zeros((7, 7))
        mujoco.mj_fullM(scene, data, inertia)
        expected = pin.crba(robot.model, pdata, q)
        expected = np.triu(expected) + np.triu(expected, 1).T
        np.testing.assert_allclose(expected, inertia, atol=1e-10)
        gravity = pin.computeGeneralizedGravity(robot.model, pdata, q)
        np.testing.assert_allclose(gravity, data.qfrc_bias, atol=1e-9)
        pin.framesForwardKinematics(robot.model, pdata, q)
        np.testing.assert_allclose(pdata.oMf[robot.tool_frame].translation, data.site_xpos[site], atol=1e-12)
