"""Objects as free MuJoCo bodies: they fall, slide, collide and can be held.

:func:`add_objects` appends each :class:`cosmos.hand.work_object.WorkObject` to a
workcell's spec before it is compiled, as a body with a free joint and one geom of its
shape, mass and friction (two: below). Being after the arm (and the gripper's fingers) in the body tree,
their joints come after the arm's in ``qpos`` (:class:`cosmos.plant.Plant` needs the arm's
first); their start pose is the body's, MuJoCo's ``qpos0`` for a free joint, which the
``home`` keyframe leaves as it is.

Contacts: an object's friction is the one its contacts use (MuJoCo's geom ``priority``), so
a program's ``FRICTION`` decides how well the pads hold it and how it slides on the table.
An object is two geoms of the same shape, one for what holds it, one for what it stands on:

- its *grip* geom (``<name>_geom``, which carries the mass) touches only the arm's links
  (``contype 2``) and the tool and fingers (``contype 4``): ``contype 0``, ``conaffinity 6``,
  with the workcell's default contact, stiff from the first touch (the pads hold it without
  sinking, and the wrist sensor measures it at once);
- its *seat* geom (``<name>_seat``, massless) touches the fixtures (their ``contype 1``), the
  hole's walls (``conaffinity 9``) and the other objects' seats (bit 16 both ways), with the
  table's contact: its force builds up over 1.5 mm of penetration, as the tool's does on
  the table, so a held object set down lands as gently as the tool (with the grip's stiff
  contact the force rose within one physics step, before the controller could brake:
  27-67 N at 5-30 mm/s for FORCE 5 N, where the tool peaks under 10 N; docs/language.md).

Each keeps the object's friction (priority 1 over the fixtures and the pads), and with it the
object's ``condim``: the grip geom's contacts with the pads are soft-finger contacts (``condim``
4, :func:`grip_friction`), whatever the pads declare.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np

from cosmos.hand.work_object import ObjectShape, WorkObject

GRIP_CONTYPE, GRIP_CONAFFINITY = 0, 6
"""An object's grip geom: touched by the links (``contype 2``) and the hand (``contype 4``)."""
SEAT_CONTYPE, SEAT_CONAFFINITY = 8 | 16, 1 | 16
"""An object's seat geom: the fixtures (``contype 1``), the hole (``conaffinity 9``), the other
objects' seats, the peg's sleeve and end disc (bit 16); never the hand (``contype 4``,
``conaffinity 1``)."""
OBJECT_PRIORITY = 1
"""Above every other geom's 0: an object's contacts (with the pads, the table, the fixtures)
take its friction (the program's ``FRICTION``) and its contact parameters."""
SEAT_SOLREF = (0.004, 1.0)
SEAT_SOLIMP = (0.2, 0.99, 0.0015, 0.5, 2.0)
"""The table's contact (``cosmos/models/puma560/scene.xml``, ``table_top``: 4 ms, impedance
0 -> 0.99 over 1.5 mm), from 0.2 at the touch: MuJoCo scales a contact's stiffness by the
mass it moves, here the object's, not the arm's, and from 0 the seat was so soft that the
realistic PUMA's force hold of a set-down block cycled between 3.8 and 8 N (its joints'
static friction); an object at rest sinks 0.34 mm under its weight, whatever its mass."""
SOFT_FINGER_LEVER_M = 0.002
"""The torsional friction's lever of a pad's contact point [m]: a soft-finger contact resists a
turn about its normal up to ``mu * SOFT_FINGER_LEVER_M`` times its normal force (the soft-finger
contact of Murray, Li and Sastry, *A Mathematical Introduction to Robotic Manipulation*, 1994,
chapter 5; MuJoCo's ``condim`` 4, whose torsional coefficient is that product). MuJoCo
puts four contact points on a pad pressed on a cylinder (two per strip,
:mod:`cosmos.hand.gripper_scene`), each standing for a quarter of the 18.5 mm line of contact
and the width the rubber gives around it (cosmos/models/panda/README.md, "The hand's pads"):
a 4.6 x 5.7 mm patch, whose mean distance from its centre, the lever of a uniform pressure's
friction, is 2.0 mm."""
OBJECT_RGBA = (0.25, 0.55, 0.85, 1.0)
_GEOM = {ObjectShape.BOX: mujoco.mjtGeom.mjGEOM_BOX, ObjectShape.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER}


def grip_friction(mu: float) -> tuple[float, float, float]:
    """MuJoCo's friction of a cylinder's grip geom: sliding ``mu``, torsional, rolling (unused).

    A cylinder touches a flat pad along a line. Its contacts with the pads are soft fingers
    (``condim`` 4, as every object's; a box keeps MuJoCo's default torsional 5 mm: its flat
    face meets the pad at the corners of their overlap, a couple across the face, not a line).
    Without the torsional part the pads' points hold a turn about the grip's axis (the line
    between the pads) only by their couples, through MuJoCo's soft friction, and a steel peg
    held at 80 N crept about it under half its Coulomb limit, 10.8 deg in 3 s
    (``tests/hand/test_grip_torsion.py``). Two point contacts cannot hold a moment about the
    line through them at all (the book above, chapter 5: a two-fingered grasp needs soft
    fingers for force closure); a rubber pad can, by its area.
    """
    return (mu, mu * SOFT_FINGER_LEVER_M, 0.0001)


def add_objects(spec: mujoco.MjSpec, objects: Sequence[WorkObject]) -> None:
    """Append each object to the scene's world body as a free body (module docstring).

    With objects the workcell has more than one kinematic tree, so MuJoCo's islands (off in
    the scenes: one tree is one island) and sleep are turned on: an object at rest on the
    table sleeps (no contacts, no solver rows) until something awake touches it.
    """
    if objects:
        spec.option.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_ISLAND)
        spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    for item in objects:
        body = spec.worldbody.add_body(name=item.name, pos=item.position_m, quat=item.quat_wxyz)
        body.add_freejoint(name=f"{item.name}_free")
        if item.peg_end:
            _peg(body, item, spec.find_default("tool").geom)
            continue
        a, b, c = item.half_extents_m
        size = (a, b, c) if item.shape is ObjectShape.BOX else (a, c, 0.0)
        grip = body.add_geom(name=f"{item.name}_geom", type=_GEOM[item.shape], size=size, mass=item.mass_kg)
        seat = body.add_geom(name=f"{item.name}_seat", type=_GEOM[item.shape], size=size, mass=0.0)
        for geom in (grip, seat):
            geom.friction = (item.friction, 0.005, 0.0001)
            geom.condim = 4
            geom.priority = OBJECT_PRIORITY
            geom.rgba = OBJECT_RGBA
        if item.shape is ObjectShape.CYLINDER:
            grip.friction = grip_friction(item.friction)
        grip.contype, grip.conaffinity = GRIP_CONTYPE, GRIP_CONAFFINITY
        seat.contype, seat.conaffinity = SEAT_CONTYPE, SEAT_CONAFFINITY
        seat.solref, seat.solimp = SEAT_SOLREF, SEAT_SOLIMP


# The welded peg's chamfered end (cosmos/models/puma560/scene.xml, "Peg"), its +z end here.
_CHAMFER_M = 0.0015
_FACETS = 32
_FACET_POS = (0.00893421393557783, 0.0, -0.000927279164369)  # from the end face
_FACET_TILT_RAD = 0.7825517141122433
_FACET_SIZE = (0.0010636922228183007, 0.0009715949035167694, 0.00025)


def _peg(body: mujoco.MjsBody, item: WorkObject, tool: mujoco.MjsGeom) -> None:
    """A steel peg: a cylinder, a flat end disc and 32 chamfer facets at its +z end.

    Its sleeve and facets, which meet the hole's walls and chamfer, take the welded tool's
    steel contact (``tool``: the scene's ``tool`` default class; models README, "Contacts"),
    so the held peg meets the hole as the welded one does. Its cylinder keeps the workcell's
    default contact, so it stands stiff in the fingers; its end disc is its seat (an object's,
    module docstring), on which it stands in its holder and is set down.
    """
    radius, _, half = item.half_extents_m
    end = half
    cylinder = body.add_geom(
        name=f"{item.name}_geom",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        fromto=(0.0, 0.0, -half, 0.0, 0.0, end - _CHAMFER_M),
        size=(radius, 0.0, 0.0),
        mass=item.mass_kg,
    )
    disc = body.add_geom(
        name=f"{item.name}_end",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        pos=(0.0, 0.0, end - _CHAMFER_M / 2),
        size=(radius - _CHAMFER_M, _CHAMFER_M / 2, 0.0),
        mass=0.0,
    )
    sleeve = body.add_geom(
        name=f"{item.name}_sleeve",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        fromto=(0.0, 0.0, -half, 0.0, 0.0, end - _CHAMFER_M),
        size=(radius, 0.0, 0.0),
        mass=0.0,
    )
    geoms = [cylinder, disc, sleeve]
    for k in range(_FACETS):
        angle = 2 * math.pi * k / _FACETS
        c, s = math.cos(angle), math.sin(angle)
        x, _, dz = _FACET_POS
        quat = np.empty(4)
        mujoco.mju_mulQuat(
            quat,
            np.array([math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]),
            np.array([math.cos(_FACET_TILT_RAD / 2), 0.0, math.sin(_FACET_TILT_RAD / 2), 0.0]),
        )
        facet = body.add_geom(
            name=f"{item.name}_chamfer{k:02d}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=(c * x, s * x, end + dz),
            quat=quat,
            size=_FACET_SIZE,
            mass=0.0,
        )
        facet.contype, facet.conaffinity = 8, 0  # the hole's geoms only (their conaffinity 9)
        geoms.append(facet)
    for geom in geoms:
        geom.friction = (item.friction, 0.005, 0.0001)
        geom.priority = OBJECT_PRIORITY
        geom.rgba = (0.8, 0.8, 0.85, 1.0)
    # The pads and links hold the stiff cylinder; the fixtures' walls (hole and holder) meet the
    # same cylinder as a soft sleeve, and the hole's chamfer its soft facets; the end disc
    # stands on the table, the holder's and the hole's bottoms as an object's seat.
    cylinder.contype, cylinder.conaffinity = 0, 6
    cylinder.friction, cylinder.condim = grip_friction(item.friction), 4
    sleeve.contype, sleeve.conaffinity = 8, SEAT_CONAFFINITY  # and the other objects' seats
    disc.contype, disc.conaffinity = SEAT_CONTYPE, SEAT_CONAFFINITY
    disc.solref, disc.solimp = SEAT_SOLREF, SEAT_SOLIMP
    for geom in geoms[2:]:
        geom.solref, geom.solimp, geom.solmix = tool.solref, tool.solimp, tool.solmix
