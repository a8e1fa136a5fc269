"""Which (capsule, obstacle) pairs the proximity model queries at a measurement, compiled (numba).

The candidate list holds the pairs that may be within ``rho_0 + margin`` of
each other (lower bounds: the midpoint's signed distance less the capsule's
bounding radius, separating axes); it is rebuilt once the arm and the
obstacles may have closed the margin. At each measurement the candidates that
may have come within rho_0 since their last query are queued: answered in
closed form (spheres, planes) or by MuJoCo (boxes, cylinders).
``tests/obstacles/test_obstacles_geometry_kernel.py`` checks that no pair
within rho_0 is ever missed, against brute-force firas distances.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.obstacles.kernels import distance as dk
from cosmos.obstacles.kernels.field import (
    OBSTACLE_ADDED_S,
    OBSTACLE_CENTER,
    OBSTACLE_RHO_0,
    OBSTACLE_VELOCITY,
)

FloatArray = np.ndarray

# ``candidates`` (m, CANDIDATE): a (capsule, obstacle) pair within rho_0 + margin, the distance at
# its last query [m] (-inf: never queried), the travel bound [m] at that query, and 1.0 when the
# obstacle is a sphere or a plane (closed form; else MuJoCo's query). Each candidate's last answer
# (distance and the segment from the capsule to the obstacle) is kept in parallel arrays.
CANDIDATE_CAPSULE, CANDIDATE_OBSTACLE, CANDIDATE_LAST_M, CANDIDATE_TRAVEL_M, CANDIDATE_ANALYTIC = range(5)
CANDIDATE = 5

# ``lists`` (m, LISTS), integers: the queue of candidates to answer, and those of them MuJoCo answers
# with their capsule's and their obstacle's geom.
LIST_QUEUE, LIST_REMOTE, LIST_REMOTE_CAPSULE, LIST_REMOTE_GEOM = range(4)
LISTS = 4


@kernel
def _center(obstacle: FloatArray, t_s: float) -> tuple[float, float, float]:
    """An obstacle's centre at ``t_s``: ``c + v (t - t_added)``, world, in [m]."""
    dt = t_s - obstacle[OBSTACLE_ADDED_S]
    return (
        obstacle[OBSTACLE_CENTER] + dt * obstacle[OBSTACLE_VELOCITY],
        obstacle[OBSTACLE_CENTER + 1] + dt * obstacle[OBSTACLE_VELOCITY + 1],
        obstacle[OBSTACLE_CENTER + 2] + dt * obstacle[OBSTACLE_VELOCITY + 2],
    )


@kernel
def _separated(
    geom_xpos: FloatArray,
    geom_xmat: FloatArray,
    capsules: FloatArray,
    i: int,
    shape: FloatArray,
    cx: float,
    cy: float,
    cz: float,
) -> float:
    """A lower bound on capsule ``i``'s distance to the obstacle (separating axes), in [m]."""
    axis = np.empty(3)
    axis[0], axis[1], axis[2] = geom_xmat[i, 2], geom_xmat[i, 5], geom_xmat[i, 8]
    gap = dk.segment_lower_bound(geom_xpos[i], axis, capsules[i, dk.CAPSULE_HALF], shape, cx, cy, cz)
    return gap - capsules[i, dk.CAPSULE_RADIUS]


@kernel
def select_queries(
    lists: np.ndarray,
    candidates: FloatArray,
    count: int,
    geom_xpos: FloatArray,
    geom_xmat: FloatArray,
    capsules: FloatArray,
    shapes: FloatArray,
    obstacles: FloatArray,
    t_s: float,
    travel_m: float,
    margin_m: float,
) -> tuple[int, int, int]:
    """The candidates that may have come within rho_0 since their last query (rebuilt first if asked).

    With ``count`` < 0 the list is rebuilt: a capsule lies within ``bound`` of
    its midpoint (``geom_xpos``, placed by :func:`place_geoms_into`), so its
    distance to an obstacle is at least the midpoint's signed distance minus
    ``bound``, and at least a separating axis' gap minus its radius
    (:func:`~cosmos.obstacles.kernels.distance.segment_lower_bound`); the pairs
    where these lower bounds are below ``rho_0 + margin_m`` become the
    candidates (capsule-major, never queried). Then a pair ``last_m`` apart at
    its last query, when the travel bound was ``travel_then``, can have closed
    at most ``travel_m - travel_then`` since: those that may be within rho_0
    are queued (``lists[:, LIST_QUEUE]``), and those needing MuJoCo (box,
    cylinder) listed with their capsule and the obstacle's geom
    (``lists[:, LIST_REMOTE:]``), unless their separating-axis bound now keeps
    them beyond rho_0 (then they are not queued).

    Returns:
        The number of candidates, of queued ones and of remote ones.
    """
    n = capsules.shape[0]
    if count < 0:
        count = 0
        for i in range(n):
            x, y, z = geom_xpos[i, 0], geom_xpos[i, 1], geom_xpos[i, 2]
            for j in range(shapes.shape[0]):
                o = obstacles[j]
                reach = o[OBSTACLE_RHO_0] + margin_m
                cx, cy, cz = _center(o, t_s)
                if (
                    dk.signed_distance(x, y, z, shapes[j], cx, cy, cz) - capsules[i, dk.CAPSULE_BOUND]
                    >= reach
                ):
                    continue
                if _separated(geom_xpos, geom_xmat, capsules, i, shapes[j], cx, cy, cz) >= reach:
                    continue
                kind = shapes[j, dk.SHAPE_KIND]
                row = candidates[count]
                row[CANDIDATE_CAPSULE], row[CANDIDATE_OBSTACLE] = i, j
                row[CANDIDATE_LAST_M], row[CANDIDATE_TRAVEL_M] = -np.inf, 0.0
                row[CANDIDATE_ANALYTIC] = 1.0 if kind == dk.KIND_SPHERE or kind == dk.KIND_PLANE else 0.0
                count += 1
    queued, remotes = 0, 0
    for c in range(count):
        row = candidates[c]
        j = int(row[CANDIDATE_OBSTACLE])
        if row[CANDIDATE_LAST_M] - (travel_m - row[CANDIDATE_TRAVEL_M]) >= obstacles[j, OBSTACLE_RHO_0]:
            continue  # it was farther than it can have come since
        if row[CANDIDATE_ANALYTIC] == 0.0:
            cx, cy, cz = _center(obstacles[j], t_s)
            i = int(row[CANDIDATE_CAPSULE])
            if (
                _separated(geom_xpos, geom_xmat, capsules, i, shapes[j], cx, cy, cz)
                >= obstacles[j, OBSTACLE_RHO_0]
            ):
                continue  # beyond rho_0 now: no query
        lists[queued, LIST_QUEUE] = c
        queued += 1
        if row[CANDIDATE_ANALYTIC] == 0.0:
            lists[remotes, LIST_REMOTE] = c
            lists[remotes, LIST_REMOTE_CAPSULE] = int(row[CANDIDATE_CAPSULE])
            lists[remotes, LIST_REMOTE_GEOM] = n + j
            remotes += 1
    return count, queued, remotes
