"""A held object in the controller's model: AL's AFFIX, the object becomes part of the arm.

While the gripper holds an object (GRASP), two things change in the controller's model
(:class:`cosmos.robot_model.RobotModel`), both fixed relative to the last link:

- the **tool frame** is the object's: its origin the centre of the face the object stood on
  (:attr:`WorkObject.base_in_body_m`), its axes the hand's tool axes at the grasp, so every
  following MOVE, CONTACT, SLIDE and INSERT moves that point of the object and keeps the
  object turned as it was when grasped (a MOVE's goal orientation means what it meant for
  the empty hand);
- its declared **mass and inertia** join the last link's (the payload), so the gravity
  g(q), the joint-space inertia A(q) and with them Lambda, mu, p of eq. 27-28 include it,
  and the wrist sensor's reading is compensated for the hand's weight and the object's.

:func:`holding` builds that model from the empty hand's; RELEASE goes back to it. The
object's place in the hand is where the fingers closed on it (the world model's pose of
the object when it is grasped, as AL's AFFIX takes it).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin

from cosmos.hand.work_object import WorkObject
from cosmos.robot_model import RobotModel
from cosmos.workcell import ToolSpec, read_only


def holding(
    hand: RobotModel,
    item: WorkObject,
    rotation_object_to_flange: np.ndarray,
    object_centre_in_flange: np.ndarray,
    declare_payload: bool = True,
) -> RobotModel:
    """The controller's model of the arm holding ``item``.

    Args:
        hand: The model with the empty hand.
        item: The object (its declared mass, shape and sizes).
        rotation_object_to_flange: The object's axes in flange coordinates. # (3, 3)
        object_centre_in_flange: Its centre (centre of mass) in the flange frame [m]. # (3,)
        declare_payload: Add the object's mass and inertia (False: only the tool frame moves,
            the controller ignores the weight it carries; for the comparison in the tests).

    Returns:
        A new model (the hand's is not changed): tool frame at the object's base point, and
        with ``declare_payload`` the object's inertia on the last link.
    """
    model = hand.model.copy()
    flange = model.frames[hand.flange_frame]
    flange_in_joint = flange.placement
    rotation = np.asarray(rotation_object_to_flange, dtype=float)
    centre = np.asarray(object_centre_in_flange, dtype=float)
    base_in_flange = centre + rotation @ np.asarray(item.base_in_body_m)
    # The tool frame: at the object's base point, with the hand's tool axes (module docstring).
    tool_rotation = hand.tool.tool_rotation_in_flange
    model.frames[hand.tool_frame].placement = flange_in_joint * pin.SE3(tool_rotation, base_in_flange)
    tool = replace(hand.tool, tool_position_in_flange=read_only(base_in_flange))
    if declare_payload:
        inertia_in_flange = rotation @ np.diag(item.inertia_diagonal_kgm2()) @ rotation.T
        payload = pin.Inertia(item.mass_kg, centre, inertia_in_flange)
        joint = flange.parentJoint
        model.inertias[joint] = model.inertias[joint] + flange_in_joint.act(payload)
        tool = _with_payload(tool, item.mass_kg, centre, inertia_in_flange)
    return replace(hand, tool=tool, model=model, data=model.createData())


def _with_payload(tool: ToolSpec, mass_kg: float, centre: np.ndarray, inertia: np.ndarray) -> ToolSpec:
    """The tool's mass properties with a point of the payload added (parallel-axis theorem)."""
    total = tool.mass_kg + mass_kg
    com = (tool.mass_kg * tool.com_in_flange + mass_kg * centre) / total

    def shifted(i: np.ndarray, m: float, c: np.ndarray) -> np.ndarray:
        r = c - com
        return i + m * (float(r @ r) * np.eye(3) - np.outer(r, r))

    combined = shifted(tool.inertia_in_flange, tool.mass_kg, tool.com_in_flange) + shifted(
        inertia, mass_kg, centre
    )
    return replace(tool, mass_kg=total, com_in_flange=read_only(com), inertia_in_flange=read_only(combined))
