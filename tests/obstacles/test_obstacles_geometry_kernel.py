"""The proximity model's compiled geometry against Pinocchio, brute-force firas and finite differences."""

from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin
import pytest

from cosmos.bench.obstacles import bench_scene
from cosmos.obstacles import arm_capsules
from cosmos.obstacles.capsules import LinkCapsules, joint_reach_m
from cosmos.obstacles.field import FieldParameters, chain_table, obstacle_table
from cosmos.obstacles.geometry import ProximityModel, capsule_table
from cosmos.obstacles.kernels import distance as dk
from cosmos.obstacles.kernels import field as fk
from cosmos.obstacles.kernels import geometry as gk
from cosmos.obstacles.obstacle import Obstacle, box, sphere
from cosmos.obstacles.proximity import capsule_proximity, signed_distances
from cosmos.workcell import HOME_Q
from tests.obstacles.obstacle_scenes import robot


@functools.cache
def _capsules() -> LinkCapsules:
    return arm_capsules(robot())


@functools.cache
def _chain() -> np.ndarray:
    return chain_table(robot(), joint_reach_m(robot(), _capsules()))


def _ends(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every capsule's segment ends, world, placed by Pinocchio. # (n, 3) each"""
    model, data = robot().model, robot().model.createData()
    pin.forwardKinematics(model, data, q)
    caps = _capsules()
    joints = [data.oMi[int(k) + 1] for k in caps.joint]
    a = np.array([m.act(p) for m, p in zip(joints, caps.a_in_joint, strict=True)])
    b = np.array([m.act(p) for m, p in zip(joints, caps.b_in_joint, strict=True)])
    return a, b


def test_capsule_geoms_are_placed_where_pinocchio_puts_the_segments() -> None:
    """A capsule geom's centre is its segment's midpoint; its z axis times the half length, half the segment.

    Catches a capsule placed on the wrong joint, the in-joint rotation applied
    on the wrong side, or a moving obstacle not moved (or a static one moved).
    """
    caps, table = capsule_table(_capsules()), capsule_table(_capsules())
    obstacles = bench_scene()
    frames = np.zeros((6, fk.FRAMES))
    n = len(caps)
    xpos, xmat = np.zeros((n + len(obstacles), 3)), np.zeros((n + len(obstacles), 9))
    rng = np.random.default_rng(8)
    for _ in range(5):
        q = rng.uniform(robot().q_lower_rad, robot().q_upper_rad)
        t_s = float(rng.uniform(0.0, 5.0))
        fk.chain_kinematics_into(frames, _chain(), q, np.zeros(6))
        gk.place_geoms_into(xpos, xmat, frames, table, obstacle_table(obstacles, FieldParameters()), t_s)
        a, b = _ends(q)
        np.testing.assert_allclose(xpos[:n], 0.5 * (a + b), atol=1e-12)
        half_axes = xmat[:n, [2, 5, 8]] * table[:, dk.CAPSULE_HALF, None]
        np.testing.assert_allclose(half_axes, 0.5 * (b - a), atol=1e-12)
        for j, obstacle in enumerate(obstacles):
            if obstacle.moving:
                np.testing.assert_allclose(xpos[n + j], obstacle.position_at(t_s), atol=1e-12)
            else:
                assert not np.any(xpos[n + j])  # left as the caller wrote it


def _brute_force(q: np.ndarray, t_s: float, obstacles: tuple[Obstacle, ...], rho_0: float) -> dict:
    """(link, obstacle) -> the least firas distance over the link's capsules, where below rho_0."""
    caps = _capsules()
    a, b = _ends(q)
    out: dict[tuple[int, int], float] = {}
    for j, obstacle in enumerate(obstacles):
        center = obstacle.position_at(t_s)
        for i in range(len(caps)):
            near = capsule_proximity(a[i], b[i], float(caps.radius_m[i]), obstacle, center)
            key = (int(caps.joint[i]), j)
            if near.distance < rho_0 and near.distance < out.get(key, np.inf):
                out[key] = near.distance
    return out


@pytest.mark.parametrize("seed", [10, 11, 12])
def test_measured_approaches_are_the_brute_force_ones_along_a_motion(seed: int) -> None:
    """Every measurement along a motion finds each (link, obstacle) within rho_0, at its firas distance.

    The arm moves among the bench's ten obstacles (one moving), measured every
    16 ms as the field does, so the candidate list is reused, pairs are skipped
    and the list is rebuilt. Catches a candidate dropped by too tight a lower
    bound, a pair skipped that may have come within rho_0, a stale answer kept
    for a queried pair, the wrong capsule kept for a link, and a point or normal
    that does not match the distance.
    """
    obstacles = bench_scene()
    parameters = FieldParameters()
    model = ProximityModel(_capsules(), obstacles, obstacle_table(obstacles, parameters))
    frames = np.zeros((6, fk.FRAMES))
    rng = np.random.default_rng(seed)
    q, dt_s = HOME_Q.copy(), 0.016
    qd = rng.normal(scale=0.15, size=6)
    compared = 0
    for step in range(60):
        t_s = step * dt_s
        if step % 15 == 0:
            qd = rng.normal(scale=0.15, size=6)
        speed = fk.chain_kinematics_into(frames, _chain(), q, qd) + 0.05  # the moving ball's speed
        count = model.measure(frames, t_s, speed)
        expected = _brute_force(q, t_s, obstacles, parameters.influence_m)
        found = {}
        for row in model.approaches[:count]:
            k, j, distance = (
                int(row[fk.APPROACH_LINK]),
                int(row[fk.APPROACH_OBSTACLE]),
                row[fk.APPROACH_DISTANCE],
            )
            found[(k, j)] = distance
            point, normal = row[fk.APPROACH_POINT : fk.APPROACH_POINT + 3], row[fk.APPROACH_NORMAL :]
            assert np.linalg.norm(normal) == pytest.approx(1.0, abs=1e-9)
            obstacle = obstacles[j]
            center = obstacle.position_at(t_s)
            assert signed_distances(point[None], obstacle, center)[0] == pytest.approx(distance, abs=2e-4)
        borderline = {key for key, d in expected.items() if d > parameters.influence_m - 1e-4}
        assert set(found) - borderline - set(expected) == set()
        assert set(expected) - borderline - set(found) == set()
        for key in set(found) & set(expected):
            assert found[key] == pytest.approx(expected[key], abs=2e-4)
            compared += 1
        q = q + dt_s * qd
    assert compared > 60  # the motion passes near obstacles


def test_estimate_moves_each_held_point_with_its_link_to_first_order() -> None:
    """The estimate is ``p + v_p dt`` (v_p the link's velocity at p, by finite differences), distance along n.

    Catches the twist of the wrong link, ``w x p`` for ``p x w``, the
    obstacle's velocity left out, or a pair kept beyond rho_0.
    """
    obstacles = bench_scene()
    model = ProximityModel(_capsules(), obstacles, obstacle_table(obstacles, FieldParameters()))
    frames = np.zeros((6, fk.FRAMES))
    rng = np.random.default_rng(13)
    pmodel, pdata = robot().model, robot().model.createData()
    q0 = HOME_Q + np.array([0.0, 0.05, -0.05, 0.0, 0.1, 0.0])
    fk.chain_kinematics_into(frames, _chain(), q0, np.zeros(6))
    held = model.approaches[: model.measure(frames, 0.0, 0.0)].copy()
    assert len(held) >= 3
    for _ in range(5):
        qd, dt_s = rng.normal(size=6), 0.008
        q1 = q0 + rng.normal(scale=0.01, size=6)
        fk.chain_kinematics_into(frames, _chain(), q1, qd)
        count = model.estimate(frames, dt_s)  # the measurement was at t = 0
        expected = []
        for row in held:
            k, j = int(row[fk.APPROACH_LINK]), int(row[fk.APPROACH_OBSTACLE])
            point, normal = row[fk.APPROACH_POINT : fk.APPROACH_POINT + 3], row[fk.APPROACH_NORMAL :]
            other = point - row[fk.APPROACH_DISTANCE] * normal
            step, moved = 1e-6, []
            for sign in (1.0, -1.0):
                pin.forwardKinematics(pmodel, pdata, q1)
                local = pdata.oMi[k + 1].actInv(point)
                pin.forwardKinematics(pmodel, pdata, q1 + sign * step * qd)
                moved.append(pdata.oMi[k + 1].act(local))
            velocity = (moved[0] - moved[1]) / (2 * step)
            obstacle_velocity = obstacles[j].velocity_world_mps
            distance = normal.dot(point + velocity * dt_s - other - obstacle_velocity * dt_s)
            if distance < FieldParameters().influence_m:
                expected.append((k, j, distance, *(point + velocity * dt_s), *normal))
        np.testing.assert_allclose(model.approaches[:count], np.array(expected), atol=1e-8)


def test_a_ball_coming_at_the_still_arm_is_picked_up_as_soon_as_it_is_within_rho_0() -> None:
    """Between rebuilds of the candidate list, a pair closing in is queried again in time.

    The ball's speed is the whole travel bound (the arm is still), so it enters
    rho_0 between two rebuilds. Catches a skip test that ignores the travel
    since a pair's last query (the pair would be found only at the next rebuild).
    """
    ball = sphere("ball", (0.85, -0.15, 0.52), 0.05, velocity_mps=(-0.2, 0.0, 0.0))
    parameters = FieldParameters()
    model = ProximityModel(_capsules(), (ball,), obstacle_table((ball,), parameters))
    frames = np.zeros((6, fk.FRAMES))
    fk.chain_kinematics_into(frames, _chain(), HOME_Q, np.zeros(6))
    first = None
    for step in range(60):
        t_s = step * 0.016
        count = model.measure(frames, t_s, 0.2)
        expected = _brute_force(HOME_Q, t_s, (ball,), parameters.influence_m)
        found = {(int(r[0]), int(r[1])): r[fk.APPROACH_DISTANCE] for r in model.approaches[:count]}
        assert set(found) == set(expected)
        if found and first is None:
            first = step
    assert first is not None and 10 < first < 50  # it entered rho_0 during the run


def test_the_fused_estimate_evaluation_is_its_three_steps() -> None:
    """``estimated_torque_into`` equals kinematics, ``estimate_into`` and ``field_torque_into`` called apart.

    Catches the fused call passing the held count instead of the estimated one
    to the torques, or the kinematics left out (twists of the last call).
    """
    obstacles = bench_scene()
    parameters = FieldParameters()
    model = ProximityModel(_capsules(), obstacles, obstacle_table(obstacles, parameters))
    kernel_parameters = np.array((parameters.eta, parameters.damping_ns_per_m, parameters.force_cap_n, 1.0))
    frames, apart = np.zeros((6, fk.FRAMES)), np.zeros((6, fk.FRAMES))
    fk.chain_kinematics_into(frames, _chain(), HOME_Q, np.zeros(6))
    held = model.measure(frames, 0.0, 0.0)
    assert held >= 3
    rng = np.random.default_rng(14)
    for _ in range(5):
        q, qd = HOME_Q + rng.normal(scale=0.03, size=6), rng.normal(size=6)
        torque, acting = np.zeros(6), np.zeros((len(obstacles), fk.ACTING))
        links, nearest = np.zeros(6), np.zeros(fk.NEAREST)
        speed = model.estimated_torque(
            torque, links, nearest, acting, _chain(), q, qd, frames, kernel_parameters, 0.008
        )
        expected_speed = fk.chain_kinematics_into(apart, _chain(), q, qd)
        count = model.estimate(apart, 0.008)
        expected, expected_acting = np.zeros(6), np.zeros((len(obstacles), fk.ACTING))
        expected_links, expected_nearest = np.zeros(6), np.zeros(fk.NEAREST)
        fk.field_torque_into(
            expected, expected_links, expected_nearest, expected_acting,
            model.approaches, count, apart, model.table, kernel_parameters,
        )  # fmt: skip
        assert speed == expected_speed
        np.testing.assert_array_equal(torque, expected)
        np.testing.assert_array_equal(acting, expected_acting)
        np.testing.assert_array_equal(links, expected_links)
        np.testing.assert_array_equal(nearest, expected_nearest)
        assert np.any(torque)


def test_a_link_inside_an_obstacle_gets_the_firas_signed_distance_and_normal() -> None:
    """Penetrating pairs (MuJoCo's depth is no signed distance) take firas' distance, point and normal.

    Catches the touching pairs left with MuJoCo's penetration depth and a zero
    normal (no force direction), or the fix-up applied to the wrong approach.
    """
    obstacles = (sphere("ball", (0.64, -0.15, 0.52), 0.05), box("crate", (0.5, -0.15, 0.6), (0.1, 0.1, 0.1)))
    model = ProximityModel(_capsules(), obstacles, obstacle_table(obstacles, FieldParameters()))
    frames = np.zeros((6, fk.FRAMES))
    fk.chain_kinematics_into(frames, _chain(), HOME_Q, np.zeros(6))
    count = model.measure(frames, 0.0, 0.0)
    expected = _brute_force(HOME_Q, 0.0, obstacles, FieldParameters().influence_m)
    assert min(expected.values()) < 0.0  # the scene does penetrate
    found = {(int(r[0]), int(r[1])): r for r in model.approaches[:count]}
    assert set(found) == set(expected)
    for key, distance in expected.items():
        row = found[key]
        assert row[fk.APPROACH_DISTANCE] == pytest.approx(distance, abs=2e-4)
        assert np.linalg.norm(row[fk.APPROACH_NORMAL :]) == pytest.approx(1.0, abs=1e-9)
