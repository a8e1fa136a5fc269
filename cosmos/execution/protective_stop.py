"""A protective stop in words: what tripped, where and how hard (:mod:`cosmos.execution.supervision`).

The supervision's compiled tick finds a stop as numbers (a kind, a contact's or a drive's index,
a value); these functions word it as the ``protective_stop`` event and the failure say it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import IntEnum

import mujoco
import numpy as np

from cosmos.execution.contact_roles import Role
from cosmos.execution.supervision_kernel import PATH_DEVIATION_M

FloatArray = np.ndarray


class StopKind(IntEnum):
    """Why the supervisor stopped the arm."""

    CONTACT = 1
    FORCE = 2
    PATH = 3
    DRIVE = 4
    SPEED = 5


@dataclass(frozen=True)
class ProtectiveStop:
    """A hazard the supervisor found.

    Attributes:
        kind: Which supervision tripped.
        message: ``protective stop: link 3 hit obstacle 'ball' at 2.31 s, 14.2 N``.
        collision: For a contact, ``link3 touches ball`` (the ``collision`` event's reason); else "".
    """

    kind: StopKind
    message: str
    collision: str = ""


def arm_part(owner: str) -> str:
    """``link3`` -> ``link 3``; ``tool`` stays."""
    return f"link {owner.removeprefix('link')}" if owner.startswith("link") else owner


def contact_stop(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    index: int,
    owners: tuple[str, str],
    roles: tuple[int, int],
    obstacle_names: Mapping[str, str],
    t_s: float,
    wrench: FloatArray,
) -> ProtectiveStop:
    """The stop for MuJoCo's contact ``index`` between a part of the arm and something else.

    Its force is the contact's normal force, and for the tool at least what the wrist
    sensor reads: the stop comes at the first touch, before much force has built up.

    Args:
        model: The workcell's model.
        data: Its data, with the contact.
        index: The contact's index in MuJoCo's list.
        owners: The bodies (as the plant names their geoms' owners) of the arm's part, then of the other.
        roles: Their geoms' roles (:class:`cosmos.execution.contact_roles.Role`), in the same order.
        obstacle_names: MuJoCo body name of each occupied obstacle slot -> the obstacle's name.
        t_s: Simulated time [s].
        wrench: The wrist sensor's wrench, world [N, N m]. # (6,)
    """
    force = np.zeros(6)
    mujoco.mj_contactForce(model, data, index, force)
    push = abs(float(force[0]))
    if roles[0] == Role.TOOL:
        push = max(push, float(np.linalg.norm(wrench[:3])))
    arm_owner, owner = owners
    if roles[1] == Role.OBSTACLE:
        name = obstacle_names.get(owner, owner)
        what = f"obstacle '{name}'"
    elif owner == "world":
        name, what = "floor", "the floor"
    elif roles[1] == Role.OBJECT:
        name, what = owner, f"object '{owner}'"
    else:  # as programs name it: hole_fixture's frame is `hole`
        name = owner.removesuffix("_fixture")
        what = f"fixture '{name}'"
    return ProtectiveStop(
        StopKind.CONTACT,
        f"protective stop: {arm_part(arm_owner)} hit {what} at {t_s:.2f} s, {push:.1f} N",
        collision=f"{arm_owner} touches {name}",
    )


def force_stop(push_n: float, limit_n: float, t_s: float) -> ProtectiveStop:
    """The wrist's force ``push_n`` [N] over the statement's ``limit_n`` [N] at ``t_s`` [s]."""
    return ProtectiveStop(
        StopKind.FORCE,
        f"protective stop: {push_n:.1f} N at the wrist at {t_s:.2f} s, above this "
        f"statement's limit of {limit_n:g} N",
    )


def drive_stop(drive: int, limit_nm: float, held_s: float, t_s: float) -> ProtectiveStop:
    """Drive ``drive`` (from 0) at its torque limit [N m] for ``held_s`` [s], at ``t_s`` [s]."""
    return ProtectiveStop(
        StopKind.DRIVE,
        f"protective stop: drive {drive + 1} at its torque limit of "
        f"{limit_nm:g} N m for {held_s * 1e3:.0f} ms at {t_s:.2f} s",
    )


def path_stop(off_m: float, t_s: float) -> ProtectiveStop:
    """The tool ``off_m`` [m] off its commanded line at ``t_s`` [s]."""
    return ProtectiveStop(
        StopKind.PATH,
        f"protective stop: the tool is {off_m * 1e3:.0f} mm off its path at {t_s:.2f} s "
        f"(limit {PATH_DEVIATION_M * 1e3:g} mm)",
    )
