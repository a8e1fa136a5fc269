"""The arm's links and the tool as capsules, in the frames of the controller's joints.

Seed section 6 controls each link's point closest to an obstacle. Each link is
modelled by capsules (a segment swollen by a radius), the collision geoms of
the workcell's arm and tool (the arm's ``scene.xml``, bodies ``link1`` .. ``link<n>`` and
``tool``): a capsule geom is taken as it is, a cylinder as the capsule of its
axis and radius (which contains it). A box is allowed only where it lies inside
another capsule of its link (the facets of the peg's chamfer inside the peg's
capsule), and is then left out. The segment ends are expressed in the
frame of the Pinocchio joint that carries the body, so the controller places
them from its own kinematics: ``a_world = oMi[joint] * a_joint``.

A *link* here is everything rigidly attached to one joint: the last link includes the
flange and the tool (sensor housing, collar, peg). A geom that lies inside
another geom of the same link (the peg's collar inside the sensor housing's
capsule) can never be that link's closest point and is left out.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from cosmos.errors import CosmosError
from cosmos.model_facts import kept
from cosmos.robot_model import RobotModel
from cosmos.workcell import SCENE_XML, TOOL_BODY, scene_model

FloatArray = np.ndarray

LINK_BODIES = ("link1", "link2", "link3", "link4", "link5", "link6")
"""Bodies of the PUMA's links, link ``k`` turned by joint ``k`` (any arm's: :func:`is_link`)."""
ARM_BODIES = (*LINK_BODIES, TOOL_BODY)
"""Every body of the PUMA in the simulation, the tool included (any arm's: :func:`is_arm_body`)."""

_LINK_NAME = re.compile(r"link[1-9][0-9]*")


def is_link(body: str) -> bool:
    """Whether ``body`` is one of an arm's links ``link1`` .. ``link<n>`` (link k turned by joint k)."""
    return _LINK_NAME.fullmatch(body) is not None


def is_arm_body(body: str) -> bool:
    """Whether ``body`` is part of the arm in the simulation: a link or the tool."""
    return body == TOOL_BODY or is_link(body)


@dataclass(frozen=True)
class LinkCapsules:
    """The capsules of the arm, stacked for vectorised evaluation (arrays read-only).

    Attributes:
        names: Geom name of each capsule in the scene. # (n,)
        links: Link of each capsule, ``link1`` .. ``link6`` (link 6 with the tool). # (n,)
        joint: Index of the carrying joint in q, 0 .. 5. # (n,)
        a_in_joint: Segment start in the joint's frame, in [m]. # (n, 3)
        b_in_joint: Segment end in the joint's frame, in [m]. # (n, 3)
        radius_m: Capsule radius, in [m]. # (n,)
        bound_m: Radius of a sphere about the segment's midpoint that holds the
            capsule (half length plus radius), in [m]. # (n,)
    """

    names: tuple[str, ...]
    links: tuple[str, ...]
    joint: np.ndarray
    a_in_joint: FloatArray
    b_in_joint: FloatArray
    radius_m: FloatArray
    bound_m: FloatArray

    def __len__(self) -> int:
        return len(self.names)


def _frozen(array: object) -> FloatArray:
    out = np.array(array, dtype=float)
    out.setflags(write=False)
    return out


def _segment_in_body(model: mujoco.MjModel, geom: int) -> tuple[FloatArray, FloatArray, float]:
    """The segment ends (in the geom's body frame) and radius of a capsule or cylinder geom."""
    kind = int(model.geom_type[geom])
    if kind not in (int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER)):
        raise CosmosError(f"arm geom '{model.geom(geom).name}' must be a capsule or a cylinder")
    axis = np.empty(9)
    mujoco.mju_quat2Mat(axis, model.geom_quat[geom])
    half = float(model.geom_size[geom, 1]) * axis.reshape(3, 3)[:, 2]
    center = model.geom_pos[geom]
    return center - half, center + half, float(model.geom_size[geom, 0])


def _body_in_link(model: mujoco.MjModel, body: int) -> pin.SE3:
    """Pose of ``body`` in its nearest ancestor among the links (identity for a link)."""
    pose = pin.SE3.Identity()
    while not is_link(model.body(body).name):
        rotation = np.empty(9)
        mujoco.mju_quat2Mat(rotation, model.body_quat[body])
        if model.body_jntnum[body] != 0:
            raise CosmosError(f"body '{model.body(body).name}' must be welded to a link")
        pose = pin.SE3(rotation.reshape(3, 3), model.body_pos[body].copy()) * pose
        body = int(model.body_parentid[body])
    return pose


def _box_corners(model: mujoco.MjModel, geom: int) -> FloatArray:
    """The eight corners of a box geom, in its body's frame. # (8, 3)."""
    rotation = np.empty(9)
    mujoco.mju_quat2Mat(rotation, model.geom_quat[geom])
    signs = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    return model.geom_pos[geom] + (signs * model.geom_size[geom]).dot(rotation.reshape(3, 3).T)


def _link_of(model: mujoco.MjModel, body: int) -> str:
    """The link (``link1`` .. ``link<n>``) that ``body`` is, or is welded to."""
    while not is_link(model.body(body).name):
        body = int(model.body_parentid[body])
    return str(model.body(body).name)


@functools.cache
def _scene_capsules(
    scene_xml: Path = SCENE_XML,
) -> tuple[tuple[str, str, FloatArray, FloatArray, float], ...]:
    """:func:`scene_capsules` once per model (kept in the user cache: :mod:`cosmos.model_facts`)."""
    return kept(scene_xml.parent, f"capsules:{scene_xml.name}", lambda: scene_capsules(scene_xml))


def scene_capsules(scene_xml: Path = SCENE_XML) -> tuple[tuple[str, str, FloatArray, FloatArray, float], ...]:
    """(geom, link, a, b, radius) of every collision geom of the arm, ends in the link's body frame."""
    model = scene_model(scene_xml)  # the workcell's compiled scene: the file is not parsed again
    out = []
    boxes = []
    for geom in range(model.ngeom):
        body = int(model.geom_bodyid[geom])
        if not is_arm_body(model.body(body).name):
            continue
        if model.geom_contype[geom] == 0 and model.geom_conaffinity[geom] == 0:
            continue  # visual only
        to_link = _body_in_link(model, body)
        link = _link_of(model, body)
        if model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_BOX:
            corners = np.array([to_link.act(c) for c in _box_corners(model, geom)])
            boxes.append((model.geom(geom).name, link, corners))
            continue
        a, b, radius = _segment_in_body(model, geom)
        out.append((model.geom(geom).name, link, to_link.act(a), to_link.act(b), radius))
    for name, link, corners in boxes:  # a box inside a capsule is never the closer one
        if not any(other[1] == link and _corners_inside(corners, other) for other in out):
            raise CosmosError(
                f"{scene_xml}: arm geom '{name}' is a box outside the link's capsules; "
                "make it a capsule or a cylinder"
            )
    return tuple(
        capsule
        for capsule in out
        if not any(
            other is not capsule and other[1] == capsule[1] and _inside(capsule, other) for other in out
        )
    )


def _corners_inside(corners: FloatArray, outer: tuple[str, str, FloatArray, FloatArray, float]) -> bool:
    """True when every corner lies within capsule ``outer`` (a capsule is convex: so does the box)."""
    return all(_segment_distance(c, outer[2], outer[3]) <= outer[4] + 1e-9 for c in corners)


def _segment_distance(point: FloatArray, a: FloatArray, b: FloatArray) -> float:
    """Distance from ``point`` to the segment ``a``-``b``."""
    d = b - a
    t = 0.0 if d.dot(d) < 1e-18 else min(1.0, max(0.0, float((point - a).dot(d) / d.dot(d))))
    return float(np.linalg.norm(point - a - t * d))


def _inside(
    inner: tuple[str, str, FloatArray, FloatArray, float],
    outer: tuple[str, str, FloatArray, FloatArray, float],
) -> bool:
    """True when capsule ``inner`` lies within capsule ``outer`` (then it never is the closer one)."""
    room = outer[4] - inner[4] + 1e-9
    return all(_segment_distance(end, outer[2], outer[3]) <= room for end in (inner[2], inner[3]))


def arm_capsules(robot: RobotModel) -> LinkCapsules:
    """The arm's and the tool's capsules in the frames of ``robot``'s joints.

    Args:
        robot: The controller's model; its body frames ``link1`` .. ``link<n>``
            place the scene's link bodies (of its arm's scene) on the joints.

    Returns:
        The capsules, in scene order.
    """
    names, links, joints, starts, ends, radii = [], [], [], [], [], []
    for geom, link, a, b, radius in _scene_capsules(robot.description.scene_xml):
        frame = robot.model.frames[robot.model.getFrameId(link, pin.BODY)]
        names.append(geom)
        links.append(link)
        joints.append(frame.parentJoint - 1)  # Pinocchio joint 0 is the universe
        starts.append(frame.placement.act(a))
        ends.append(frame.placement.act(b))
        radii.append(radius)
    a_arr, b_arr, r_arr = np.array(starts), np.array(ends), np.array(radii)
    joint = np.array(joints, dtype=int)
    joint.setflags(write=False)
    return LinkCapsules(
        names=tuple(names),
        links=tuple(links),
        joint=joint,
        a_in_joint=_frozen(a_arr),
        b_in_joint=_frozen(b_arr),
        radius_m=_frozen(r_arr),
        bound_m=_frozen(0.5 * np.linalg.norm(b_arr - a_arr, axis=1) + r_arr),
    )


def joint_reach_m(robot: RobotModel, capsules: LinkCapsules) -> FloatArray:
    """For each joint, a bound on the distance from its axis to any point of the capsules it moves, in [m].

    Joint j's own capsules are fixed in its frame: their exact distance to its
    axis. A capsule of link k > j is within ``|a|`` (its segment end's distance
    to joint k's origin) plus its radius of joint k's origin, joint m's origin
    is a fixed distance from joint m-1's (a serial chain), and joint j+1's
    origin a fixed distance from joint j's axis; by the triangle inequality the
    bound holds in every configuration, and ``sum_j |qd_j| reach_j`` bounds the
    speed of every point of the arm. # (n,)
    """
    model, data = robot.model, robot.model.createData()
    n = model.nv
    pin.computeJointJacobians(model, data, pin.neutral(model))
    # Joint j's axis in its own frame (Pinocchio joint j + 1): the angular part of its Jacobian column.
    axes = [data.oMi[j + 1].rotation.T.dot(data.J[3:, j]) for j in range(n)]
    hops = [float(np.linalg.norm(model.jointPlacements[j + 1].translation)) for j in range(n)]

    def to_axis(j: int, point: FloatArray) -> float:
        return float(np.linalg.norm(np.cross(axes[j], point)))

    ends = np.maximum(
        np.linalg.norm(capsules.a_in_joint, axis=1), np.linalg.norm(capsules.b_in_joint, axis=1)
    )
    reach = np.zeros(n)
    for i, k in enumerate(capsules.joint.tolist()):
        radius = float(capsules.radius_m[i])
        for j in range(k + 1):
            if j == k:
                bound = max(to_axis(j, capsules.a_in_joint[i]), to_axis(j, capsules.b_in_joint[i])) + radius
            else:
                next_origin = to_axis(j, model.jointPlacements[j + 2].translation)
                bound = next_origin + sum(hops[j + 2 : k + 1]) + float(ends[i]) + radius
            reach[j] = max(reach[j], bound)
    return _frozen(reach)
