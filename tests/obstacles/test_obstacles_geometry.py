"""The arm's capsules and the capsule-to-obstacle distances, against MuJoCo's own geometry."""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from cosmos.obstacles import arm_capsules
from cosmos.obstacles.capsules import joint_reach_m
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.obstacles.proximity import capsule_proximity, signed_distances
from cosmos.plan import ObstacleShape
from cosmos.workcell import SCENE_XML
from tests.obstacles.obstacle_scenes import robot


def _random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_capsules_follow_the_simulated_links() -> None:
    """Segment ends placed by Pinocchio's joints coincide with MuJoCo's geoms at random q."""
    model = mujoco.MjModel.from_xml_path(str(SCENE_XML))
    data = mujoco.MjData(model)
    caps = arm_capsules(robot())
    assert set(caps.links) == {f"link{k}" for k in range(1, 7)}
    assert {"peg", "link3_forearm", "link2_upper_arm", "ft_sensor_housing"} <= set(caps.names)
    assert "peg_collar" not in caps.names  # inside the sensor housing's capsule
    pdata = robot().model.createData()
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = rng.uniform(robot().q_lower_rad, robot().q_upper_rad)
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        pin.forwardKinematics(robot().model, pdata, q)
        for i, name in enumerate(caps.names):
            g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
            axis = data.geom_xmat[g].reshape(3, 3)[:, 2] * model.geom_size[g, 1]
            joint = pdata.oMi[int(caps.joint[i]) + 1]
            a, b = joint.act(caps.a_in_joint[i]), joint.act(caps.b_in_joint[i])
            np.testing.assert_allclose(a, data.geom_xpos[g] - axis, atol=1e-9)
            np.testing.assert_allclose(b, data.geom_xpos[g] + axis, atol=1e-9)
            assert caps.radius_m[i] == model.geom_size[g, 0]


def _mujoco_distance(obstacle: Obstacle, a: np.ndarray, b: np.ndarray, radius: float) -> float:
    """Distance between a capsule and the obstacle, by MuJoCo's collision code."""
    spec = mujoco.MjSpec()
    half = obstacle.half_extents_m
    kinds = {
        ObstacleShape.SPHERE: (mujoco.mjtGeom.mjGEOM_SPHERE, [half[0], 0, 0]),
        ObstacleShape.CYLINDER: (mujoco.mjtGeom.mjGEOM_CYLINDER, [half[0], half[2], 0]),
        ObstacleShape.BOX: (mujoco.mjtGeom.mjGEOM_BOX, list(half)),
    }
    kind, size = kinds[obstacle.shape]
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, obstacle.rotation_world.reshape(9))
    spec.worldbody.add_geom(type=kind, size=size, pos=obstacle.position_world, quat=quat)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, fromto=[*a, *b], size=[radius, 0, 0])
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    return mujoco.mj_geomDistance(model, data, 0, 1, 10.0, np.zeros(6))


def _turned(obstacle: Obstacle, rotation: np.ndarray) -> Obstacle:
    rotation = rotation.copy()
    rotation.setflags(write=False)
    return Obstacle(
        obstacle.name,
        obstacle.shape,
        obstacle.position_world,
        rotation,
        obstacle.half_extents_m,
        obstacle.velocity_world_mps,
    )


@pytest.mark.parametrize(
    "shape",
    [
        sphere("s", (0.1, 0.0, 0.2), 0.07),
        box("b", (0.0, 0.1, 0.2), (0.3, 0.1, 0.2)),
        cylinder("c", (0.05, 0.0, 0.1), 0.05, 0.3),
    ],
    ids=["sphere", "box", "cylinder"],
)
def test_distances_agree_with_mujoco(shape: Obstacle) -> None:
    """Exact distances match mj_geomDistance; the SDF agrees at the capsule's ends."""
    rng = np.random.default_rng(7)
    for _ in range(25):
        obstacle = _turned(shape, _random_rotation(rng))
        a = obstacle.position_world + rng.uniform(-0.4, 0.4, 3)
        b = a + rng.uniform(-0.2, 0.2, 3)
        radius = float(rng.uniform(0.01, 0.06))
        near = capsule_proximity(a, b, radius, obstacle, obstacle.position_world)
        expected = _mujoco_distance(obstacle, a, b, radius)
        if expected > 0.0:  # MuJoCo's penetration depth is not the signed distance
            assert near.distance == pytest.approx(expected, abs=2e-4)
            # The reported point is on the capsule and the normal points away from the obstacle.
            tip = near.point - 1e-3 * near.normal
            assert signed_distances(tip[None], obstacle, obstacle.position_world)[0] < near.distance
        # No point of the capsule is closer than the closest one: its ends, for instance.
        ends = signed_distances(np.array([a, b]), obstacle, obstacle.position_world) - radius
        assert ends.min() >= near.distance - 1e-6


def test_plane_distance_is_height_above_it() -> None:
    normal = np.array([0.0, 0.6, 0.8])
    rotation = np.column_stack((np.array([1.0, 0, 0]), np.cross(normal, [1.0, 0, 0]), normal))
    plane = Obstacle(
        "floor",
        ObstacleShape.PLANE,
        np.array([0.0, 0.0, 0.1]),
        rotation,
        np.array([np.inf, np.inf, 0.0]),
        np.zeros(3),
    )
    a, b = np.array([0.0, 0.0, 0.5]), np.array([0.3, -0.2, 0.6])
    near = capsule_proximity(a, b, 0.02, plane, plane.position_world)
    heights = [(p - plane.position_world).dot(normal) for p in (a, b)]
    assert near.distance == pytest.approx(min(heights) - 0.02)
    np.testing.assert_allclose(near.normal, normal)


def test_reach_bounds_the_speed_of_every_capsule_point() -> None:
    """sum |qd_j| reach_j >= the speed of any point on the capsules' surfaces, at random states."""
    caps = arm_capsules(robot())
    reach = joint_reach_m(robot(), caps)
    model, data = robot().model, robot().model.createData()
    rng = np.random.default_rng(11)
    offsets = rng.normal(size=(len(caps), 3))  # a point on each capsule's surface, beyond each end
    offsets *= (caps.radius_m / np.linalg.norm(offsets, axis=1))[:, None]
    step = 1e-7
    for _ in range(20):
        q = rng.uniform(robot().q_lower_rad, robot().q_upper_rad)
        qd = rng.normal(size=6)
        points = []
        for configuration in (q, q + step * qd):
            pin.forwardKinematics(model, data, configuration)
            points.append(
                np.array(
                    [
                        data.oMi[int(caps.joint[i]) + 1].act(end[i] + offsets[i])
                        for end in (caps.a_in_joint, caps.b_in_joint)
                        for i in range(len(caps))
                    ]
                )
            )
        speeds = np.linalg.norm(points[1] - points[0], axis=1) / step
        assert speeds.max() <= float(np.abs(qd).dot(reach)) * (1 + 1e-6)
