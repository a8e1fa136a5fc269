"""The parallel gripper mounted in a workcell's MuJoCo spec, below the wrist force/torque sensor.

:func:`mount_gripper` edits a scene's spec before it is compiled (as the obstacle slots and a
sweep's variation do): the peg's geoms leave the ``tool`` body, the sensor housing stays,
and the gripper's housing, its two fingers, their pads and the pads' touch sensors are
added inside ``tool``. The ``force``/``torque`` sensor on site ``ft_sensor`` measures the
interaction between ``tool`` and link 6, which is everything in the subtree of ``tool``:
the hand, the fingers and whatever they hold.

Frames (tool body frame = flange frame, z away from the flange, fingers along x):

- coupling plate z 35 .. 45 mm, housing z 45 .. 145 mm (90 x 65 mm);
- each finger a slide on x, its joint the half opening: the left finger's inner face at
  ``x = q_left``, the right one's at ``x = -q_right``, each from 0 (closed) to half the
  85 mm stroke; fingers reach from z 145 to 200 mm (the peg's tip was at 200 mm);
- a rubber pad (1 mm, 22 x 25 mm, friction 1.0) on each inner face, z 175 .. 200 mm, as two
  strips (its upper and lower thirds: two contact lines on a cylinder, not one pivot), and a
  touch site around it (MuJoCo's ``touch`` sums the normal forces of the contacts inside);
  the pad's friction and ``condim`` meet the fixtures: against an object, the contact takes
  the object's (its geom ``priority``; a soft finger, :func:`cosmos.hand.object_scene.grip_friction`);
- the tool point (site ``tool``) between the pads' centres, z 187.5 mm, z along the fingers.

The drive: the two fingers are coupled (a joint equality, the 2F-85's linkage) and driven
together through a tendon, the opening ``q_left + q_right``, by one ``intvelocity``
actuator: its control is the opening speed [m/s], its activation the commanded opening,
and its force ``kp (opening_cmd - opening) - kv opening_dot`` is clipped to the grip force
setting (``actuator_forcerange``, set per GRASP as the 2F-85's force register limits its
motor current). A tendon force ``f`` pushes each pad with ``f``: the grip force.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import mujoco
import numpy as np

from cosmos.hand.tool import FRANKA_HAND, GRIPPER, GripperDatasheet

FINGERS = ("finger_left", "finger_right")
"""The finger bodies and their slide joints, same names."""
PADS = ("pad_left", "pad_right")
"""The pads: geoms ``<pad>`` and ``<pad>_lower`` (two strips), touch sensor and site ``<pad>_touch``."""
OPENING_TENDON = "gripper_opening"
DRIVE = "gripper"
"""The actuator of the fingers (after the arm's motors)."""

_KEEP = ("ft_sensor_housing",)
SENSOR_FACE_Z_M = 0.035
"""The wrist sensor's tool-side face in the tool body: where a hand is mounted [m]."""


@dataclass(frozen=True)
class HandGeometry:
    """A parallel gripper's shape and drive, in the tool body's frame (z away from the flange).

    Attributes:
        datasheet: What it can do.
        housing: Its fixed geoms: name, box or cylinder, MuJoCo size, centre [m], mass [kg].
        housing_inertial: Mass [kg], centre [m] and principal moments [kg m^2] (tool axes) of
            the housing from a published inertial (then the housing geoms carry no mass), or
            None (the geoms' masses).
        finger_base_z_m: Where the fingers' slides are [m].
        finger_half_m: Half sizes of a finger's box [m] (its inner face behind the pad).
        finger_mass_kg: Mass of each finger [kg].
        pad_half_m: Half sizes of a pad (thickness, width, height) [m].
        tcp_z_m: The tool point between the pads' centres [m].
    """

    datasheet: GripperDatasheet
    housing: tuple[
        tuple[str, mujoco.mjtGeom, tuple[float, float, float], tuple[float, float, float], float], ...
    ]
    housing_inertial: tuple[float, tuple[float, float, float], tuple[float, float, float]] | None
    finger_base_z_m: float
    finger_half_m: tuple[float, float, float]
    finger_mass_kg: float
    pad_half_m: tuple[float, float, float]
    tcp_z_m: float


_BOX, _CYLINDER = mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_CYLINDER
ROBOTIQ_2F85 = HandGeometry(
    datasheet=GRIPPER,
    housing=(
        ("gripper_coupling", _CYLINDER, (0.0375, 0.005, 0.0), (0.0, 0.0, 0.040), 0.10),
        ("gripper_housing", _BOX, (0.045, 0.0325, 0.050), (0.0, 0.0, 0.095), 0.625),
    ),
    housing_inertial=None,
    finger_base_z_m=0.145,
    finger_half_m=(0.005, 0.011, 0.0275),
    finger_mass_kg=0.100,
    pad_half_m=(0.0005, 0.011, 0.0125),
    tcp_z_m=0.1875,
)
"""The PUMA's gripper (module docstring; ``cosmos/models/puma560/README.md``, "Gripper")."""

_HAND_Z_M = SENSOR_FACE_Z_M  # the URDF's panda_hand frame, mounted on the sensor's face
FRANKA_HAND_GEOMETRY = HandGeometry(
    datasheet=FRANKA_HAND,
    # A box over the hand's collision mesh (not shipped: its extent, 200 x 60 mm, 58 mm tall
    # to where the fingers start, is this model's), massless: the URDF's inertial carries it.
    housing=(("hand_housing", _BOX, (0.03, 0.10, 0.0292), (0.0, 0.0, _HAND_Z_M + 0.0292), 0.0),),
    # URDF panda_hand: 0.73 kg at (-0.01, 0, 0.03), diag(0.001, 0.0025, 0.0017) in its axes;
    # its fingers close along its y, here along the tool's x: hand y -> tool x, hand x -> -tool y.
    housing_inertial=(0.73, (0.0, 0.01, _HAND_Z_M + 0.03), (0.0025, 0.001, 0.0017)),
    finger_base_z_m=_HAND_Z_M + 0.0584,  # URDF panda_finger_joint1: 0.0584 m from the hand
    finger_half_m=(0.0075, 0.011, 0.027),  # the URDF's collision boxes' extent, 15 x 22 x 54 mm
    finger_mass_kg=0.015,
    pad_half_m=(0.0005, 0.00875, 0.00925),  # the fingertip's 17.5 x 18.5 mm box
    tcp_z_m=_HAND_Z_M + 0.1034,  # URDF panda_hand_tcp_joint
)
"""The Panda's own hand, from ``cosmos/models/panda/source/panda.urdf``, below the sensor."""

HAND_GEOMETRIES = {"puma560": ROBOTIQ_2F85, "panda": FRANKA_HAND_GEOMETRY}
"""Each arm's gripper, by the arm's name."""

PAD_FRICTION = (1.0, 0.005, 0.0001)
"""The pads' friction against the fixtures (an object's contacts take the object's: module docstring)."""
DRIVE_KP_N_PER_M = 2.0e4
"""Stiffness of the drive's position loop on the opening [N/m]: the 2F-85's largest grip force
is reached 12 mm past contact, the Panda hand's 5 mm."""
DRIVE_KV_NS_PER_M = 100.0
"""Its damping [N s/m] (about critical for the 2F-85's fingers, 0.2 kg and the armature)."""
FINGER_ARMATURE_KG = 0.05
"""Reflected inertia of the drive on each finger's slide [kg]."""
TOOL_CONTYPE, TOOL_CONAFFINITY = 4, 1
NOSLIP_ITERATIONS = 3
"""MuJoCo's no-slip pass on the gripper's workcell: without it a soft contact's friction creeps
under a steady load, and a peg held at 60 N turned 2 deg/s in the pads while pressed into the
hole's chamfer (``tests/hand/test_grasp_and_insert.py``)."""


def mount_gripper(spec: mujoco.MjSpec, robot: str = "puma560") -> None:
    """Replace the peg of the scene's ``tool`` body by the arm's gripper (module docstring).

    Args:
        spec: A workcell's spec (``cosmos/models/<arm>/scene.xml``), edited in place.
        robot: The arm's name: the PUMA carries the 2F-85, the Panda its own hand.
    """
    hand = _mounted(HAND_GEOMETRIES.get(robot, ROBOTIQ_2F85), spec)
    spec.option.noslip_iterations = NOSLIP_ITERATIONS
    tool = spec.body("tool")
    for geom in list(tool.geoms):
        if geom.name not in _KEEP:
            spec.delete(geom)
    spec.site("tool").pos = (0.0, 0.0, hand.tcp_z_m)
    holder = tool
    if hand.housing_inertial is not None:
        mass, centre, moments = hand.housing_inertial
        holder = tool.add_body(name="hand", mass=mass, ipos=centre, inertia=moments, explicitinertial=True)
    for name, kind, size, pos, mass in hand.housing:
        _hand_geom(holder, name, kind, size, pos, mass)
    half_stroke = 0.5 * hand.datasheet.stroke_m
    pad = hand.pad_half_m
    strip, strip_z = (pad[0], pad[1], pad[2] / 3), 2 * pad[2] / 3  # upper and lower thirds
    for name, pad_name, side in zip(FINGERS, PADS, (1.0, -1.0), strict=True):
        finger = tool.add_body(name=name, pos=(0.0, 0.0, hand.finger_base_z_m))
        finger.add_joint(
            name=name,
            type=mujoco.mjtJoint.mjJNT_SLIDE,
            axis=(side, 0.0, 0.0),
            range=(0.0, half_stroke),
            armature=FINGER_ARMATURE_KG,
        )
        half = hand.finger_half_m
        behind = 2.0 * pad[0]  # the finger's inner face is behind the pad
        _hand_geom(
            finger, f"{name}_link", _BOX, half, (side * (behind + half[0]), 0.0, half[2]), hand.finger_mass_kg
        )
        pad_z = hand.tcp_z_m - hand.finger_base_z_m
        # Two strips per pad, its upper and lower thirds: a part held at two lines on each
        # side is held against turning about the pad's normal by a couple, as by a real pad's
        # area (one flat box against a cylinder makes one contact, a pivot).
        for part, dz in ((pad_name, strip_z), (f"{pad_name}_lower", -strip_z)):
            geom = _hand_geom(finger, part, _BOX, strip, (side * pad[0], 0.0, pad_z + dz), 0.0)
            geom.friction = PAD_FRICTION
            geom.condim = 4
            geom.solref = (0.004, 1.0)
            geom.solimp = (0.95, 0.99, 0.001, 0.5, 2.0)
            geom.rgba = (0.15, 0.15, 0.15, 1.0)
        finger.add_site(
            name=f"{pad_name}_touch",
            type=_BOX,
            pos=(side * pad[0], 0.0, pad_z),
            size=(3.0 * pad[0], pad[1] + 0.001, pad[2] + 0.001),
            rgba=(0.2, 0.8, 0.2, 0.3),
        )
        spec.add_sensor(
            name=f"{pad_name}_touch",
            type=mujoco.mjtSensor.mjSENS_TOUCH,
            objtype=mujoco.mjtObj.mjOBJ_SITE,
            objname=f"{pad_name}_touch",
        )
    _add_drive(spec, hand.datasheet)


def _mounted(hand: HandGeometry, spec: mujoco.MjSpec) -> HandGeometry:
    """``hand`` moved along z by the flange's height in the ``tool`` body.

    The PUMA's ``tool`` body is at its flange; the Panda's sits at link 7's origin, the flange
    107 mm out (its scene keeps the peg's sensor housing there): the hand hangs from the flange.
    """
    dz = float(spec.site("flange").pos[2] - spec.body("tool").pos[2])
    if dz == 0.0:
        return hand
    inertial = hand.housing_inertial
    return replace(
        hand,
        housing=tuple((n, k, size, (p[0], p[1], p[2] + dz), m) for n, k, size, p, m in hand.housing),
        housing_inertial=None
        if inertial is None
        else (inertial[0], (inertial[1][0], inertial[1][1], inertial[1][2] + dz), inertial[2]),
        finger_base_z_m=hand.finger_base_z_m + dz,
        tcp_z_m=hand.tcp_z_m + dz,
    )


def _add_drive(spec: mujoco.MjSpec, datasheet: GripperDatasheet) -> None:
    """The fingers' linkage (a joint equality), their opening tendon and its drive; open at every key."""
    spec.add_equality(
        name="gripper_linkage",
        type=mujoco.mjtEq.mjEQ_JOINT,
        name1=FINGERS[1],
        name2=FINGERS[0],
        data=np.array([0.0, 1.0] + [0.0] * 10),
    )
    tendon = spec.add_tendon(name=OPENING_TENDON)
    for name in FINGERS:
        tendon.wrap_joint(name, 1.0)
    drive = spec.add_actuator(name=DRIVE, target=OPENING_TENDON, trntype=mujoco.mjtTrn.mjTRN_TENDON)
    drive.set_to_intvelocity(kp=DRIVE_KP_N_PER_M, kv=DRIVE_KV_NS_PER_M)
    drive.actlimited = True
    drive.actrange = (0.0, datasheet.stroke_m)
    drive.ctrlrange = (-datasheet.speed_max_mps, datasheet.speed_max_mps)
    drive.forcelimited = True
    drive.forcerange = (-datasheet.grip_force_max_n, datasheet.grip_force_max_n)
    half_stroke = 0.5 * datasheet.stroke_m
    for key in spec.keys:  # every keyframe starts with the fingers open
        key.qpos = [*key.qpos, half_stroke, half_stroke]
        key.act = [datasheet.stroke_m]


def _hand_geom(
    body: mujoco.MjsBody,
    name: str,
    kind: mujoco.mjtGeom,
    size: tuple[float, float, float],
    pos: tuple[float, float, float],
    mass_kg: float,
) -> mujoco.MjsGeom:
    """A geom of the hand: it touches the world and objects (contype 4, conaffinity 1), never the arm."""
    geom = body.add_geom(name=name, type=kind, size=size, pos=pos, mass=mass_kg)
    geom.contype, geom.conaffinity = TOOL_CONTYPE, TOOL_CONAFFINITY
    geom.rgba = (0.25, 0.25, 0.28, 1.0)
    return geom
