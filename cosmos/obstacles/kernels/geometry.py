"""The proximity model's arithmetic around MuJoCo's distance queries, compiled (numba).

:class:`cosmos.obstacles.geometry.ProximityModel` places the capsules and the
moving obstacles in its private MuJoCo model (here), picks the candidate pairs
worth a distance query (:mod:`cosmos.obstacles.kernels.candidates`), answers
those with a sphere or a plane in closed form
(:mod:`cosmos.obstacles.kernels.distance`) and asks ``mj_geomDistance`` for the
others (from Python: one call a pair), and keeps, per (link, obstacle) within
rho_0, the link's closest capsule and its point and normal (here). Between
measurements it carries those points forward to first order with the links'
twists, as the seed's servo level estimates the end effector between
evaluations of the model (here). ``tests/obstacles/test_obstacles_geometry_kernel.py``
checks it against Pinocchio's kinematics, brute-force distances
(:mod:`cosmos.osc.firas`) and first-order motion by finite differences.

Layouts of the packed arrays are below; the frames, obstacles and approaches are
those of :mod:`cosmos.obstacles.kernels.field`, the candidates and lists those of
:mod:`cosmos.obstacles.kernels.candidates`.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.obstacles.kernels import distance as dk
from cosmos.obstacles.kernels.candidates import (
    CANDIDATE_ANALYTIC,
    CANDIDATE_CAPSULE,
    CANDIDATE_LAST_M,
    CANDIDATE_OBSTACLE,
    CANDIDATE_TRAVEL_M,
    LIST_QUEUE,
    select_queries,
)
from cosmos.obstacles.kernels.field import (
    APPROACH_DISTANCE,
    APPROACH_LINK,
    APPROACH_NORMAL,
    APPROACH_OBSTACLE,
    APPROACH_POINT,
    FRAME_ORIGIN,
    FRAME_ROTATION,
    FRAME_TWIST,
    OBSTACLE_ADDED_S,
    OBSTACLE_CENTER,
    OBSTACLE_RHO_0,
    OBSTACLE_VELOCITY,
    chain_kinematics_into,
    field_torque_into,
)

FloatArray = np.ndarray

# ``held`` (m, HELD): per approach measured, link, obstacle, capsule, the link's point and the
# obstacle's point [m], the unit normal pointing away from the obstacle, world, and the time [s].
HELD_LINK, HELD_OBSTACLE, HELD_CAPSULE, HELD_POINT, HELD_OTHER, HELD_NORMAL, HELD_S = 0, 1, 2, 3, 6, 9, 12
HELD = 13

NORMAL_FROM_POINTS_M = 1e-4
"""Below this distance MuJoCo's two points do not define the normal: firas gives it (in Python)."""


@kernel
def place_geoms_into(
    geom_xpos: FloatArray,
    geom_xmat: FloatArray,
    frames: FloatArray,
    capsules: FloatArray,
    obstacles: FloatArray,
    t_s: float,
) -> None:
    """World poses of the capsule geoms (0..n-1) and of the moving obstacles' geoms (n + j) at ``t_s``.

    A capsule's geom is ``R_k (R_in_joint, mid_in_joint) + p_k`` of its joint
    k; a moving obstacle's centre is ``c + v (t - t_added)``. Static obstacles
    keep the pose written when the model was built.
    """
    n = capsules.shape[0]
    for i in range(n):
        c = capsules[i]
        f = frames[int(c[dk.CAPSULE_JOINT])]
        for row in range(3):
            r0 = f[FRAME_ROTATION + 3 * row]
            r1 = f[FRAME_ROTATION + 3 * row + 1]
            r2 = f[FRAME_ROTATION + 3 * row + 2]
            geom_xpos[i, row] = (
                r0 * c[dk.CAPSULE_MID] + r1 * c[dk.CAPSULE_MID + 1] + r2 * c[dk.CAPSULE_MID + 2]
            ) + f[FRAME_ORIGIN + row]
            for col in range(3):
                geom_xmat[i, 3 * row + col] = (
                    r0 * c[dk.CAPSULE_ROTATION + col]
                    + r1 * c[dk.CAPSULE_ROTATION + 3 + col]
                    + r2 * c[dk.CAPSULE_ROTATION + 6 + col]
                )
    for j in range(obstacles.shape[0]):
        o = obstacles[j]
        vx, vy, vz = o[OBSTACLE_VELOCITY], o[OBSTACLE_VELOCITY + 1], o[OBSTACLE_VELOCITY + 2]
        if vx == 0.0 and vy == 0.0 and vz == 0.0:
            continue
        dt = t_s - o[OBSTACLE_ADDED_S]
        geom_xpos[n + j, 0] = o[OBSTACLE_CENTER] + dt * vx
        geom_xpos[n + j, 1] = o[OBSTACLE_CENTER + 1] + dt * vy
        geom_xpos[n + j, 2] = o[OBSTACLE_CENTER + 2] + dt * vz


@kernel
def place_and_select(
    lists: np.ndarray,
    candidates: FloatArray,
    count: int,
    geom_xpos: FloatArray,
    geom_xmat: FloatArray,
    frames: FloatArray,
    capsules: FloatArray,
    shapes: FloatArray,
    obstacles: FloatArray,
    t_s: float,
    travel_m: float,
    margin_m: float,
) -> tuple[int, int, int]:
    """:func:`place_geoms_into` then :func:`~cosmos.obstacles.kernels.candidates.select_queries`, one call."""
    place_geoms_into(geom_xpos, geom_xmat, frames, capsules, obstacles, t_s)
    return select_queries(
        lists, candidates, count, geom_xpos, geom_xmat, capsules, shapes, obstacles, t_s, travel_m, margin_m
    )


@kernel
def nearest_into(
    approaches: FloatArray,
    held: FloatArray,
    candidates: FloatArray,
    distances: FloatArray,
    fromtos: FloatArray,
    lists: np.ndarray,
    queued: int,
    geom_xpos: FloatArray,
    geom_xmat: FloatArray,
    capsules: FloatArray,
    shapes: FloatArray,
    obstacles: FloatArray,
    margin_m: float,
    travel_m: float,
    t_s: float,
) -> tuple[int, int]:
    """Per (link, obstacle) within rho_0, the link's closest capsule among the queued candidates.

    The queued candidates with a sphere or a plane are answered here (closed
    form, up to ``rho_0 + margin_m``); the others' ``distances[c]`` and
    ``fromtos[c]`` are MuJoCo's answers (the distance, then the capsule's
    closest point and the obstacle's). They become each candidate's last query.
    The approaches are written in the order their (link, obstacle) first
    appears in the queue, with the normal from the obstacle's point to the
    link's; a pair closer than :data:`NORMAL_FROM_POINTS_M` keeps the distance
    and points, for the caller to replace (firas).

    Returns:
        How many approaches (and held rows) were written, and how many of them
        are that close (touching).
    """
    links = 0  # the arm's joints that carry capsules: slots per (link, obstacle)
    for i in range(capsules.shape[0]):
        links = max(links, int(capsules[i, dk.CAPSULE_JOINT]) + 1)
    slots = np.full((links, obstacles.shape[0]), -1)
    best = np.empty(queued, dtype=np.int64)
    count, touching = 0, 0
    for q in range(queued):
        c = lists[q, LIST_QUEUE]
        row = candidates[c]
        i, j = int(row[CANDIDATE_CAPSULE]), int(row[CANDIDATE_OBSTACLE])
        limit = obstacles[j, OBSTACLE_RHO_0]
        if row[CANDIDATE_ANALYTIC] != 0.0:
            distances[c] = dk.analytic_distance(
                fromtos[c], geom_xpos, geom_xmat, capsules, i, shapes, j, limit + margin_m
            )
        distance = distances[c]
        row[CANDIDATE_LAST_M], row[CANDIDATE_TRAVEL_M] = distance, travel_m
        if distance >= limit:
            continue
        k = int(capsules[i, dk.CAPSULE_JOINT])
        slot = slots[k, j]
        if slot < 0:
            slots[k, j] = count
            best[count] = c
            count += 1
        elif distance < distances[best[slot]]:
            best[slot] = c
    for s in range(count):
        c = best[s]
        row = candidates[c]
        i, j = int(row[CANDIDATE_CAPSULE]), int(row[CANDIDATE_OBSTACLE])
        distance = distances[c]
        f = fromtos[c]
        px, py, pz, ox, oy, oz = f[0], f[1], f[2], f[3], f[4], f[5]
        if distance > NORMAL_FROM_POINTS_M:
            nx, ny, nz = (px - ox) / distance, (py - oy) / distance, (pz - oz) / distance
        else:
            nx, ny, nz = 0.0, 0.0, 0.0  # replaced by the caller
            touching += 1
        h = held[s]
        h[HELD_LINK], h[HELD_OBSTACLE], h[HELD_CAPSULE] = capsules[i, dk.CAPSULE_JOINT], j, i
        h[HELD_POINT], h[HELD_POINT + 1], h[HELD_POINT + 2] = px, py, pz
        h[HELD_OTHER], h[HELD_OTHER + 1], h[HELD_OTHER + 2] = ox, oy, oz
        h[HELD_NORMAL], h[HELD_NORMAL + 1], h[HELD_NORMAL + 2] = nx, ny, nz
        h[HELD_S] = t_s
        a = approaches[s]
        a[APPROACH_LINK], a[APPROACH_OBSTACLE], a[APPROACH_DISTANCE] = h[HELD_LINK], j, distance
        a[APPROACH_POINT], a[APPROACH_POINT + 1], a[APPROACH_POINT + 2] = px, py, pz
        a[APPROACH_NORMAL], a[APPROACH_NORMAL + 1], a[APPROACH_NORMAL + 2] = nx, ny, nz
    return count, touching


@kernel
def estimate_into(
    approaches: FloatArray,
    held: FloatArray,
    count: int,
    frames: FloatArray,
    obstacles: FloatArray,
    t_s: float,
) -> int:
    """The first ``count`` held approaches carried forward to ``t_s`` to first order.

    Each held closest point moves with its link's current twist ``(v, w)`` at
    the world origin (``p + (v + w x p) dt``), the obstacle's point with the
    obstacle's velocity, and the distance is their separation along the held
    normal; the pairs still within rho_0 are written to ``approaches``.

    Returns:
        How many approaches were written.
    """
    out = 0
    for s in range(count):
        h = held[s]
        k, j = int(h[HELD_LINK]), int(h[HELD_OBSTACLE])
        dt = t_s - h[HELD_S]
        px, py, pz = h[HELD_POINT], h[HELD_POINT + 1], h[HELD_POINT + 2]
        f = frames[k]
        vx, vy, vz = f[FRAME_TWIST], f[FRAME_TWIST + 1], f[FRAME_TWIST + 2]
        wx, wy, wz = f[FRAME_TWIST + 3], f[FRAME_TWIST + 4], f[FRAME_TWIST + 5]
        px, py, pz = (
            px + (vx + wy * pz - wz * py) * dt,
            py + (vy + wz * px - wx * pz) * dt,
            pz + (vz + wx * py - wy * px) * dt,
        )
        o = obstacles[j]
        ux, uy, uz = o[OBSTACLE_VELOCITY], o[OBSTACLE_VELOCITY + 1], o[OBSTACLE_VELOCITY + 2]
        nx, ny, nz = h[HELD_NORMAL], h[HELD_NORMAL + 1], h[HELD_NORMAL + 2]
        distance = (
            nx * (px - h[HELD_OTHER] - ux * dt)
            + ny * (py - h[HELD_OTHER + 1] - uy * dt)
            + nz * (pz - h[HELD_OTHER + 2] - uz * dt)
        )
        if distance < o[OBSTACLE_RHO_0]:
            a = approaches[out]
            a[APPROACH_LINK], a[APPROACH_OBSTACLE], a[APPROACH_DISTANCE] = k, j, distance
            a[APPROACH_POINT], a[APPROACH_POINT + 1], a[APPROACH_POINT + 2] = px, py, pz
            a[APPROACH_NORMAL], a[APPROACH_NORMAL + 1], a[APPROACH_NORMAL + 2] = nx, ny, nz
            out += 1
    return out


@kernel
def estimated_torque_into(
    torque: FloatArray,
    link_torque: FloatArray,
    nearest: FloatArray,
    acting: FloatArray,
    frames: FloatArray,
    chain: FloatArray,
    q: FloatArray,
    qd: FloatArray,
    approaches: FloatArray,
    held: FloatArray,
    count: int,
    obstacles: FloatArray,
    parameters: FloatArray,
    t_s: float,
) -> float:
    """An evaluation between measurements in one call: kinematics, :func:`estimate_into`, the torques.

    Returns:
        The arm's speed bound, as :func:`~cosmos.obstacles.kernels.field.chain_kinematics_into`.
    """
    speed = chain_kinematics_into(frames, chain, q, qd)
    estimated = estimate_into(approaches, held, count, frames, obstacles, t_s)
    field_torque_into(
        torque, link_torque, nearest, acting, approaches, estimated, frames, obstacles, parameters
    )
    return speed
