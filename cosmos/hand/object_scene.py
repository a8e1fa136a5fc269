"""Objects as free MuJoCo bodies: they fall, slide, collide and can be held.

:func:`add_objects` appends each :class:`cosmos.hand.work_object.WorkObject` to a
workcell's spec before it is compiled, as a body with a free joint and one geom of its
shape, mass and friction. Being after the arm (and the gripper's fingers) in the body tree,
their joints come after the arm's in ``qpos`` (:class:`cosmos.plant.Plant` needs the arm's
first); their start pose is the body's, MuJoCo's ``qpos0`` for a free joint, which the
``home`` keyframe leaves as it is.

Contacts: an object's friction is the one its contacts use (MuJoCo's geom ``priority``), so
a program's ``FRICTION`` decides how well the pads hold it and how it slides on the table.
``contype 1`` touches the fixtures and other objects (their ``conaffinity`` 1);
``conaffinity 7`` lets the arm's links (``contype 2``) and the tool and fingers
(``contype 4``) touch them.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco

from cosmos.hand.work_object import ObjectShape, WorkObject

OBJECT_CONTYPE, OBJECT_CONAFFINITY = 1, 7
OBJECT_PRIORITY = 1
"""Above every other geom's 0: an object's contacts (with the pads, the table, the fixtures)
take its friction (the program's ``FRICTION``) and its contact parameters."""
OBJECT_RGBA = (0.25, 0.55, 0.85, 1.0)
_GEOM = {ObjectShape.BOX: mujoco.mjtGeom.mjGEOM_BOX, ObjectShape.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER}


def add_objects(spec: mujoco.MjSpec, objects: Sequence[WorkObject]) -> None:
    """Append each object to the scene's world body as a free body (module docstring)."""
    for item in objects:
        body = spec.worldbody.add_body(name=item.name, pos=item.position_m, quat=item.quat_wxyz)
        body.add_freejoint(name=f"{item.name}_free")
        a, b, c = item.half_extents_m
        size = (a, b, c) if item.shape is ObjectShape.BOX else (a, c, 0.0)
        geom = body.add_geom(name=f"{item.name}_geom", type=_GEOM[item.shape], size=size, mass=item.mass_kg)
        geom.friction = (item.friction, 0.005, 0.0001)
        geom.condim = 4
        geom.contype, geom.conaffinity = OBJECT_CONTYPE, OBJECT_CONAFFINITY
        geom.priority = OBJECT_PRIORITY
        geom.rgba = OBJECT_RGBA
