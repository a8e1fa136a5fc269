"""The workcell's fixtures as scene primitives for the run log's 3D view."""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.plant import Plant
from cosmos.runlog.scene import FIXTURE_COLOR, Box, Cylinder, Primitive, Sphere

FIXTURES = ("table", "hole_fixture", "slope_fixture")
"""The scene's fixture frames (their geoms belong to the world body)."""


def fixture_primitives(plant: Plant) -> list[Primitive]:
    """The workcell's fixtures as scene primitives (boxes, cylinders, spheres), world poses."""
    model, data = plant.model, plant.data
    owners = plant.geom_owners
    primitives: list[Primitive] = []
    for geom in range(model.ngeom):
        owner = owners[geom]
        if owner not in FIXTURES:
            continue
        name = model.geom(geom).name or f"{owner}_{geom}"
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, data.geom_xmat[geom])
        size = model.geom_size[geom]
        position = data.geom_xpos[geom].tolist()
        kind = model.geom_type[geom]
        if kind == mujoco.mjtGeom.mjGEOM_BOX:
            primitives.append(Box(name, position, (2 * size).tolist(), quat.tolist(), FIXTURE_COLOR))
        elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
            primitives.append(
                Cylinder(name, position, float(size[0]), 2 * float(size[1]), quat.tolist(), FIXTURE_COLOR)
            )
        elif kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            primitives.append(Sphere(name, position, float(size[0]), FIXTURE_COLOR))
    return primitives
