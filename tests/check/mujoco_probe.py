"""MuJoCo's own answers about the workcell's fixtures, for the checker's tests to compare with.

The scene is compiled with a point-sized probe sphere on a mocap body and the arm's geoms
moved to another group: ``mj_geomDistance`` between the probe and a fixture's geom gives
the signed distance of a point to it, and ``mj_ray`` cast down onto group 0 (the fixtures)
gives the z of a fixture's top.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import mujoco
import numpy as np

from cosmos.plant_scene import geom_owners
from cosmos.robots import ROBOTS
from cosmos.workcell import scene_spec

PROBE_RADIUS_M = 1e-4
"""The probe sphere's radius [m] (its distances are the point's minus this)."""
FAR_M = 0.05
"""``mj_geomDistance`` looks this far [m]."""
CALLED = {"hole_fixture": "hole", "slope_fixture": "slope", "table": "table", "world": "floor"}
"""The fixture frames of the scenes by the names the language gives their sites."""


@dataclass(frozen=True)
class Probe:
    """A compiled scene with a probe: see the module's docstring."""

    model: mujoco.MjModel
    data: mujoco.MjData
    probe: int
    fixture_geoms: dict[int, str]  # geom id -> fixture name


@functools.cache
def probe(robot: str = "puma560") -> Probe:
    """The arm's scene with a probe sphere (compiled once per arm)."""
    spec = scene_spec(ROBOTS[robot].scene_xml, robot=robot)
    for geom in spec.geoms:
        if geom.parent.name != "world":
            geom.group = 3  # the arm: out of the rays' group
    body = spec.worldbody.add_body(name="probe", mocap=True)
    body.add_geom(
        name="probe", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[PROBE_RADIUS_M, 0, 0], contype=0, conaffinity=0
    )
    model = spec.compile()
    owners = geom_owners(spec, model)
    fixtures = {
        g: CALLED[owners[g]]
        for g in range(model.ngeom)
        if model.geom_bodyid[g] == 0 and (model.geom_contype[g] or model.geom_conaffinity[g])
    }
    return Probe(model, mujoco.MjData(model), model.geom("probe").id, fixtures)


def signed_distance(point: np.ndarray, robot: str = "puma560") -> tuple[float, str]:
    """MuJoCo's distance from ``point`` to the nearest fixture geom [m] (negative inside), and its fixture.

    Farther than :data:`FAR_M` reads as ``FAR_M``.
    """
    scene = probe(robot)
    scene.data.mocap_pos[0] = point
    mujoco.mj_kinematics(scene.model, scene.data)
    best, name = FAR_M, ""
    for geom, fixture in scene.fixture_geoms.items():
        distance = mujoco.mj_geomDistance(scene.model, scene.data, scene.probe, geom, FAR_M, None)
        if distance + PROBE_RADIUS_M < best:
            best, name = distance + PROBE_RADIUS_M, fixture
    return best, name


def top_at(x: float, y: float, robot: str = "puma560") -> tuple[float, str]:
    """The z [m] of the first fixture MuJoCo's ray meets going down at ``(x, y)``, and which."""
    scene = probe(robot)
    mujoco.mj_kinematics(scene.model, scene.data)
    geomgroup = np.array([1, 0, 0, 0, 0, 0], dtype=np.uint8)
    hit = np.array([-1], dtype=np.int32)
    distance = mujoco.mj_ray(
        scene.model, scene.data, np.array([x, y, 2.0]), np.array([0.0, 0.0, -1.0]), geomgroup, 1, -1, hit
    )
    return 2.0 - distance, scene.fixture_geoms[int(hit[0])]


def site(name: str, robot: str = "puma560") -> tuple[np.ndarray, np.ndarray]:
    """A fixture site's position [m] and rotation, as MuJoCo places it."""
    scene = probe(robot)
    mujoco.mj_kinematics(scene.model, scene.data)
    index = scene.model.site(name).id
    return scene.data.site_xpos[index].copy(), scene.data.site_xmat[index].reshape(3, 3).copy()
