"""Collision events: contacts between the arm and anything it should not touch.

The tool touching a fixture (table, hole, plate) is the task's intended
contact. Anything else the simulator reports between the arm and the world is
a collision: the arm (a link or the tool) against an obstacle, or a link
against a fixture or the floor.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from cosmos.obstacles.capsules import is_arm_body
from cosmos.plant import Plant
from cosmos.workcell import TOOL_BODY


@dataclass(frozen=True)
class Collision:
    """One unintended contact.

    Attributes:
        arm_body: The arm's body in contact (``link1`` .. ``link<n>`` or ``tool``).
        other: The obstacle's name, or the body it touched (``world`` for the floor).
        is_obstacle: True when ``other`` is an obstacle.
        depth_m: Penetration depth (>= 0), in [m].
    """

    arm_body: str
    other: str
    is_obstacle: bool
    depth_m: float


def collisions(plant: Plant, obstacle_geoms: Mapping[str, str]) -> list[Collision]:
    """The plant's current contacts that are collisions, one per (arm body, other) pair.

    Args:
        plant: The simulated workcell.
        obstacle_geoms: MuJoCo geom name of a slot -> obstacle name, for the obstacles
            in the scene (:meth:`cosmos.obstacles.ObstacleScene.body_names`).

    Returns:
        The collisions, deepest penetration per pair, in the order MuJoCo found them.
        ``other`` is the obstacle's name, else the body touched.
    """
    found: dict[tuple[str, str], Collision] = {}
    for contact in plant.contacts():
        if is_arm_body(contact.body1) and not is_arm_body(contact.body2):
            arm, other, other_geom = contact.body1, contact.body2, contact.geom2
        elif is_arm_body(contact.body2) and not is_arm_body(contact.body1):
            arm, other, other_geom = contact.body2, contact.body1, contact.geom1
        else:
            continue
        is_obstacle = other_geom in obstacle_geoms
        if arm == TOOL_BODY and not is_obstacle:
            continue  # the tool on a fixture: the intended contact
        name = obstacle_geoms[other_geom] if is_obstacle else other
        depth = max(0.0, -contact.distance_m)
        previous = found.get((arm, name))
        if previous is None or depth > previous.depth_m:
            found[(arm, name)] = Collision(arm, name, is_obstacle, depth)
    return list(found.values())
