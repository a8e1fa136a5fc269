"""Which hand the arm carries, and the gripper's datasheet (no simulator: the language imports it).

The workcell's scene files carry the welded peg (``TOOL PEG``, the default, so every
program and figure from before the gripper runs unchanged). ``TOOL GRIPPER`` replaces the
peg by a parallel two-finger gripper mounted below the same wrist force/torque sensor
(:mod:`cosmos.hand.gripper_scene`), so the wrist sensor measures the hand and everything
it holds.

The gripper is a Robotiq 2F-85 reduced to what a parallel grasp needs. From its datasheet
(Robotiq, *2F-85 & 2F-140 Instruction Manual*, section 6.1 "Specifications"): stroke
85 mm, grip force 20 to 235 N, closing speed 20 to 150 mm/s, mass 0.925 kg. The 2F-85's
linkage keeps its fingertips parallel in a pinch grasp; its fingertips also rise a few
millimetres as it closes (Robotiq's note on the gripper's vertical motion), which this
model leaves out: each finger is a straight slide. The dimensions of the housing and
fingers are this model's own, of the 2F-85's order (``cosmos/models/puma560/README.md``,
"Gripper").
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class Tool(Enum):
    """The hand on the flange."""

    PEG = "peg"
    """The welded peg of the shipped workcell (the default)."""
    GRIPPER = "gripper"
    """A parallel two-finger gripper with a force sensor in each finger pad."""


@dataclass(frozen=True)
class GripperDatasheet:
    """What the gripper can do, as its datasheet states it.

    Attributes:
        stroke_m: Largest opening between the finger pads [m].
        grip_force_min_n: Smallest grip force the drive can hold [N].
        grip_force_max_n: Largest grip force [N].
        speed_min_mps: Slowest closing speed [m/s].
        speed_max_mps: Fastest closing speed [m/s].
        mass_kg: Mass of the whole gripper, fingers included [kg].
    """

    stroke_m: float = 0.085
    grip_force_min_n: float = 20.0
    grip_force_max_n: float = 235.0
    speed_min_mps: float = 0.020
    speed_max_mps: float = 0.150
    mass_kg: float = 0.925


GRIPPER = GripperDatasheet()
"""The PUMA's gripper of ``TOOL GRIPPER`` (a Robotiq 2F-85, module docstring)."""

FRANKA_HAND = GripperDatasheet(
    stroke_m=0.080,
    grip_force_min_n=GRIPPER.grip_force_min_n,
    grip_force_max_n=100.0,
    speed_min_mps=GRIPPER.speed_min_mps,
    speed_max_mps=0.150,
    mass_kg=0.73 + 2 * 0.015,
)
"""The Panda's own hand (``cosmos/models/panda/source/panda.urdf``: ``panda_hand`` 0.73 kg,
``panda_leftfinger``/``panda_rightfinger`` 0.015 kg each, finger joints 0 .. 0.04 m with an
effort limit of 100 N and 0.2 m/s); the URDF gives no smallest force: the 2F-85's is kept,
and the fastest closing is the 2F-85's too (the datasheets' order)."""

HANDS: dict[str, GripperDatasheet] = {"puma560": GRIPPER, "panda": FRANKA_HAND}
"""Each arm's gripper, by the arm's name (``ROBOT``)."""


def gripper_of(robot: str) -> GripperDatasheet:
    """The datasheet of the gripper ``TOOL GRIPPER`` mounts on the arm named ``robot``."""
    return HANDS.get(robot, GRIPPER)


DEFAULT_GRIP_FORCE_N = 40.0
"""The grip force of a GRASP that names none [N]."""

DEFAULT_FINGER_SPEED_MPS = 0.050
"""The fingers' closing and opening speed [m/s]."""


def tool_named(name: str) -> Tool | None:
    """The tool called ``name`` (case-insensitive), or None."""
    for tool in Tool:
        if tool.value == name.lower():
            return tool
    return None
