"""An OBSTACLE placed through the arm where the program starts, foreseen from its text.

The run adds an obstacle as a body of the simulation and refuses one that overlaps the arm
(:meth:`cosmos.execution.obstacles.ObstacleWorld.apply`: "OBSTACLE lamp would be placed through
the arm (link5 inside it)"), at the moment it is added. Where that moment is known to find the
arm at home (an OBSTACLE before anything that moves it: the first motion, a block, a GRASP), the
checker says so at the statement.

The arm is judged by capsules *inscribed* in its collision geoms at home (a capsule geom
itself; the longest capsule inside a cylinder or a box): an obstacle that reaches into one
reaches into the arm, so the warning is never false; a graze of a geom's corner is left to the
run.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from cosmos import plan
from cosmos.runtime.fixture_solids import signed_distances
from cosmos.runtime.goals_in_fixtures import obstacle_solid
from cosmos.user_cache import cached_array

SAMPLES = 64
"""Points along each capsule's segment at which the obstacle's distance is taken."""


@dataclass(frozen=True)
class ArmCapsule:
    """A capsule inside one collision geom of the arm at home.

    Attributes:
        part: The link (``link5``) or ``tool`` the geom belongs to.
        a: One end of its segment, world [m], read-only. # (3,)
        b: The other end, world [m], read-only. # (3,)
        radius_m: Its radius [m].
    """

    part: str
    a: np.ndarray
    b: np.ndarray
    radius_m: float

    def as_json(self) -> dict[str, Any]:
        """Its entries for the user cache's JSON (:func:`from_json` reads them back)."""
        return {"part": self.part, "a": self.a.tolist(), "b": self.b.tolist(), "radius": self.radius_m}

    @staticmethod
    def from_json(entries: dict[str, Any]) -> ArmCapsule:
        """The capsule :meth:`as_json` wrote."""
        a, b = cached_array(entries["a"], (3,)), cached_array(entries["b"], (3,))
        return ArmCapsule(str(entries["part"]), a, b, float(entries["radius"]))


def inscribed(
    kind: str, center: np.ndarray, rotation: np.ndarray, size: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float]:
    """The longest capsule inside a MuJoCo capsule, cylinder or box geom: its segment's ends and radius.

    Args:
        kind: ``capsule``, ``cylinder`` or ``box``.
        center: The geom's centre, world [m]. # (3,)
        rotation: Its axes (geom to world). # (3, 3)
        size: MuJoCo's ``size`` of it [m]. # (3,)
    """
    if kind == "box":
        axis = int(np.argmax(size))
        radius = float(min(size[i] for i in range(3) if i != axis))
        half = float(size[axis]) - radius
    else:
        axis, radius = 2, float(size[0])
        half = float(size[1]) if kind == "capsule" else float(size[1]) - radius
    if half < 0.0:  # a cylinder shorter than it is wide: the ball inside it
        radius, half = radius + half, 0.0
    along = rotation[:, axis] * half
    return center - along, center + along, radius


def capsules_at(model: Any, data: Any) -> tuple[ArmCapsule, ...]:
    """The capsules inside the collision geoms of the arm's links and tool, where ``data`` has them."""
    import mujoco

    capsules = []
    for g in range(model.ngeom):
        kind = mujoco.mjtGeom(int(model.geom_type[g])).name.removeprefix("mjGEOM_").lower()
        if kind not in ("capsule", "cylinder", "box") or (
            model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0
        ):
            continue
        body, part = int(model.geom_bodyid[g]), None
        while body != 0 and part is None:  # the link or tool it belongs to, if any
            name = model.body(body).name
            part = (
                name
                if name == "tool" or (name.startswith("link") and name[4:].isdigit() and name != "link0")
                else None
            )
            body = int(model.body_parentid[body])
        if part is not None:
            a, b, radius = inscribed(
                kind, data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
            )
            capsules.append(ArmCapsule(part, cached_array(a, (3,)), cached_array(b, (3,)), radius))
    return tuple(capsules)


def obstacles_through_arm(steps: tuple[plan.Step, ...], arm: tuple[ArmCapsule, ...]) -> list[plan.Diagnostic]:
    """A warning for each OBSTACLE that the text adds into the arm at home.

    Args:
        steps: The compiled plan's steps.
        arm: The arm's capsules at home.

    Returns:
        One diagnostic per such obstacle, at its statement.
    """
    found = []
    for step in steps:
        if isinstance(step, plan.AddObstacle):
            parts = _parts_inside(step, arm)
            if parts:
                inside = ", ".join(f"{part} inside it" for part in parts)
                found.append(
                    plan.Diagnostic(
                        f"OBSTACLE {step.name} would be placed through the arm at its home pose "
                        f"({inside}); the run will fail here",
                        step.span,
                    )
                )
        elif not isinstance(step, plan.RemoveObstacle):
            break  # the arm may have moved (a WAIT may turn it in its null space)
    return found


def _parts_inside(step: plan.AddObstacle, arm: tuple[ArmCapsule, ...]) -> list[str]:
    """The arm's parts (links, the tool) whose capsules the obstacle reaches into, in order."""
    weights = np.linspace(0.0, 1.0, SAMPLES)[:, None]
    parts: list[str] = []
    for capsule in arm:
        points = capsule.a + weights * (capsule.b - capsule.a)  # (SAMPLES, 3)
        if capsule.part not in parts and np.min(_distances(step, points)) < capsule.radius_m:
            parts.append(capsule.part)
    return parts


def _distances(step: plan.AddObstacle, points: np.ndarray) -> np.ndarray:
    """Signed distances from ``points`` to the obstacle where it is added [m]: negative inside."""
    center = np.asarray(step.position_world, dtype=float)
    rotation = np.asarray(step.rotation_world, dtype=float)
    if step.shape is plan.ObstacleShape.PLANE:  # the solid side is behind its normal
        return (points - center) @ rotation[:, 2]
    solid = obstacle_solid(replace(step, velocity_world_mps=np.zeros(3)))  # MOVING: where it starts
    assert solid is not None  # every shape but a plane has a solid
    return signed_distances((solid,), points)[:, 0]
