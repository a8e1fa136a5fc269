"""Obstacles as geoms of the simulated workcell: slots, bounds, poses, contacts, collision events."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from cosmos.errors import CosmosError
from cosmos.obstacles import ObstacleScene, collisions, obstacle_scene_xml
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.obstacles.scene import CAPACITY, DEFAULT_SLOTS, SWEEP_S, geom_size_and_bounds
from cosmos.plan import ObstacleShape
from cosmos.plant import Contact, Plant
from cosmos.workcell import HOME_Q

PLANE = Obstacle(
    "floor2",
    ObstacleShape.PLANE,
    np.array([0.0, 0.0, 0.1]),
    np.eye(3),
    np.array([np.inf, np.inf, 0.0]),
    np.zeros(3),
)


@pytest.mark.parametrize(
    "obstacle",
    [
        sphere("s", (0, 0, 0), 0.07),
        box("b", (0, 0, 0), (0.1, 0.2, 0.3)),
        cylinder("c", (0, 0, 0), 0.05, 0.4),
        PLANE,
    ],
    ids=["sphere", "box", "cylinder", "plane"],
)
def test_bounds_match_the_compiler(obstacle: Obstacle) -> None:
    """The bounding volumes set at run time are those MuJoCo compiles for that geom."""
    size, rbound, aabb = geom_size_and_bounds(obstacle)
    spec = mujoco.MjSpec()
    kinds = {
        ObstacleShape.SPHERE: mujoco.mjtGeom.mjGEOM_SPHERE,
        ObstacleShape.BOX: mujoco.mjtGeom.mjGEOM_BOX,
        ObstacleShape.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER,
        ObstacleShape.PLANE: mujoco.mjtGeom.mjGEOM_PLANE,
    }
    spec.worldbody.add_body(mocap=True).add_geom(type=kinds[obstacle.shape], size=size)
    model = spec.compile()
    assert model.geom_rbound[0] == pytest.approx(rbound)
    np.testing.assert_allclose(model.geom_aabb[0], aabb)
    np.testing.assert_allclose(model.bvh_aabb[model.body_bvhadr[1]], aabb)


def test_the_slotted_workcell_is_the_workcell() -> None:
    """Slots are geoms of the world, not bodies: a body costs every physics step (twelve parked mocap
    bodies made a tick 1.2-1.3x dearer with no obstacle), so the slotted workcell has no more bodies."""
    plain, slotted = Plant(), Plant(obstacle_scene_xml())
    assert DEFAULT_SLOTS == CAPACITY >= 64
    assert slotted.model.nbody == plain.model.nbody and slotted.model.nmocap == 0
    assert slotted.model.ngeom == plain.model.ngeom + CAPACITY
    assert slotted.model.nq == plain.model.nq and slotted.model.nu == plain.model.nu
    for _ in range(50):
        plain.step(np.zeros(6))
        slotted.step(np.zeros(6))
    np.testing.assert_allclose(slotted.read_encoders()[0], plain.read_encoders()[0], atol=1e-12)
    assert slotted.contacts() == [] or all(c.body1 != c.body2 for c in slotted.contacts())


def test_an_obstacle_is_a_body_the_arm_touches() -> None:
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    ball = sphere("ball", (0.596, -0.15, 0.50), 0.03)  # around the peg at home
    scene.add(ball)
    plant.step(np.zeros(6))
    hits = collisions(plant, scene.body_names())
    assert [(h.arm_body, h.other, h.is_obstacle) for h in hits] == [("tool", "ball", True)]
    assert scene.remove("ball") is ball
    plant.step(np.zeros(6))
    assert collisions(plant, scene.body_names()) == []


def test_a_box_slot_collides_as_a_box_and_moves_with_its_velocity() -> None:
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    # A thin plate 60 mm beside the peg, moving toward it at 0.5 m/s: no contact, then contact.
    plate = box("plate", (0.596 + 0.0096 + 0.06 + 0.005, -0.15, 0.52), (0.01, 0.3, 0.05), (-0.5, 0.0, 0.0))
    scene.add(plate)
    seen = []
    for _ in range(200):
        scene.update(plant.time_s)
        plant.step(np.zeros(6))
        seen.append(bool(collisions(plant, scene.body_names())))
    assert not any(seen[:100]) and any(seen[130:])
    geom = plant.model.geom("obstacle_slot0").id
    assert plant.data.geom_xpos[geom][0] == pytest.approx(
        plate.position_world[0] - 0.5 * (plant.time_s - plant.dt_s), abs=1e-9
    )


def test_restore_puts_moving_obstacles_where_they_are_at_a_time() -> None:
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    scene.add(cylinder("post", (0.4, 0.2, 0.5), 0.05, 0.4))
    scene.add(sphere("ball", (0.4, -0.2, 0.5), 0.05, velocity_mps=(0.0, 0.0, 0.1)))
    scene.update(1.0)
    plant.reset()
    scene.restore(0.5)
    mujoco.mj_kinematics(plant.model, plant.data)
    np.testing.assert_allclose(plant.data.geom_xpos[plant.model.geom("obstacle_slot0").id], (0.4, 0.2, 0.5))
    np.testing.assert_allclose(plant.data.geom_xpos[plant.model.geom("obstacle_slot1").id], (0.4, -0.2, 0.55))


def _world_box(plant: Plant, geom: int) -> tuple[np.ndarray, np.ndarray]:
    """The geom's axis-aligned box in the world from MuJoCo's own placement (geom_xpos, geom_xmat)."""
    model, data = plant.model, plant.data
    size = model.geom_size[geom]
    kind = model.geom_type[geom]
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        half = np.full(3, size[0])
    elif kind == mujoco.mjtGeom.mjGEOM_BOX:
        half = np.abs(data.geom_xmat[geom].reshape(3, 3)) @ size
    else:
        raise AssertionError("spheres and boxes only")
    return data.geom_xpos[geom] - half, data.geom_xpos[geom] + half


def test_the_world_hierarchy_holds_every_obstacle_as_it_moves() -> None:
    """MuJoCo's midphase only looks inside a node whose box overlaps the arm: a slot geom outside its
    leaf or an ancestor is never collided. Every placed or moving obstacle must lie inside the boxes
    of its leaf and of every node above it, at every tick (MuJoCo's own placement of the geom)."""
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    model = plant.model
    rotated = Obstacle(
        "tilted",
        ObstacleShape.BOX,
        np.array((0.5, 0.3, 0.6)),
        np.array(((0.0, -1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0))),
        np.array((0.05, 0.2, 0.01)),
        np.zeros(3),
    )
    scene.add(rotated)
    scene.add(sphere("fast", (0.2, -0.4, 0.5), 0.04, velocity_mps=(0.8, 0.5, -0.3)))
    scene.add(box("drift", (0.7, 0.0, 0.4), (0.03, 0.03, 0.1), (-0.1, 0.0, 0.0)))
    scene.remove("tilted")
    scene.add(rotated)
    root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
    for tick in range(int(3 * SWEEP_S / plant.dt_s)):
        scene.update(plant.time_s)  # the first one rebuilds the hierarchy: read its shape after it
        parent = {int(c): n for n in range(root, root + nodes) for c in model.bvh_child[n] if c >= 0}
        leaf = {
            int(model.bvh_nodeid[n]) + int(model.body_geomadr[0]): n
            for n in range(root, root + nodes)
            if model.bvh_child[n][0] < 0
        }
        mujoco.mj_kinematics(model, plant.data)
        for geom in (model.geom(f"obstacle_slot{i}").id for i in range(3)):
            low, high = _world_box(plant, geom)
            node = leaf[geom]
            while True:
                box_ = model.bvh_aabb[node]
                assert np.all(box_[:3] - box_[3:] <= low + 1e-9) and np.all(
                    high <= box_[:3] + box_[3:] + 1e-9
                ), tick
                if node not in parent:
                    break
                node = parent[node]
        plant.data.time += plant.dt_s


def _outside_an_ancestor(plant: Plant, geom: int) -> list[int]:
    """The nodes on the way from the geom's leaf to the root (read from MuJoCo's ``bvh_child``) whose
    box does not hold the geom where MuJoCo places it."""
    model = plant.model
    root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
    parent = {int(c): n for n in range(root, root + nodes) for c in model.bvh_child[n] if c >= 0}
    first = int(model.body_geomadr[0])
    leaves = [n for n in range(root, root + nodes) if model.bvh_child[n][0] < 0]
    node = next(n for n in leaves if model.bvh_nodeid[n] == geom - first)
    mujoco.mj_kinematics(model, plant.data)
    low, high = _world_box(plant, geom)
    outside = []
    while node >= 0:
        box_ = model.bvh_aabb[node]
        if not (np.all(box_[:3] - box_[3:] <= low + 1e-9) and np.all(high <= box_[:3] + box_[3:] + 1e-9)):
            outside.append(node)
        node = parent.get(node, -1)
    return outside


def _not_holding_their_children(plant: Plant) -> list[int]:
    """The world's nodes whose box does not hold both its children's (MuJoCo's ``bvh_child``)."""
    model = plant.model
    root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
    boxes, children = model.bvh_aabb[root : root + nodes], model.bvh_child[root : root + nodes]
    low, high = boxes[:, :3] - boxes[:, 3:], boxes[:, :3] + boxes[:, 3:]
    return [
        node
        for node in range(nodes)
        for child in children[node].tolist()
        if child >= 0
        and not (np.all(low[node] <= low[child] + 1e-12) and np.all(high[child] <= high[node] + 1e-12))
    ]


def test_obstacles_added_after_the_hierarchy_is_rebuilt_are_held_by_it() -> None:
    """The nodes above a slot's leaf are listed when the slot is first refitted after a rebuild (most
    slots stay parked): catches a list kept from the tree before the rebuild, or one listed from the
    wrong parents, which refits nodes that are not the leaf's ancestors and leaves an obstacle added
    after the rebuild outside its ancestors' boxes (MuJoCo's midphase never collides it), or a node
    refitted from the wrong child off the way up (the geoms below it are then outside it). The nodes
    are walked here from MuJoCo's own ``bvh_child``."""
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    for i in range(CAPACITY):  # every slot refitted in the compiled tree
        scene.add(sphere(f"s{i}", (0.01 * i, 0.0, 2.0), 0.01))
    for i in range(CAPACITY):
        scene.remove(f"s{i}")
    scene.add(sphere("first", (0.4, -0.3, 0.5), 0.05))
    scene.update(plant.time_s)  # the hierarchy rebuilt for the first
    scene.add(box("later", (0.6, 0.2, 0.3), (0.05, 0.3, 0.02), (0.0, -0.2, 0.0)))  # no update: refitted
    scene.add(sphere("far", (-0.5, 0.5, 1.2), 0.03))
    slot = [plant.model.geom(f"obstacle_slot{i}").id for i in range(3)]
    assert [_outside_an_ancestor(plant, geom) for geom in slot] == [[], [], []]
    scene.remove("first")
    plant.data.time += 0.3  # "later" moves on, refitted on its way
    scene.update(plant.time_s)  # rebuilt again: the freed slot's nodes are others
    scene.add(sphere("again", (0.3, 0.4, 0.6), 0.04))
    assert [_outside_an_ancestor(plant, geom) for geom in slot] == [[], [], []]
    assert _not_holding_their_children(plant) == []  # each refit's way up took the other children in


def test_scene_errors_name_the_fix() -> None:
    with pytest.raises(CosmosError, match="obstacle_scene_xml"):
        ObstacleScene(Plant())
    plant = Plant(obstacle_scene_xml())
    scene = ObstacleScene(plant)
    for i in range(scene.capacity):
        scene.add(sphere(f"b{i}", (2.0, 0.1 * i, 0.5), 0.01))
    with pytest.raises(CosmosError, match=f"at most {CAPACITY} obstacles"):
        scene.add(sphere("one_more", (2.0, 0.0, 0.5), 0.01))
    with pytest.raises(CosmosError, match="already"):
        scene.add(sphere("b0", (2.0, 0.0, 0.5), 0.01))
    with pytest.raises(CosmosError, match="no obstacle 'nope'"):
        scene.remove("nope")


class _Contacts:
    """A stand-in plant with given contacts (for the filter's logic)."""

    def __init__(self, pairs: list[tuple[str, str, float]]) -> None:
        # A slot's geom is named as its frame (its owner); other geoms are named after their bodies.
        def geom_body(name: str) -> tuple[str, str]:
            return (name, name) if name.startswith("obstacle_slot") else (f"{name}_geom", name)

        self._contacts = []
        for first, second, d in pairs:
            (g1, b1), (g2, b2) = geom_body(first), geom_body(second)
            self._contacts.append(Contact(g1, g2, b1, b2, d, np.zeros(3)))

    def contacts(self) -> list[Contact]:
        return self._contacts


def test_the_tool_on_a_fixture_is_intended_a_link_on_it_is_not() -> None:
    plant = _Contacts(
        [
            ("tool", "table", -0.001),  # the task's contact
            ("hole_fixture", "tool", -0.002),  # the task's contact, either order
            ("link3", "table", -0.003),
            ("world", "link2", -0.001),  # the floor
            ("tool", "world", -0.001),  # the tool on the floor: a fixture's kind of contact
            ("obstacle_slot4", "tool", -0.004),
            ("obstacle_slot4", "tool", -0.006),  # same pair: the deepest is kept
            ("obstacle_slot4", "table", -0.001),  # not the arm
        ]
    )
    found = collisions(plant, {"obstacle_slot4": "ball"})  # type: ignore[arg-type]
    assert [(c.arm_body, c.other, c.is_obstacle) for c in found] == [
        ("link3", "table", False),
        ("link2", "world", False),
        ("tool", "ball", True),
    ]
    assert found[2].depth_m == pytest.approx(0.006)


def test_home_pose_has_no_collision() -> None:
    plant = Plant(obstacle_scene_xml())
    plant.reset(HOME_Q)
    plant.step(np.zeros(6))
    assert collisions(plant, {}) == []


def test_a_compiled_program_builds_the_scene_and_the_field() -> None:
    from cosmos.lang import compile_program
    from cosmos.obstacles import ObstacleField, from_step
    from tests.obstacles.obstacle_scenes import robot

    program = compile_program(
        "OBSTACLE post CYLINDER AT (0.4, -0.2, 0.3) RADIUS 40 mm HEIGHT 0.6 m\n"
        "OBSTACLE ball SPHERE AT (0.6, -0.15, 0.44) RADIUS 30 mm MOVING (0, -50 mm/s, 0) INFLUENCE 50 mm\n"
        "OBSTACLE floor2 PLANE AT (0, 0, 0.5) NORMAL (0, 0, 1)\n"
        "OBSTACLE REMOVE post\n"
    )
    plant = Plant(obstacle_scene_xml())
    scene, field = ObstacleScene(plant), ObstacleField(robot())
    for step in program.steps:
        if hasattr(step, "shape"):
            obstacle = from_step(step, plant.time_s)
            scene.add(obstacle)
            field.add(obstacle)
        else:
            scene.remove(step.name)
            field.remove(step.name)
    assert [o.name for o in field.obstacles] == ["ball", "floor2"]
    plant.step(np.zeros(6))
    # The tool hangs below the plane z = 0.5 (inside its solid side) and the ball touches the peg's tip.
    touched = {(c.arm_body, c.other) for c in collisions(plant, scene.body_names())}
    assert ("tool", "floor2") in touched and ("tool", "ball") in touched
    field.torque(HOME_Q, np.zeros(6), 0.0)
    assert {i.obstacle for i in field.influences} == {"ball", "floor2"}


def test_a_slot_is_owned_by_its_own_name_not_by_the_world() -> None:
    """Slots are world geoms; if the plant named their owner ``world``, a contact with an obstacle
    would read as the floor or a fixture (the tool's intended contact) to everything that judges
    contacts by owner. Each slot's owner is the slot, and an obstacle contact names it."""
    plant = Plant(obstacle_scene_xml())
    model = plant.model
    for i in range(CAPACITY):
        geom = model.geom(f"obstacle_slot{i}").id
        assert plant.geom_owners[geom] == f"obstacle_slot{i}"
    scene = ObstacleScene(plant)
    scene.add(sphere("ball", (0.596, -0.15, 0.50), 0.03))  # around the peg at home
    plant.step(np.zeros(6))
    owners = {(c.body1, c.body2) for c in plant.contacts()}
    assert ("tool", "obstacle_slot0") in owners or ("obstacle_slot0", "tool") in owners


@pytest.mark.parametrize(
    "obstacle",
    [sphere("s", (0, 0, 0), 0.07, (0.0, 0.0, 0.0)), sphere("m", (0, 0, 0), 0.07, (0.0, -1e-9, 0.0))],
    ids=["still", "moving"],
)
def test_whether_an_obstacle_moves_is_worked_out_once_from_a_velocity_that_cannot_change(
    obstacle: Obstacle,
) -> None:
    """``moving`` is kept after its first answer (the scene's drawing asks it every 40 ms): catches
    a velocity that can be written after it (a kept answer would go stale) or an answer that is not
    whether a component of the velocity is non-zero."""
    assert obstacle.moving == any(v != 0.0 for v in obstacle.velocity_world_mps.tolist())
    with pytest.raises(ValueError, match="read-only"):
        obstacle.velocity_world_mps[0] = 1.0
    assert obstacle.moving == (obstacle.name == "m")
