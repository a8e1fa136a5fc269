"""The contact gate: bodies clear of the world skip the contact test; the contacts stay MuJoCo's own."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

from cosmos.obstacles import ContactGate, FieldParameters, ObstacleField, ObstacleScene, obstacle_scene_xml
from cosmos.obstacles.gate import reach_m
from cosmos.obstacles.kernels import gate as gk
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.robots import robot_named
from cosmos.runtime.loop import Runtime
from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

# With the field off the arm runs into what is in its way: a crate beside a post while a ball
# flies through the links' space (its box refitted as it goes), or, fast, a wall and nothing
# else (the world's tree never changes: only the bound on the arm's motion keeps a body on).
CRATE = (
    box("crate", (0.48, -0.15, 0.45), (0.04, 0.30, 0.30)),
    cylinder("post", (0.45, 0.10, 0.40), 0.04, 0.5),
    sphere("ball", (0.30, -0.60, 0.75), 0.06, velocity_mps=(0.0, 0.5, 0.0)),
)
WALL = (box("wall", (0.42, -0.15, 0.45), (0.02, 0.60, 0.40)),)
GOAL = (0.36, -0.15, 0.457)


def _ball_at_the_still_forearm() -> tuple[Obstacle, ...]:
    """A ball that flies into the forearm of the arm held at home (the arm's motion bound is nil)."""
    plant = Plant(obstacle_scene_xml())
    forearm = plant.data.geom_xpos[plant.model.geom("link3_forearm").id]
    start = (float(forearm[0]), float(forearm[1]) - 0.5, float(forearm[2]))
    return (sphere("ball", start, 0.05, velocity_mps=(0.0, 0.5, 0.0)),)


def _runtime(
    gated: bool,
    rates: Rates | None = None,
    obstacles: tuple[Obstacle, ...] = CRATE,
    speed: float = 0.3,
    goal: tuple[float, float, float] | None = GOAL,
) -> tuple[Runtime, ContactGate]:
    robot = build_robot_model()
    plant = Plant(obstacle_scene_xml())
    runtime = Runtime(plant, robot, rates or Rates())
    scene = ObstacleScene(plant)
    field = ObstacleField(robot, FieldParameters())
    field.enabled = False  # nothing keeps the arm off the crate
    for obstacle in obstacles:
        scene.add(obstacle)
        field.add(obstacle)
    runtime.fields.append(field)
    gate = ContactGate(plant, scene.version)
    if gated:
        runtime.contact_gate = gate
    ev = runtime.evaluation
    target = ev.position.copy() if goal is None else np.array(goal)
    runtime.set_setpoint(
        ServoSetpoint(MotionMode.GOAL, target, ev.rotation_tool_to_world, start_s=0.0, max_speed=speed)
    )
    runtime.scene = scene  # type: ignore[attr-defined]
    return runtime, gate


def _contacts(data: mujoco.MjData) -> list[tuple[object, ...]]:
    return [
        (int(c.geom1), int(c.geom2), float(c.dist), tuple(c.pos.tolist()), tuple(c.frame.tolist()))
        for c in data.contact[: data.ncon]
    ]


@pytest.mark.parametrize("case", ["crate", "wall", "ball"])
def test_the_gate_leaves_every_contact_as_mujoco_finds_it(case: str) -> None:
    """Twin runs, the gate on in one: after every tick both must hold the same contacts (geoms, depth,
    point, frame) and the same state, bit for bit, while the arm hits a crate as a ball flies by, hits
    a wall at speed, or is held while a ball flies into it. Catches a body switched off when it could
    touch: a bound on its motion too small (the wall), a clearance kept after the world's tree changed
    (the ball: only the ball's refitted box comes near), a box in the wrong frame, a world geom's
    contype read wrongly, or flags not given back when a body comes near."""
    obstacles, speed, goal = {
        "crate": (CRATE, 0.3, GOAL),
        "wall": (WALL, 1.0, GOAL),
        "ball": (_ball_at_the_still_forearm(), 0.3, None),
    }[case]
    plain, _ = _runtime(gated=False, obstacles=obstacles, speed=speed, goal=goal)
    gated, gate = _runtime(gated=True, obstacles=obstacles, speed=speed, goal=goal)
    touching = switched_off = 0
    for _ in range(1500):
        for runtime in (plain, gated):
            runtime.scene.update(runtime.time_s)  # type: ignore[attr-defined]
            runtime.tick()
        found = _contacts(plain.plant.data)
        assert _contacts(gated.plant.data) == found
        np.testing.assert_array_equal(gated.plant.data.qpos, plain.plant.data.qpos)
        touching += bool(found)
        switched_off += gate.gated
    assert touching > 20  # the arm does hit it: the lists compared are not empty
    assert switched_off > 1500  # and the gate does switch bodies off


def test_a_tick_of_two_steps_switches_nothing_off() -> None:
    """At a 500 Hz servo a tick takes two physics steps; the gate proves a body clear for one step
    only, so it must switch nothing off. Catches a gate whose proof for the first step is taken for
    the second, where the arm has moved on."""
    runtime, gate = _runtime(gated=True, rates=Rates(servo_hz=500.0, param_hz=125.0))
    for _ in range(300):
        runtime.scene.update(runtime.time_s)  # type: ignore[attr-defined]
        runtime.tick()
        assert gate.gated == 0
    assert gate.bodies == 7  # it could: six links and the tool can only touch the world


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_a_body_reach_bounds_its_geoms_distance_from_every_joint_axis(robot: str) -> None:
    """MuJoCo's own kinematics at 300 random configurations (each joint anywhere in its range): every
    point of a gated body's geoms (each geom's centre plus its bounding radius) lies within
    ``reach_m`` of the axis of each joint that carries it (MuJoCo's ``xanchor``, ``xaxis``). The gate
    takes ``sum_j |dq_j| reach_j`` as the farthest the body can have moved; catches a reach that
    leaves out an offset (the joint's anchor in its body, a body between the joint and the geoms,
    a geom's offset in its body) and so a body switched off while it could touch."""
    plant = Plant(obstacle_scene_xml(scene_xml=robot_named(robot).scene_xml))
    model, data = plant.model, plant.data
    gate = ContactGate(plant, np.zeros(1))
    assert len(gate.body_ids) == {"puma560": 7, "panda": 8}[robot]  # the links and the tool
    rng = np.random.default_rng(0)
    for _ in range(300):
        for joint in range(model.njnt):
            data.qpos[model.jnt_qposadr[joint]] = rng.uniform(*model.jnt_range[joint])
        mujoco.mj_kinematics(model, data)
        for body in gate.body_ids:
            first, count = int(model.body_geomadr[body]), int(model.body_geomnum[body])
            for joint in range(model.njnt):
                reach = reach_m(model, body, joint)
                if not _carries(model, joint, body):
                    assert reach == 0.0
                    continue
                anchor, axis = data.xanchor[joint], data.xaxis[joint]
                for geom in range(first, first + count):
                    offset = data.geom_xpos[geom] - anchor
                    across = float(np.linalg.norm(offset - offset.dot(axis) * axis)) + model.geom_rbound[geom]
                    assert across <= reach + 1e-12, (body, joint, geom)


def _carries(model: mujoco.MjModel, joint: int, body: int) -> bool:
    """Whether ``joint`` is on the way from the world to ``body`` (an independent walk)."""
    while body > 0:
        if int(model.jnt_bodyid[joint]) == body:
            return True
        body = int(model.body_parentid[body])
    return False


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_a_body_clearance_is_never_more_than_mujoco_s_distance_to_what_it_can_touch(robot: str) -> None:
    """At 200 random configurations among random spheres, boxes and cylinders (some turned), each
    gated body's clearance (its geoms' boxes from the world's tree) is at most MuJoCo's own distance
    (``mj_geomDistance``) from any of its geoms to any world geom it can touch, and it is not
    vacuous (many bodies are found clear). Catches a separation taken along a wrong axis (the
    boxes' own axes as the rows of their rotation instead of its columns), a box in the wrong frame,
    and a leaf of the world's tree skipped: all of them switch a body off that could touch."""
    rng = np.random.default_rng(1)
    plant = Plant(obstacle_scene_xml(scene_xml=robot_named(robot).scene_xml))
    model, data = plant.model, plant.data
    scene = ObstacleScene(plant)
    for k in range(12):
        center = (rng.uniform(-0.2, 0.9), rng.uniform(-0.7, 0.7), rng.uniform(0.3, 1.2))
        size = rng.uniform(0.02, 0.15, 3)
        if k % 3 == 0:
            scene.add(sphere(f"s{k}", center, size[0]))
        elif k % 3 == 1:
            scene.add(cylinder(f"c{k}", center, size[0], 2.0 * size[2]))
        else:  # a box turned anyhow
            quat, turn = rng.normal(size=4), np.empty(9)
            mujoco.mju_quat2Mat(turn, quat / np.linalg.norm(quat))
            scene.add(dataclasses.replace(box(f"b{k}", center, size), rotation_world=turn.reshape(3, 3)))
    scene.update(0.0)  # the world's tree rebuilt for them
    gate = ContactGate(plant, scene.version)
    world = range(int(model.body_geomadr[0]), int(model.body_geomadr[0] + model.body_geomnum[0]))
    arrays = (data.xipos, data.ximat, gate._ints, model.bvh_aabb, model.bvh_child, model.bvh_nodeid)  # noqa: SLF001
    clear = 0
    for _ in range(200):
        for joint in range(model.njnt):
            data.qpos[model.jnt_qposadr[joint]] = rng.uniform(*model.jnt_range[joint])
        mujoco.mj_kinematics(model, data)
        for k, body in enumerate(gate.body_ids):
            found = gk.body_clearance(k, 0.1, *arrays)
            first, count = int(model.body_geomadr[body]), int(model.body_geomnum[body])
            nearest = np.inf
            for geom in range(first, first + count):
                for other in world:
                    touch = model.geom_contype[geom] & model.geom_conaffinity[other]
                    if touch or model.geom_contype[other] & model.geom_conaffinity[geom]:
                        distance = mujoco.mj_geomDistance(model, data, geom, other, 1.0, None)
                        nearest = min(nearest, distance)
            # found clear, it must be at least that far (touching, any overlap is a fair answer)
            assert found <= max(nearest, 0.0) + 1e-9, (model.body(body).name, found, nearest)
            clear += found > 0.0
    assert clear > 2 * len(gate.body_ids) * 200 / 7  # of 200 per body: the bound is not vacuous
