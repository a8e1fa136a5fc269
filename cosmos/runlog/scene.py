"""Scene primitives (fixtures, obstacles) as Foxglove scene entities.

A primitive has an ``id`` unique in the scene; writing one with an id already
shown replaces it (a moving obstacle is re-sent with its new position), and
:meth:`cosmos.runlog.RunLog.scene` deletes ids that are removed.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Final, NamedTuple

from cosmos.runlog.foxglove import WORLD_FRAME, stamp


class Color(NamedTuple):
    """RGBA, each in [0, 1]."""

    r: float
    g: float
    b: float
    a: float = 1.0


FIXTURE_COLOR: Final = Color(0.62, 0.60, 0.56, 1.0)
OBSTACLE_COLOR: Final = Color(0.90, 0.35, 0.20, 0.6)
IDENTITY_WXYZ: Final = (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Box:
    """A box centred on ``position`` with edge lengths ``size`` along its own axes.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre in the world frame [m].
        size: Edge lengths along the box's x, y, z axes [m].
        quat_wxyz: Orientation in the world frame.
        color: Display colour.
    """

    id: str
    position: Sequence[float]
    size: Sequence[float]
    quat_wxyz: Sequence[float] = IDENTITY_WXYZ
    color: Color = OBSTACLE_COLOR


@dataclass(frozen=True)
class Cylinder:
    """A cylinder centred on ``position``, its axis along its own z axis.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre (half-way up the axis) in the world frame [m].
        radius: Radius [m].
        height: Length along the axis [m].
        quat_wxyz: Orientation in the world frame.
        color: Display colour.
    """

    id: str
    position: Sequence[float]
    radius: float
    height: float
    quat_wxyz: Sequence[float] = IDENTITY_WXYZ
    color: Color = OBSTACLE_COLOR


@dataclass(frozen=True)
class Sphere:
    """A sphere centred on ``position``.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre in the world frame [m].
        radius: Radius [m].
        color: Display colour.
    """

    id: str
    position: Sequence[float]
    radius: float
    color: Color = OBSTACLE_COLOR


Primitive = Box | Cylinder | Sphere


def _pose(position: Sequence[float], quat_wxyz: Sequence[float]) -> dict[str, Any]:
    x, y, z = (float(v) for v in position)
    w, qx, qy, qz = (float(v) for v in quat_wxyz)
    return {
        "position": {"x": x, "y": y, "z": z},
        "orientation": {"x": qx, "y": qy, "z": qz, "w": w},
    }


def _xyz(x: float, y: float, z: float) -> dict[str, float]:
    return {"x": float(x), "y": float(y), "z": float(z)}


def entity(primitive: Primitive, t_ns: int) -> dict[str, Any]:
    """The ``foxglove.SceneEntity`` that shows ``primitive`` from ``t_ns`` on."""
    color = primitive.color._asdict()
    shape: dict[str, Any]
    match primitive:
        case Box(position=position, size=size, quat_wxyz=quat):
            shape = {"pose": _pose(position, quat), "size": _xyz(*size), "color": color}
            key = "cubes"
        case Cylinder(position=position, radius=radius, height=height, quat_wxyz=quat):
            shape = {
                "pose": _pose(position, quat),
                "size": _xyz(2 * radius, 2 * radius, height),
                "bottom_scale": 1.0,
                "top_scale": 1.0,
                "color": color,
            }
            key = "cylinders"
        case Sphere(position=position, radius=radius):
            diameter = 2 * radius
            shape = {
                "pose": _pose(position, IDENTITY_WXYZ),
                "size": _xyz(diameter, diameter, diameter),
                "color": color,
            }
            key = "spheres"
    return {
        "timestamp": stamp(t_ns),
        "frame_id": WORLD_FRAME,
        "id": primitive.id,
        "lifetime": {"sec": 0, "nsec": 0},
        "frame_locked": False,
        key: [shape],
    }
