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
- the tool point (site ``tool``) between the pads' centres, z 187.5 mm, z along the fingers.

The drive: the two fingers are coupled (a joint equality, the 2F-85's linkage) and driven
together through a tendon, the opening ``q_left + q_right``, by one ``intvelocity``
actuator: its control is the opening speed [m/s], its activation the commanded opening,
and its force ``kp (opening_cmd - opening) - kv opening_dot`` is clipped to the grip force
setting (``actuator_forcerange``, set per GRASP as the 2F-85's force register limits its
motor current). A tendon force ``f`` pushes each pad with ``f``: the grip force.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.hand.tool import GRIPPER

FINGERS = ("finger_left", "finger_right")
"""The finger bodies and their slide joints, same names."""
PADS = ("pad_left", "pad_right")
"""The pads: geoms ``<pad>`` and ``<pad>_lower`` (two strips), touch sensor and site ``<pad>_touch``."""
OPENING_TENDON = "gripper_opening"
DRIVE = "gripper"
"""The actuator of the fingers (after the arm's motors)."""
TCP_Z_M = 0.1875
"""The tool point between the pads, on the flange's z axis [m]."""

_KEEP = ("ft_sensor_housing",)
_COUPLING = (0.0375, 0.005, 0.040, 0.10)  # radius, half height, centre z [m], mass [kg]
_HOUSING = ((0.045, 0.0325, 0.050), 0.095, 0.625)  # half sizes, centre z [m], mass [kg]
_FINGER_BASE_Z_M = 0.145
_FINGER = ((0.005, 0.011, 0.0275), 0.100)  # half sizes [m], mass [kg] each
_PAD = (0.0005, 0.011, 0.0125)  # half sizes [m]; the pad's centre is at z TCP_Z_M
_PAD_STRIP = (_PAD[0], _PAD[1], _PAD[2] / 3)  # each of its two strips (upper and lower third)
_PAD_STRIP_Z = 2 * _PAD[2] / 3  # their centres above and below the pad's centre [m]
_PAD_FRICTION = (1.0, 0.005, 0.0001)
DRIVE_KP_N_PER_M = 2.0e4
"""Stiffness of the drive's position loop on the opening [N/m]: the largest grip force is
reached 12 mm past contact."""
DRIVE_KV_NS_PER_M = 100.0
"""Its damping [N s/m] (about critical for the fingers' 0.2 kg)."""
FINGER_ARMATURE_KG = 0.05
"""Reflected inertia of the drive on each finger's slide [kg]."""
TOOL_CONTYPE, TOOL_CONAFFINITY = 4, 1
NOSLIP_ITERATIONS = 3
"""MuJoCo's no-slip pass on the gripper's workcell: without it a soft contact's friction creeps
under a steady load, and a peg held at 60 N turned 2 deg/s in the pads while pressed into the
hole's chamfer (``tests/hand/test_grasp_and_insert.py``)."""


def mount_gripper(spec: mujoco.MjSpec) -> None:
    """Replace the peg of the scene's ``tool`` body by the gripper (module docstring).

    Args:
        spec: A workcell's spec (``cosmos/models/<arm>/scene.xml``), edited in place.
    """
    spec.option.noslip_iterations = NOSLIP_ITERATIONS
    tool = spec.body("tool")
    for geom in list(tool.geoms):
        if geom.name not in _KEEP:
            spec.delete(geom)
    spec.site("tool").pos = (0.0, 0.0, TCP_Z_M)
    radius, half, z, mass = _COUPLING
    _hand_geom(tool, "gripper_coupling", mujoco.mjtGeom.mjGEOM_CYLINDER, (radius, half, 0), (0, 0, z), mass)
    sizes, z, mass = _HOUSING
    _hand_geom(tool, "gripper_housing", mujoco.mjtGeom.mjGEOM_BOX, sizes, (0, 0, z), mass)
    half_stroke = 0.5 * GRIPPER.stroke_m
    finger_sizes, finger_mass = _FINGER
    for name, pad, side in zip(FINGERS, PADS, (1.0, -1.0), strict=True):
        finger = tool.add_body(name=name, pos=(0.0, 0.0, _FINGER_BASE_Z_M))
        finger.add_joint(
            name=name,
            type=mujoco.mjtJoint.mjJNT_SLIDE,
            axis=(side, 0.0, 0.0),
            range=(0.0, half_stroke),
            armature=FINGER_ARMATURE_KG,
        )
        behind = 2.0 * _PAD[0]  # the finger's inner face is behind the pad
        _hand_geom(
            finger,
            f"{name}_link",
            mujoco.mjtGeom.mjGEOM_BOX,
            finger_sizes,
            (side * (behind + finger_sizes[0]), 0.0, finger_sizes[2]),
            finger_mass,
        )
        pad_z = TCP_Z_M - _FINGER_BASE_Z_M
        # Two strips per pad, its upper and lower thirds: a part held at two lines on each
        # side is held against turning about the pad's normal by a couple, as by a real pad's
        # area (one flat box against a cylinder makes one contact, a pivot).
        for part, dz in ((pad, _PAD_STRIP_Z), (f"{pad}_lower", -_PAD_STRIP_Z)):
            geom = _hand_geom(
                finger, part, mujoco.mjtGeom.mjGEOM_BOX, _PAD_STRIP, (side * _PAD[0], 0.0, pad_z + dz), 0.0
            )
            geom.friction = _PAD_FRICTION
            geom.condim = 4
            geom.solref = (0.004, 1.0)
            geom.solimp = (0.95, 0.99, 0.001, 0.5, 2.0)
            geom.rgba = (0.15, 0.15, 0.15, 1.0)
        finger.add_site(
            name=f"{pad}_touch",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=(side * _PAD[0], 0.0, pad_z),
            size=(3.0 * _PAD[0], _PAD[1] + 0.001, _PAD[2] + 0.001),
            rgba=(0.2, 0.8, 0.2, 0.3),
        )
        spec.add_sensor(
            name=f"{pad}_touch",
            type=mujoco.mjtSensor.mjSENS_TOUCH,
            objtype=mujoco.mjtObj.mjOBJ_SITE,
            objname=f"{pad}_touch",
        )
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
    drive = spec.add_actuator(
        name=DRIVE,
        target=OPENING_TENDON,
        trntype=mujoco.mjtTrn.mjTRN_TENDON,
    )
    drive.set_to_intvelocity(kp=DRIVE_KP_N_PER_M, kv=DRIVE_KV_NS_PER_M)
    drive.actlimited = True
    drive.actrange = (0.0, GRIPPER.stroke_m)
    drive.ctrlrange = (-GRIPPER.speed_max_mps, GRIPPER.speed_max_mps)
    drive.forcelimited = True
    drive.forcerange = (-GRIPPER.grip_force_max_n, GRIPPER.grip_force_max_n)
    for key in spec.keys:  # every keyframe starts with the fingers open
        key.qpos = [*key.qpos, half_stroke, half_stroke]
        key.act = [GRIPPER.stroke_m]


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
