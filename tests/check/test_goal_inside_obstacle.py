"""The checker warns of a goal inside an obstacle the program added, as MuJoCo places the shape."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from tests.check.test_goal_inside_fixture import inside_warnings


def _mujoco_obstacle(
    kind: str, at: tuple[float, ...], rpy_deg: tuple[float, float, float], dims: tuple[float, ...]
):
    """A MuJoCo scene of the one obstacle as docs/language.md describes it, and a probe sphere.

    ``AT`` is a sphere's or a box's centre and the centre of a cylinder's base (it rises HEIGHT
    along its z axis); a box's SIZE is its edges.
    """
    spec = mujoco.MjSpec()
    rotation = np.zeros(9)
    quat = np.zeros(4)
    roll, pitch, yaw = (math.radians(a) for a in rpy_deg)
    mujoco.mju_euler2Quat(quat, np.array([roll, pitch, yaw]), "XYZ")  # fixed axes x, y, z
    mujoco.mju_quat2Mat(rotation, quat)
    axes = rotation.reshape(3, 3)
    if kind == "cylinder":
        radius, height = dims
        center = np.array(at) + axes[:, 2] * height / 2.0
        size, geom = [radius, height / 2.0, 0.0], mujoco.mjtGeom.mjGEOM_CYLINDER
    elif kind == "box":
        center, size, geom = np.array(at), [d / 2.0 for d in dims], mujoco.mjtGeom.mjGEOM_BOX
    else:
        center, size, geom = np.array(at), [dims[0], 0.0, 0.0], mujoco.mjtGeom.mjGEOM_SPHERE
    spec.worldbody.add_geom(name="obstacle", type=geom, size=size, pos=center, quat=quat)
    probe = spec.worldbody.add_body(name="probe", mocap=True)
    probe.add_geom(
        name="probe", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[1e-4, 0, 0], contype=0, conaffinity=0
    )
    model = spec.compile()
    return model, mujoco.MjData(model)


def _mujoco_says(model: mujoco.MjModel, data: mujoco.MjData, goal: np.ndarray) -> tuple[float, float]:
    """The goal's signed distance to the obstacle and the z of the obstacle's top above it [m]."""
    data.mocap_pos[0] = goal
    mujoco.mj_kinematics(model, data)
    distance = mujoco.mj_geomDistance(
        model, data, model.geom("probe").id, model.geom("obstacle").id, 1.0, None
    )
    hit = np.array([-1], dtype=np.int32)
    down = mujoco.mj_ray(
        model,
        data,
        np.array([goal[0], goal[1], 3.0]),
        np.array([0.0, 0.0, -1.0]),
        None,
        1,
        model.body("probe").id,
        hit,
    )
    return distance + 1e-4, 3.0 - down


CASES = [
    (
        "OBSTACLE post CYLINDER AT (0.4, -0.2, 0.2) RADIUS 40 mm HEIGHT 0.3 m",
        "cylinder",
        (0.4, -0.2, 0.2),
        (0, 0, 0),
        (0.04, 0.3),
        (0.41, -0.2, 0.45),
    ),
    (
        "OBSTACLE tilted BOX AT (0.5, 0.3, 0.3) RPY (0, 30 deg, 20 deg) SIZE (0.1, 0.2, 0.05)",
        "box",
        (0.5, 0.3, 0.3),
        (0, 30, 20),
        (0.1, 0.2, 0.05),
        (0.51, 0.31, 0.305),
    ),
    (
        "OBSTACLE leaning CYLINDER AT (0.5, 0.0, 0.25) RPY (40 deg, 0, 0) RADIUS 50 mm HEIGHT 0.2 m",
        "cylinder",
        (0.5, 0.0, 0.25),
        (40, 0, 0),
        (0.05, 0.2),
        (0.5, -0.08, 0.34),
    ),
    (
        "OBSTACLE ball SPHERE AT (0.45, 0.1, 0.5) RADIUS 60 mm",
        "sphere",
        (0.45, 0.1, 0.5),
        (0, 0, 0),
        (0.06,),
        (0.46, 0.12, 0.48),
    ),
]


@pytest.mark.parametrize(("statement", "kind", "at", "rpy", "dims", "goal"), CASES)
def test_a_goal_inside_an_obstacle_is_warned_with_mujocos_depth(
    statement: str,
    kind: str,
    at: tuple[float, ...],
    rpy: tuple[float, float, float],
    dims: tuple[float, ...],
    goal: tuple[float, float, float],
) -> None:
    """A MOVE TO a point inside an obstacle the program added (a cylinder standing on its base,
    one leaning, a turned box, a ball): one warning naming it, with the top MuJoCo's ray meets
    above the goal and the depth below it, the shape placed as the docs say (a cylinder's AT is its
    base). Catches obstacles left out of the check, and a cylinder centred on its AT."""
    model, data = _mujoco_obstacle(kind, at, rpy, dims)
    distance, top = _mujoco_says(model, data, np.array(goal))
    assert distance < -1e-3  # the case is what it claims
    found = inside_warnings(f"{statement}\nMOVE TO {tuple(goal)}\n")
    assert [(line, m["fixture"]) for line, m in found] == [(2, statement.split()[1])]
    assert (found[0][1]["kind"], found[0][1]["ending"]) == ("obstacle", "short of it")
    assert float(found[0][1]["top"]) == pytest.approx(top * 1e3, abs=0.051)
    assert float(found[0][1]["depth"]) == pytest.approx((top - goal[2]) * 1e3, abs=0.051)


def test_obstacles_gone_moving_or_in_a_block_are_not_warned() -> None:
    """No warning for a goal where an obstacle was before OBSTACLE REMOVE, inside a MOVING one (it
    will have moved), or inside one added in an IF once the block is over (it may not have been).
    Catches removed obstacles kept, moving ones taken as still, and a block's obstacle kept after it."""
    post = "OBSTACLE post CYLINDER AT (0.4, -0.2, 0.2) RADIUS 40 mm HEIGHT 0.3 m\n"
    goal = "MOVE TO (0.41, -0.2, 0.45)\n"
    assert inside_warnings(post + goal)
    assert not inside_warnings(post + "OBSTACLE REMOVE post\n" + goal)
    moving = "OBSTACLE post CYLINDER AT (0.4, -0.2, 0.2) RADIUS 40 mm HEIGHT 0.3 m MOVING (0, 10 mm/s, 0)\n"
    assert not inside_warnings(moving + goal)
    in_if = "IF FORCE > 3 N\n  " + post + "END\n"
    assert not inside_warnings(in_if + goal)
