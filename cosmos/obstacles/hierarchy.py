"""The world body's bounding-volume hierarchy, rebuilt when obstacles come and go.

MuJoCo collides the world's geoms with an arm's body by walking two trees of
axis-aligned boxes (``mj_collideTree`` in ``engine_collision_driver.c``): a pair
of nodes whose boxes are apart is dropped with everything below it; a pair of
leaves goes on to the bounding-sphere test, the oriented-box test and, if both
pass, the narrow phase. The compiler builds the world's tree once, from where
the geoms are then: the parked obstacle slots (far below the floor) fill half
of it, and the rest share subtrees with the fixtures. Refitting boxes as slots
move keeps that shape, so an obstacle's box and the parked slots' grow into one
node that reaches from 50 m below the floor to the workcell, and every link
walks down it every step (with 10 obstacles of the bench: 143 node tests a
step instead of 7).

:func:`layout` rebuilds the tree for the geoms where they are now: the
workcell's own geoms and the parked slots in one subtree (below the table's top,
so a link above it leaves it in one test), planes and moving obstacles in
subtrees of their own (:data:`NESTING`), and the obstacles split by the
surface-area heuristic, which keeps big boxes out of small ones' subtrees where
the compiler's median split mixes them (the floor's 4 m box held every obstacle
it shared a node with). Among the bench's 10 obstacles: 70 node tests a step.
A tree of the same leaves has the same number of nodes, so it fits in the
world's range of the model's ``bvh_*`` arrays. Whatever its shape, a node's box
holds its leaves' boxes, so every pair of leaves that could touch is still
reached and tested exactly as before: the contacts are the same, and MuJoCo
sorts each body pair's contacts by geom, so their order is too.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import mujoco
import numpy as np

UNBOUNDED_HALF_M = 1e9
"""A leaf whose box has a half-size of at least this [m] is unbounded (a plane): a group of its own."""

QUERY_REACH_M = 0.05
"""What a tree walk tests against the world's boxes (a link, the tool) reaches this far [m]."""


@dataclass(frozen=True)
class Tree:
    """A binary tree of boxes in MuJoCo's layout (node 0 the root, each node before its children).

    Attributes:
        child: Per node, its two children (-1 for none), ``(nodes, 2)``.
        leaf: Per node, the index of its leaf among the tree's leaves, or -1, ``(nodes,)``.
        box: Per node, centre and half-sizes, ``(nodes, 6)``.
        depth: Per node, its depth (the root's is 0), ``(nodes,)``.
    """

    child: np.ndarray
    leaf: np.ndarray
    box: np.ndarray
    depth: np.ndarray


def union(boxes: np.ndarray) -> np.ndarray:
    """The box (centre, half-sizes) holding every box of ``boxes`` ``(k, 6)``. # (6,)."""
    low = np.min(boxes[:, :3] - boxes[:, 3:], axis=0)
    high = np.max(boxes[:, :3] + boxes[:, 3:], axis=0)
    return np.concatenate(((low + high) / 2.0, (high - low) / 2.0))


class Group(IntEnum):
    """Leaves of the world's tree kept apart, each group in a subtree of its own."""

    OBSTACLE = 0  # a placed obstacle that does not move
    MOVING = 1  # a MOVING obstacle: its box is refitted as it moves
    UNBOUNDED = 2  # a plane (found by its box, whatever it was labelled)
    FIXTURE = 3  # a geom of the compiled workcell (floor, table, fixtures)
    PARKED = 4  # a free obstacle slot, far below the floor


Nest = Group | tuple["Nest", "Nest"]

NESTING: Nest = (Group.OBSTACLE, (Group.MOVING, (Group.UNBOUNDED, (Group.FIXTURE, Group.PARKED))))
"""How the groups hang below the root. Every body of the arm walks the tree from its root every
step, testing both children of each node whose box it meets: the still obstacles' subtree hangs
right below the root, so a link reaches their surface-area tree in one test; the rest (a moving
obstacle, the planes, whose box is unbounded and so is met by every link, the fixtures and the
parked slots) in a chain beside it, where a link above the table leaves the fixtures' and the
parked slots' subtree (below the table's top and the floor) in one test. The obstacles are not
mixed with the floor, whose 4 m box would hold them all. Among the bench's 50 obstacles, 99 node
and 16 leaf tests a step, where obstacles and moving ones first joined the planes and then the
rest took 114 and 23 (:mod:`cosmos.bench.obstacles`)."""


def layout(boxes: np.ndarray, groups: np.ndarray, compiled: bool = True) -> Tree:
    """A tree over leaves with these ``boxes`` ``(n, 6)`` in these :class:`Group` ``groups`` ``(n,)``.

    The groups hang below the root as :data:`NESTING` says (an empty group is left
    out); inside a group, the leaves are split as MuJoCo's compiler splits them, but
    by the surface-area heuristic (:func:`best_split`): each group in one compiled call
    (:func:`cosmos.obstacles.kernels.split.split_into`, the same tree), or, with
    ``compiled=False``, node by node in NumPy.
    """
    count = len(boxes)
    unbounded = np.any(boxes[:, 3:] >= UNBOUNDED_HALF_M, axis=1)
    labels = np.where(unbounded, int(Group.UNBOUNDED), groups)
    child = np.full((2 * count - 1, 2), -1, dtype=np.int32)
    leaf = np.full(2 * count - 1, -1, dtype=np.int32)
    box = np.zeros((2 * count - 1, 6))
    depth = np.zeros(2 * count - 1, dtype=np.int32)
    state = {"next": 0}

    def new_node(members: np.ndarray, level: int) -> int:
        index = state["next"]
        state["next"] += 1
        box[index] = union(boxes[members])
        depth[index] = level
        return index

    def split(members: np.ndarray, level: int) -> int:
        if compiled:
            from cosmos.obstacles.kernels.split import split_into

            index = state["next"]
            state["next"] = split_into(
                boxes, members.astype(np.int64), QUERY_REACH_M, index, level, child, leaf, box, depth
            )
            return index
        index = new_node(members, level)
        if len(members) == 1:
            leaf[index] = members[0]
            return index
        order = best_split(boxes[members])
        half = order[1]
        ordered = members[order[0]]
        child[index, 0] = split(ordered[:half], level + 1)
        child[index, 1] = split(ordered[half:], level + 1)
        return index

    members: dict[Nest, np.ndarray] = {}  # each group's and nest's leaves, listed once

    def members_of(nest: Nest) -> np.ndarray:
        if nest not in members:
            members[nest] = (
                np.flatnonzero(labels == nest)
                if isinstance(nest, Group)
                else np.concatenate([members_of(part) for part in nest])
            )
        return members[nest]

    def join(nest: Nest, level: int) -> int:
        if isinstance(nest, Group):
            return split(members_of(nest), level)
        parts = [part for part in nest if len(members_of(part))]
        if len(parts) == 1:
            return join(parts[0], level)
        index = new_node(members_of(nest), level)
        child[index, 0] = join(parts[0], level + 1)
        child[index, 1] = join(parts[1], level + 1)
        return index

    join(NESTING, 0)
    return Tree(child=child, leaf=leaf, box=box, depth=depth)


def best_split(boxes: np.ndarray, reach_m: float = QUERY_REACH_M) -> tuple[np.ndarray, int]:
    """Where to split leaves with these ``boxes`` ``(k, 6)``: their order and where the second part starts.

    The surface-area heuristic: along each axis the leaves are sorted by their
    centres and every cut is scored by the children's areas (each box grown by
    ``reach_m``, the size of what is tested against it) times their leaf counts;
    the cheapest cut wins. A tree walk reaches a node about as often as a query
    overlaps its box, so this keeps big boxes (the floor, a wall) out of the
    small ones' subtrees, where a median cut puts them.
    """
    count = len(boxes)
    order = np.argsort(boxes[:, :3].T, axis=1, kind="stable")  # (3, k): the leaves sorted along each axis
    low = (boxes[:, :3] - boxes[:, 3:] - reach_m)[order]  # (3, k, 3)
    high = (boxes[:, :3] + boxes[:, 3:] + reach_m)[order]
    # per axis and cut after leaf j: areas of the boxes of leaves 0..j and j+1..k-1
    head = _areas(np.minimum.accumulate(low, axis=1), np.maximum.accumulate(high, axis=1))[:, :-1]
    tail = _areas(np.minimum.accumulate(low[:, ::-1], axis=1), np.maximum.accumulate(high[:, ::-1], axis=1))
    cuts = np.arange(1, count)
    costs = head * cuts + tail[:, ::-1][:, 1:] * (count - cuts)  # (3, k-1)
    axis, cut = np.unravel_index(int(np.argmin(costs)), costs.shape)
    return order[axis], int(cut) + 1


def _areas(low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Half the surface area of each box with corners ``low``, ``high`` ``(..., 3)``. # (...,)."""
    edge = high - low
    return edge[..., 0] * edge[..., 1] + edge[..., 1] * edge[..., 2] + edge[..., 2] * edge[..., 0]


def world_leaves(model: mujoco.MjModel) -> np.ndarray:
    """The geoms that are leaves of the world body's tree, in node order. # (n,)."""
    root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
    ids = model.bvh_nodeid[root : root + nodes]
    leaves = (model.bvh_child[root : root + nodes] < 0).all(axis=1) & (ids >= 0)
    return ids[leaves].astype(np.int64) + int(model.body_geomadr[0])


def install(model: mujoco.MjModel, geoms: np.ndarray, tree: Tree) -> None:
    """Write ``tree`` over leaves ``geoms`` (``tree.leaf`` indexes them) into the world body's nodes.

    Raises:
        ValueError: If the tree's size is not the world's.
    """
    root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
    if len(tree.child) != nodes:
        raise ValueError(f"a tree of {len(tree.child)} nodes for the world's {nodes}")
    first = int(model.body_geomadr[0])
    model.bvh_child[root : root + nodes] = tree.child
    model.bvh_nodeid[root : root + nodes] = np.where(tree.leaf >= 0, geoms[tree.leaf] - first, -1)
    model.bvh_aabb[root : root + nodes] = tree.box
    model.bvh_depth[root : root + nodes] = tree.depth
