"""One evaluation of the obstacle field in as few compiled calls as it can be (numba).

:meth:`cosmos.obstacles.field.ObstacleField.torque` evaluates at 125 Hz; between
measurements of the closest points it is :func:`estimated_into` (one call), at a
measurement :func:`select_into` (the arm's kinematics, the travel bound, the
candidates and queries), MuJoCo's ``mj_geomDistance`` for the pairs with a box or
a cylinder (from Python), then :func:`nearest_into` (the approaches and the
torques). The arrays are listed once in an
:class:`~cosmos.obstacles.kernels.arrays.ArrayTable` (``ARRAY_*`` below), so each
call from Python converts a few arguments instead of a dozen: most of what these
calls cost was their arguments. The arithmetic is that of
:mod:`cosmos.obstacles.kernels.geometry` and :mod:`cosmos.obstacles.kernels.field`,
called as they are.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.obstacles.kernels import geometry as gk
from cosmos.obstacles.kernels.arrays import ENTRY, float_rows, int64_rows
from cosmos.obstacles.kernels.field import chain_kinematics_into, field_torque_into

FloatArray = np.ndarray

# The arrays of an evaluation, in their table's order: the field's (torque, its links' part, the
# nearest link, per obstacle whether it acted, the joint frames, the chain, the parameters), the
# proximity model's (approaches, held points, obstacles, candidates, lists, the last distances and
# points, its private model's geom poses, capsules, shapes) and the scalars below.
ARRAY_TORQUE, ARRAY_LINK_TORQUE, ARRAY_NEAREST, ARRAY_ACTING, ARRAY_FRAMES, ARRAY_CHAIN = range(6)
ARRAY_PARAMETERS, ARRAY_APPROACHES, ARRAY_HELD, ARRAY_OBSTACLES, ARRAY_CANDIDATES = range(6, 11)
ARRAY_LISTS, ARRAY_DISTANCES, ARRAY_FROMTOS, ARRAY_XPOS, ARRAY_XMAT, ARRAY_CAPSULES = range(11, 17)
ARRAY_SHAPES, ARRAY_SCALARS = 17, 18
ARRAYS = 19

# ``scalars`` (SCALARS,): the bound on how far arm and obstacles may have closed since the candidates
# were listed [m], the time of the last measurement [s] (NaN: none), how many candidates are listed
# (-1: to be listed), how many approaches are held, the bound on the arm's speed over the last
# estimates [m/s], the obstacles' largest speed [m/s], the candidates' margin [m].
SCALAR_TRAVEL, SCALAR_LAST_S, SCALAR_COUNT, SCALAR_HELD, SCALAR_SPEED_BOUND = range(5)
SCALAR_OBSTACLE_SPEED, SCALAR_MARGIN = 5, 6
SCALARS = 7


@kernel
def estimated_into(table: np.ndarray, q: FloatArray, qd: FloatArray, t_s: float) -> None:
    """An evaluation between measurements: the held approaches carried to ``t_s`` [s], the torques.

    As :func:`cosmos.obstacles.kernels.geometry.estimated_torque_into`, into zeroed
    torques; the arm's speed bound is kept for the next measurement.
    """
    torque, link_torque = (
        float_rows(table, ENTRY * ARRAY_TORQUE)[0],
        float_rows(table, ENTRY * ARRAY_LINK_TORQUE)[0],
    )
    torque[:] = 0.0
    link_torque[:] = 0.0
    scalars = float_rows(table, ENTRY * ARRAY_SCALARS)[0]
    speed = gk.estimated_torque_into(
        torque,
        link_torque,
        float_rows(table, ENTRY * ARRAY_NEAREST)[0],
        float_rows(table, ENTRY * ARRAY_ACTING),
        float_rows(table, ENTRY * ARRAY_FRAMES),
        float_rows(table, ENTRY * ARRAY_CHAIN),
        q,
        qd,
        float_rows(table, ENTRY * ARRAY_APPROACHES),
        float_rows(table, ENTRY * ARRAY_HELD),
        int(scalars[SCALAR_HELD]),
        float_rows(table, ENTRY * ARRAY_OBSTACLES),
        float_rows(table, ENTRY * ARRAY_PARAMETERS)[0],
        t_s,
    )
    bound = speed + scalars[SCALAR_OBSTACLE_SPEED]
    scalars[SCALAR_SPEED_BOUND] = max(scalars[SCALAR_SPEED_BOUND], bound)


@kernel
def select_into(table: np.ndarray, q: FloatArray, qd: FloatArray, t_s: float) -> tuple[int, int]:
    """A measurement's first half: kinematics, the travel bound, the candidates and the queries.

    The arm's joint frames at ``(q, qd)``; the bound on how far the arm and the
    obstacles may have closed grows by the larger of the last estimates' speed
    bound and this one's over the time since the last measurement, and the
    candidates are listed again once it reaches the margin (as
    :meth:`cosmos.obstacles.geometry.ProximityModel.measure`); then
    :func:`cosmos.obstacles.kernels.geometry.place_and_select`.

    Returns:
        How many candidates are queued, and how many of them MuJoCo answers.
    """
    scalars = float_rows(table, ENTRY * ARRAY_SCALARS)[0]
    frames = float_rows(table, ENTRY * ARRAY_FRAMES)
    speed = (
        chain_kinematics_into(frames, float_rows(table, ENTRY * ARRAY_CHAIN), q, qd)
        + scalars[SCALAR_OBSTACLE_SPEED]
    )
    if not np.isnan(scalars[SCALAR_LAST_S]):
        scalars[SCALAR_TRAVEL] += max(scalars[SCALAR_SPEED_BOUND], speed) * abs(t_s - scalars[SCALAR_LAST_S])
    scalars[SCALAR_LAST_S] = t_s
    scalars[SCALAR_SPEED_BOUND] = speed
    margin = scalars[SCALAR_MARGIN]
    count = int(scalars[SCALAR_COUNT])
    if count < 0 or scalars[SCALAR_TRAVEL] >= margin:
        scalars[SCALAR_TRAVEL], count = 0.0, -1  # list the candidates again
    count, queued, remotes = gk.place_and_select(
        int64_rows(table, ENTRY * ARRAY_LISTS),
        float_rows(table, ENTRY * ARRAY_CANDIDATES),
        count,
        float_rows(table, ENTRY * ARRAY_XPOS),
        float_rows(table, ENTRY * ARRAY_XMAT),
        frames,
        float_rows(table, ENTRY * ARRAY_CAPSULES),
        float_rows(table, ENTRY * ARRAY_SHAPES),
        float_rows(table, ENTRY * ARRAY_OBSTACLES),
        t_s,
        scalars[SCALAR_TRAVEL],
        margin,
    )
    scalars[SCALAR_COUNT] = count
    return queued, remotes


@kernel
def torque_into(table: np.ndarray, count: int) -> None:
    """The field's torques from the first ``count`` approaches, into zeroed torques."""
    torque, link_torque = (
        float_rows(table, ENTRY * ARRAY_TORQUE)[0],
        float_rows(table, ENTRY * ARRAY_LINK_TORQUE)[0],
    )
    torque[:] = 0.0
    link_torque[:] = 0.0
    field_torque_into(
        torque,
        link_torque,
        float_rows(table, ENTRY * ARRAY_NEAREST)[0],
        float_rows(table, ENTRY * ARRAY_ACTING),
        float_rows(table, ENTRY * ARRAY_APPROACHES),
        count,
        float_rows(table, ENTRY * ARRAY_FRAMES),
        float_rows(table, ENTRY * ARRAY_OBSTACLES),
        float_rows(table, ENTRY * ARRAY_PARAMETERS)[0],
    )


@kernel
def nearest_into(table: np.ndarray, queued: int, t_s: float) -> tuple[int, int]:
    """A measurement's second half: the approaches (MuJoCo's answers in), and the torques from them.

    :func:`cosmos.obstacles.kernels.geometry.nearest_into`; unless an approach
    touches (then the caller first replaces its point and normal, and calls
    :func:`torque_into`), :func:`torque_into`.

    Returns:
        How many approaches are held, and how many of them touch.
    """
    scalars = float_rows(table, ENTRY * ARRAY_SCALARS)[0]
    count, touching = gk.nearest_into(
        float_rows(table, ENTRY * ARRAY_APPROACHES),
        float_rows(table, ENTRY * ARRAY_HELD),
        float_rows(table, ENTRY * ARRAY_CANDIDATES),
        float_rows(table, ENTRY * ARRAY_DISTANCES)[0],
        float_rows(table, ENTRY * ARRAY_FROMTOS),
        int64_rows(table, ENTRY * ARRAY_LISTS),
        queued,
        float_rows(table, ENTRY * ARRAY_XPOS),
        float_rows(table, ENTRY * ARRAY_XMAT),
        float_rows(table, ENTRY * ARRAY_CAPSULES),
        float_rows(table, ENTRY * ARRAY_SHAPES),
        float_rows(table, ENTRY * ARRAY_OBSTACLES),
        scalars[SCALAR_MARGIN],
        scalars[SCALAR_TRAVEL],
        t_s,
    )
    scalars[SCALAR_HELD] = count
    if touching == 0:
        torque_into(table, count)
    return count, touching
