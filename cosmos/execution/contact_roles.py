"""What each geom of the workcell is to the protective stops, and what a contact between two is.

Each geom gets a :class:`Role` (a link, the tool with what hangs from it and what it
holds, a fixture, an obstacle, an object); each pair of roles a kind the compiled look at
MuJoCo's contact list reads (:mod:`cosmos.execution.contact_kernel`): nothing of the arm,
the tool on a fixture or an object, the tool on an obstacle, a link on anything.
"""

from __future__ import annotations

from enum import IntEnum

import mujoco
import numpy as np

from cosmos.execution.contact_kernel import IGNORED, LINK_ANY, TOOL_FIXTURE, TOOL_OBSTACLE
from cosmos.execution.fixtures import FIXTURES
from cosmos.obstacles.capsules import is_link
from cosmos.obstacles.scene import SLOT_PREFIX
from cosmos.plant import Plant
from cosmos.workcell import TOOL_BODY, descends

FREE = mujoco.mjtJoint.mjJNT_FREE


class Role(IntEnum):
    """What a geom belongs to, for the contact supervision."""

    NONE = 0  # touches nothing (contype = conaffinity = 0) or not named
    LINK = 1
    TOOL = 2  # the tool's body and the bodies on it (a gripper's fingers), and a held object
    FIXTURE = 3  # table, hole, plate, floor
    OBSTACLE = 4  # an OBSTACLE slot
    OBJECT = 5  # a free body of the workcell (OBJECT, the gripper's peg and blocks) not held


ROLES = len(Role)


def pair_kind(a: Role, b: Role) -> int:
    """What a contact between geoms of roles ``a`` and ``b`` is, for the supervision."""
    arm = {Role.LINK, Role.TOOL}
    if (a in arm) == (b in arm) or Role.NONE in (a, b):
        return IGNORED  # nothing of the arm, or the arm on itself
    part, other = (a, b) if a in arm else (b, a)
    if part is Role.LINK:
        return LINK_ANY
    return TOOL_OBSTACLE if other is Role.OBSTACLE else TOOL_FIXTURE  # an object as a fixture


PAIR_KINDS = [pair_kind(a, b) for a in Role for b in Role]
"""Per pair of roles (``role1 * len(Role) + role2``): what such a contact is (looked up per contact)."""


def geom_roles(plant: Plant) -> np.ndarray:
    """Each geom's :class:`Role` in ``plant`` (nothing held), read-only. # (ngeom,) int8."""
    model = plant.model
    roles = np.zeros(model.ngeom, dtype=np.int8)
    tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, TOOL_BODY)
    for geom, owner in enumerate(plant.geom_owners):
        if model.geom_contype[geom] == 0 and model.geom_conaffinity[geom] == 0:
            continue
        body = int(model.geom_bodyid[geom])
        if is_link(owner):
            roles[geom] = Role.LINK
        elif descends(model, body, tool):  # the tool's body, a gripper's finger
            roles[geom] = Role.TOOL
        elif owner.startswith(SLOT_PREFIX):
            roles[geom] = Role.OBSTACLE
        elif owner in FIXTURES or owner == "world":
            roles[geom] = Role.FIXTURE
        elif model.body_jntnum[body] and model.jnt_type[model.body_jntadr[body]] == FREE:
            roles[geom] = Role.OBJECT
    roles.setflags(write=False)
    return roles
