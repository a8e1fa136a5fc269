"""The arm drawn on ``/scene``: one entity per link, its shapes from the MuJoCo model's geoms.

Each link entity lies in the link's own ``/tf`` frame (the MuJoCo body frame
that :class:`cosmos.execution.recording.LogRecorder` publishes) and is frame
locked, so Foxglove moves it with the link; the shapes are placed with the
geoms' poses in their body (``geom_pos``, ``geom_quat``) and sized from
``geom_size``. The pedestal and other world geoms that belong to no fixture
(the floor plane excepted) are entities of their own in ``world``, named after the geom.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from cosmos.runlog.foxglove import ARM_FRAMES, WORLD_FRAME
from cosmos.runlog.scene import Box, Capsule, Color, Cylinder, Group, Primitive, Shape, Sphere


def geom_shape(model: mujoco.MjModel, geom: int, frame: str) -> Shape | None:
    """The shape of one geom in its body's frame; None for a type Foxglove has no primitive for."""
    name = model.geom(geom).name or f"geom{geom}"
    position = model.geom_pos[geom].tolist()
    quat = model.geom_quat[geom].tolist()  # w x y z
    size = model.geom_size[geom]
    color = Color(*(float(c) for c in model.geom_rgba[geom]))
    match model.geom_type[geom]:
        case mujoco.mjtGeom.mjGEOM_BOX:
            return Box(name, position, (2 * size).tolist(), quat, color, frame)
        case mujoco.mjtGeom.mjGEOM_CYLINDER:
            return Cylinder(name, position, float(size[0]), 2 * float(size[1]), quat, color, frame)
        case mujoco.mjtGeom.mjGEOM_CAPSULE:
            return Capsule(name, position, float(size[0]), float(size[1]), quat, color, frame)
        case mujoco.mjtGeom.mjGEOM_SPHERE:
            return Sphere(name, position, float(size[0]), color, frame)
    return None


def arm_entities(
    model: mujoco.MjModel, owners: Sequence[str], frames: Sequence[str] = ARM_FRAMES
) -> list[Primitive]:
    """One :class:`Group` per arm frame (its body's geoms), then the base's shapes in ``world``.

    Args:
        model: The MuJoCo model of the workcell.
        owners: Per geom, the name of what it belongs to (``Plant.geom_owners``):
            a body's name, or ``world`` for a world geom outside every fixture.
        frames: The ``/tf`` frames, each the name of a body of ``model``.
    """
    groups: list[Primitive] = []
    for frame in frames:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, frame)
        geoms = np.flatnonzero(model.geom_bodyid == body)
        shapes = [s for g in geoms if (s := geom_shape(model, int(g), frame)) is not None]
        groups.append(Group(frame, frame, tuple(shapes)))
    base = [
        shape
        for g in range(model.ngeom)
        if owners[g] == WORLD_FRAME
        and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE
        and (shape := geom_shape(model, g, WORLD_FRAME)) is not None
    ]
    return groups + base
