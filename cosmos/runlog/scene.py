"""Scene primitives (the arm's links, fixtures, obstacles) as Foxglove scene entities.

A primitive has an ``id`` unique in the scene; writing one with an id already
shown replaces it (a moving obstacle is re-sent with its new position), and
:meth:`cosmos.runlog.RunLog.scene` deletes ids that are removed. A primitive
is placed in its ``frame``: ``world``, or a frame of ``/tf`` (an arm link), to
which the entity is locked so that it moves with the link.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Final, NamedTuple

from foxglove import messages as fm

from cosmos.runlog.foxglove import WORLD_FRAME, stamp


class Color(NamedTuple):
    """RGBA, each in [0, 1]."""

    r: float
    g: float
    b: float
    a: float = 1.0


FIXTURE_COLOR: Final = Color(0.62, 0.60, 0.56, 1.0)
LINK_COLOR: Final = Color(0.75, 0.75, 0.78, 1.0)
OBSTACLE_COLOR: Final = Color(0.90, 0.35, 0.20, 0.6)
IDENTITY_WXYZ: Final = (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Box:
    """A box centred on ``position`` with edge lengths ``size`` along its own axes.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre in ``frame`` [m].
        size: Edge lengths along the box's x, y, z axes [m].
        quat_wxyz: Orientation in the frame.
        color: Display colour.
        frame: Frame of the pose: ``world`` or a frame of ``/tf``.
    """

    id: str
    position: Sequence[float]
    size: Sequence[float]
    quat_wxyz: Sequence[float] = IDENTITY_WXYZ
    color: Color = OBSTACLE_COLOR
    frame: str = WORLD_FRAME


@dataclass(frozen=True)
class Cylinder:
    """A cylinder centred on ``position``, its axis along its own z axis.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre (half-way up the axis) in ``frame`` [m].
        radius: Radius [m].
        height: Length along the axis [m].
        quat_wxyz: Orientation in the frame.
        color: Display colour.
        frame: Frame of the pose: ``world`` or a frame of ``/tf``.
    """

    id: str
    position: Sequence[float]
    radius: float
    height: float
    quat_wxyz: Sequence[float] = IDENTITY_WXYZ
    color: Color = OBSTACLE_COLOR
    frame: str = WORLD_FRAME


@dataclass(frozen=True)
class Sphere:
    """A sphere centred on ``position``.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre in ``frame`` [m].
        radius: Radius [m].
        color: Display colour.
        frame: Frame of the position: ``world`` or a frame of ``/tf``.
    """

    id: str
    position: Sequence[float]
    radius: float
    color: Color = OBSTACLE_COLOR
    frame: str = WORLD_FRAME


@dataclass(frozen=True)
class Capsule:
    """A capsule: a cylinder of ``half_length`` either side of ``position`` with hemispherical ends.

    Foxglove has no capsule: it is drawn as a cylinder and two spheres.

    Attributes:
        id: Name of the entity, unique in the scene.
        position: Centre in ``frame`` [m].
        radius: Radius [m].
        half_length: Half the length of the cylindrical part, along its own z axis [m].
        quat_wxyz: Orientation in the frame.
        color: Display colour.
        frame: Frame of the pose: ``world`` or a frame of ``/tf``.
    """

    id: str
    position: Sequence[float]
    radius: float
    half_length: float
    quat_wxyz: Sequence[float] = IDENTITY_WXYZ
    color: Color = LINK_COLOR
    frame: str = WORLD_FRAME


Shape = Box | Cylinder | Sphere | Capsule


@dataclass(frozen=True)
class Group:
    """Several shapes shown as one entity in one frame (an arm link and what it carries).

    Attributes:
        id: Name of the entity, unique in the scene.
        frame: Frame of every part's pose (the parts' own ``frame`` is not used).
        parts: The shapes.
    """

    id: str
    frame: str
    parts: tuple[Shape, ...]


Primitive = Box | Cylinder | Sphere | Capsule | Group


def _pose(position: Sequence[float], quat_wxyz: Sequence[float]) -> fm.Pose:
    x, y, z = (float(v) for v in position)
    w, qx, qy, qz = (float(v) for v in quat_wxyz)
    return fm.Pose(position=fm.Vector3(x=x, y=y, z=z), orientation=fm.Quaternion(x=qx, y=qy, z=qz, w=w))


def _color(color: Color) -> fm.Color:
    return fm.Color(r=color.r, g=color.g, b=color.b, a=color.a)


def _rotate(quat_wxyz: Sequence[float], v: Sequence[float]) -> list[float]:
    """``v`` rotated by the unit quaternion ``quat_wxyz``."""
    w, x, y, z = (float(c) for c in quat_wxyz)
    vx, vy, vz = (float(c) for c in v)
    # t = 2 q_vec x v; v' = v + w t + q_vec x t
    tx, ty, tz = 2 * (y * vz - z * vy), 2 * (z * vx - x * vz), 2 * (x * vy - y * vx)
    return [
        vx + w * tx + (y * tz - z * ty),
        vy + w * ty + (z * tx - x * tz),
        vz + w * tz + (x * ty - y * tx),
    ]


class _Parts:
    """The primitive lists of one entity, filled shape by shape."""

    def __init__(self) -> None:
        self.cubes: list[fm.CubePrimitive] = []
        self.cylinders: list[fm.CylinderPrimitive] = []
        self.spheres: list[fm.SpherePrimitive] = []

    def sphere(self, position: Sequence[float], radius: float, color: Color) -> None:
        d = 2 * float(radius)
        self.spheres.append(
            fm.SpherePrimitive(
                pose=_pose(position, IDENTITY_WXYZ), size=fm.Vector3(x=d, y=d, z=d), color=_color(color)
            )
        )

    def cylinder(
        self, position: Sequence[float], quat: Sequence[float], radius: float, height: float, color: Color
    ) -> None:
        d = 2 * float(radius)
        self.cylinders.append(
            fm.CylinderPrimitive(
                pose=_pose(position, quat),
                size=fm.Vector3(x=d, y=d, z=float(height)),
                bottom_scale=1.0,
                top_scale=1.0,
                color=_color(color),
            )
        )

    def add(self, shape: Shape) -> None:
        match shape:
            case Box(position=position, size=size, quat_wxyz=quat, color=color):
                x, y, z = (float(v) for v in size)
                self.cubes.append(
                    fm.CubePrimitive(
                        pose=_pose(position, quat), size=fm.Vector3(x=x, y=y, z=z), color=_color(color)
                    )
                )
            case Cylinder(position=position, radius=radius, height=height, quat_wxyz=quat, color=color):
                self.cylinder(position, quat, radius, height, color)
            case Sphere(position=position, radius=radius, color=color):
                self.sphere(position, radius, color)
            case Capsule(position=p, radius=radius, half_length=half, quat_wxyz=quat, color=color):
                self.cylinder(p, quat, radius, 2 * half, color)
                axis = _rotate(quat, (0.0, 0.0, float(half)))
                for sign in (1.0, -1.0):
                    self.sphere([float(c) + sign * a for c, a in zip(p, axis, strict=True)], radius, color)


def entity(primitive: Primitive, t_ns: int) -> fm.SceneEntity:
    """The ``foxglove.SceneEntity`` that shows ``primitive`` from ``t_ns`` on, in its frame."""
    parts = _Parts()
    if isinstance(primitive, Group):
        for shape in primitive.parts:
            parts.add(shape)
    else:
        parts.add(primitive)
    return fm.SceneEntity(
        timestamp=stamp(t_ns),
        frame_id=primitive.frame,
        id=primitive.id,
        lifetime=fm.Duration(0, 0),
        frame_locked=primitive.frame != WORLD_FRAME,
        cubes=parts.cubes,
        cylinders=parts.cylinders,
        spheres=parts.spheres,
    )
