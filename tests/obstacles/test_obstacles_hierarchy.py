"""The world's rebuilt bounding-volume hierarchy: the contacts are MuJoCo's own, found without it."""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.bench.obstacles import crowded_scene
from cosmos.obstacles import ObstacleScene, obstacle_scene_xml
from cosmos.obstacles.hierarchy import Group, layout, union
from cosmos.obstacles.obstacle import Obstacle, box, sphere
from cosmos.plan import ObstacleShape
from cosmos.plant import Plant


def _contacts(model: mujoco.MjModel, data: mujoco.MjData) -> list[tuple[object, ...]]:
    """Every contact MuJoCo reports for the state in ``data``, in MuJoCo's order."""
    mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    return [
        (int(c.geom1), int(c.geom2), float(c.dist), tuple(c.pos.tolist()), tuple(c.frame.tolist()))
        for c in data.contact[: data.ncon]
    ]


def _crowded_plant(rebuild: bool) -> Plant:
    """The workcell with the bench's fifty obstacles and one on the hole; the tree rebuilt or refitted."""
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    for obstacle in crowded_scene(50):
        scene.add(obstacle)
    scene.add(sphere("on_the_hole", (0.60, 0.15, 0.27), 0.02))
    if rebuild:
        scene.update(plant.time_s)  # the first update rebuilds the hierarchy
    return plant


def test_contacts_through_the_rebuilt_hierarchy_are_mujocos_own() -> None:
    """Two independent contact lists for the arm in random poses among the bench's fifty obstacles (a
    plane and a moving one among them) and the fixtures: (1) MuJoCo with its midphase disabled, where
    every pair of geoms meets the bitmask and sphere tests and the narrow phase with no tree at all:
    the rebuilt tree must find the same contacts (geoms, depth, point, frame); (2) the tree MuJoCo
    compiled, only refitted as obstacles were placed: the rebuilt one must give the same list in the
    same order, bit for bit (MuJoCo sorts a body pair's contacts by geom, whatever the tree's shape).
    Catches a rebuilt node whose box misses a leaf, a leaf given another geom's id, or a tree written
    over the wrong nodes: each drops or invents contacts."""
    rebuilt, refitted = _crowded_plant(rebuild=True), _crowded_plant(rebuild=False)
    model = rebuilt.model
    assert not np.array_equal(model.bvh_child, refitted.model.bvh_child)  # the shapes do differ
    midphase = int(mujoco.mjtDisableBit.mjDSBL_MIDPHASE)
    low, high = model.jnt_range[:6].T
    rng = np.random.default_rng(7)
    touching = 0
    for _ in range(300):
        q = rng.uniform(low, high)
        rebuilt.data.qpos[:6] = refitted.data.qpos[:6] = q
        through_tree = _contacts(model, rebuilt.data)
        assert through_tree == _contacts(refitted.model, refitted.data)
        model.opt.disableflags |= midphase
        without = _contacts(model, rebuilt.data)
        model.opt.disableflags &= ~midphase
        assert sorted(through_tree) == sorted(without)
        touching += bool(without)
    assert touching > 100  # the poses do touch things: the comparison is not of empty lists


def test_every_node_holds_its_leaves_and_each_leaf_is_once_in_the_tree() -> None:
    """A node's box must hold every box below it (else MuJoCo skips a pair that touches), and a tree
    of n leaves must use each leaf once in 2n - 1 nodes (the world's node count). Catches an
    off-by-one in the split, a group dropped when joined, or a box computed from the wrong members."""
    rng = np.random.default_rng(3)
    boxes = np.c_[rng.uniform(-1.0, 1.0, (40, 3)), rng.uniform(0.001, 0.3, (40, 3))]
    boxes[5, 3:] = (1e10, 1e10, 5e9)  # a plane
    groups = np.full(40, Group.OBSTACLE)
    groups[30:] = Group.PARKED
    groups[20:25] = Group.FIXTURE
    groups[[3, 17]] = Group.MOVING
    tree = layout(boxes, groups)
    assert len(tree.child) == 2 * 40 - 1
    assert sorted(tree.leaf[tree.leaf >= 0].tolist()) == list(range(40))

    def below(node: int) -> list[int]:
        if tree.leaf[node] >= 0:
            return [int(tree.leaf[node])]
        return [leaf for child in tree.child[node] if child >= 0 for leaf in below(int(child))]

    for node in range(len(tree.child)):
        leaves = below(node)
        np.testing.assert_array_equal(tree.box[node], union(boxes[leaves]))
        if node > 0:
            assert tree.depth[node] >= 1
    # the groups stay apart: the still obstacles hang right below the root (one test reaches them),
    # and the fixtures and the parked slots share a subtree with nothing else
    root_children = [below(int(c)) for c in tree.child[0]]
    still = [i for i in range(30) if i not in (3, 5, 17, *range(20, 25))]  # not moving, a plane, a fixture
    assert sorted(root_children[0]) == still
    subtrees = [sorted(below(node)) for node in range(len(tree.child))]
    assert [*range(20, 25), *range(30, 40)] in subtrees


def test_a_slot_keeps_the_worlds_axes_only_when_its_obstacle_is_not_turned() -> None:
    """An unturned obstacle's geom is marked as having the world's axes, so MuJoCo copies them instead
    of composing quaternions: its pose must be bit for bit the one MuJoCo composes (sameframe NONE),
    and a turned one must keep MuJoCo's composition. Catches a turned obstacle marked unturned (it
    would collide as if not turned) and a removed one left turned or unmarked."""
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    model, data = plant.model, plant.data
    turned = Obstacle(
        "turned",
        ObstacleShape.BOX,
        np.array((0.5, 0.3, 0.6)),
        np.array(((0.0, -1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0))),
        np.array((0.05, 0.2, 0.01)),
        np.zeros(3),
    )
    for obstacle in (
        sphere("ball", (0.3, -0.2, 0.9), 0.05),
        box("crate", (0.7, 0.4, 0.5), (0.1, 0.1, 0.1)),
        turned,
    ):
        scene.add(obstacle)
    slots = [model.geom(f"obstacle_slot{i}").id for i in range(3)]
    none = int(mujoco.mjtSameFrame.mjSAMEFRAME_NONE)
    assert [int(model.geom_sameframe[g]) for g in slots] == [
        int(mujoco.mjtSameFrame.mjSAMEFRAME_BODYROT)
    ] * 2 + [none]
    mujoco.mj_kinematics(model, data)
    marked = data.geom_xpos[slots].copy(), data.geom_xmat[slots].copy()
    model.geom_sameframe[slots] = none
    mujoco.mj_kinematics(model, data)
    np.testing.assert_array_equal(marked[0], data.geom_xpos[slots])
    np.testing.assert_array_equal(marked[1], data.geom_xmat[slots])
    assert not np.allclose(data.geom_xmat[slots[2]].reshape(3, 3), np.eye(3))  # the turned one is turned
    scene.remove("turned")
    assert int(model.geom_sameframe[slots[2]]) == int(mujoco.mjtSameFrame.mjSAMEFRAME_BODYROT)
    np.testing.assert_array_equal(model.geom_quat[slots[2]], (1.0, 0.0, 0.0, 0.0))


def test_the_compiled_split_builds_numpys_tree() -> None:
    """Each group is split in one compiled call. Catches a tree that differs from the node-by-node
    NumPy split in any node's children, leaf, box or depth (another tree changes the order MuJoCo
    tests pairs in): ties among the centres (the stable sort), an unbounded box, groups of one,
    and the cut chosen where two cost the same (the first, as NumPy's argmin takes it)."""
    rng = np.random.default_rng(5)
    for trial in range(120):
        count = int(rng.integers(1, 50))
        boxes = np.concatenate((rng.normal(0.0, 1.0, (count, 3)), rng.uniform(0.01, 0.5, (count, 3))), axis=1)
        if trial % 3 == 0:
            boxes[:, :3] = np.round(boxes[:, :3], 1)  # ties
            boxes[:, 3:] = 0.1  # equal sizes: equal costs
        if trial % 7 == 0:
            boxes[0, 3:] = 1e10  # a plane
        groups = rng.integers(0, len(Group), count)
        numpy, compiled = layout(boxes, groups, compiled=False), layout(boxes, groups)
        for field in ("child", "leaf", "box", "depth"):
            np.testing.assert_array_equal(getattr(compiled, field), getattr(numpy, field), err_msg=field)
