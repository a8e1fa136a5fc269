"""Which bodies are clear of every world geom for the coming physics step, compiled (numba).

:class:`cosmos.obstacles.gate.ContactGate` turns MuJoCo's contact test off, for
one step, for each body of the arm that provably cannot touch any geom of the
world body in that step: it has no contact to find, and MuJoCo's walk of the
world's tree (obstacles and fixtures, ``mj_collideTree``) for it is the most
expensive part of a step among obstacles. The proof, per body:

* When the body's clearance is found, the poses in ``data`` are those MuJoCo
  computed at the start of the previous step, at the joint angles ``q_found``
  the gate saw then (one step before: the time says so). Its geoms' boxes there
  (the leaves of MuJoCo's own tree of the body, in its inertial frame) hold them;
  its clearance is how far, along an axis, those boxes are from every box of the
  world's tree leading to a geom that can touch the body.
* MuJoCo collides a later step at the joint angles ``q`` it starts from. Turning
  revolute joint ``j`` moves a point by at most ``|dq_j| reach_jb``, where
  ``reach_jb`` bounds the distance of the body's geoms from the joint's axis in
  every configuration (an arc is longer than its chord), so from ``q_found`` to
  ``q`` (one joint after the other) no point of them moved more than
  ``moved = sum_j |q_j - q_found_j| reach_jb``, whatever the way.
* So while ``moved`` and MuJoCo's margins stay below the clearance, the body's
  geoms lie inside a box that meets no box leading to a geom it can touch: no pair
  of geoms can pass MuJoCo's own box tests, the contacts are the same with the body
  switched off, and none is lost.

A body whose clearance is spent is looked at again at once; one not shown clear
is looked at again once it may have moved by as much as its box overlapped the
world's, at least :data:`RETRY_M` (it collides as compiled meanwhile: waiting only
costs MuJoCo's test). A change of the world's tree forgets every clearance.

The arrays are MuJoCo's own, read in place, and the gate's; :func:`engage_into` finds
them all in ``ints`` (:class:`cosmos.obstacles.kernels.arrays.ArrayTable`: the call from
Python every tick takes one array instead of twelve). The body flags are written in
place (:func:`release_into` restores the compiled ones).
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.obstacles.kernels.arrays import ENTRY, float_rows, int32_rows

FloatArray = np.ndarray

RETRY_M = 1e-3
"""A body not shown clear is looked at again once it may have moved at least this far [m]."""
ENOUGH_M = 0.02
"""A node of a body's tree this clear is clear enough: its geoms below are not looked at [m]."""

# ``ints`` (int64): the counts, the floats of ``state`` per body, where the stacks and the arrays'
# table start; per gated body its id,
# the first node of its tree and how many (boxes in its inertial frame) and its compiled contype
# and conaffinity; the qpos indices of the arm's joints; per world geom (from the world's first) a bit
# per gated body that it can touch; room for the stacks of a walk of the world's tree and of a
# body's (written by the walks); then the table of the arrays (ARRAY_*, each ENTRY long:
# cosmos.obstacles.kernels.arrays).
INT_BODIES, INT_WORLD_ROOT, INT_JOINTS, INT_BODY_STATE, INT_STACK, INT_BODY_STACK, INT_ARRAYS = range(7)
INT_HEADER = 7
ARRAY_CONTYPE, ARRAY_CONAFFINITY, ARRAY_QPOS, ARRAY_XIPOS, ARRAY_XIMAT = range(5)
ARRAY_BVH_AABB, ARRAY_BVH_CHILD, ARRAY_BVH_NODEID, ARRAY_VERSION, ARRAY_STATE = range(5, 10)
ARRAYS = 10
BODY_ID, BODY_NODE, BODY_NODES, BODY_CONTYPE, BODY_CONAFFINITY = range(5)
BODY = 5

# ``state`` (float64): the time of the last step seen and whether it is set, the physics time
# step [s], the slack [m] (MuJoCo's margins and a rounding allowance), the largest clearance worth
# finding [m], the world's tree's version when the clearances were found; the joint angles of the
# last step seen; then per gated body: its clearance [m], how far it may move before it is looked at
# again [m], the joint angles its clearance was found at, and per joint its reach [m] (0: the joint
# does not carry it).
STATE_TIME, STATE_SEEN, STATE_DT, STATE_SLACK, STATE_CAP, STATE_VERSION, STATE_Q = range(7)
STATE_CLEARANCE, STATE_RETRY, STATE_FOUND_Q = range(3)


@kernel
def clearance(
    center: tuple[float, float, float],
    rot: FloatArray,
    half: tuple[float, float, float],
    bit: int,
    cap: float,
    ints: np.ndarray,
    bvh_aabb: FloatArray,
    bvh_child: np.ndarray,
    bvh_nodeid: np.ndarray,
) -> float:
    """How far, along an axis, a box is from every world geom that can touch body ``bit``.

    The box: its ``center`` [m] and its axes (the columns of ``rot``, row-major) in
    world, its ``half`` sizes along them [m]. The smallest of its separations from
    the leaves of the world's tree whose geom can touch it, at most ``cap``; zero
    or less if it meets one (then the first such separation found). A separation
    along any axis is a lower bound on the distance: the world's axes and the
    box's own are tried (a link lying across the world's axes is far better
    bounded along its own). Nodes farther than the best found so far are not opened.
    """
    cx, cy, cz = center
    h0, h1, h2 = half
    # the box's extent along the world's axes
    w0 = abs(rot[0]) * h0 + abs(rot[1]) * h1 + abs(rot[2]) * h2
    w1 = abs(rot[3]) * h0 + abs(rot[4]) * h1 + abs(rot[5]) * h2
    w2 = abs(rot[6]) * h0 + abs(rot[7]) * h1 + abs(rot[8]) * h2
    root = ints[INT_WORLD_ROOT]
    compat = INT_HEADER + BODY * ints[INT_BODIES] + ints[INT_JOINTS]
    stack = ints[INT_STACK]
    best = cap
    ints[stack] = root
    count = 1
    while count:
        count -= 1
        node = ints[stack + count]
        box = bvh_aabb[node]
        d0, d1, d2 = cx - box[0], cy - box[1], cz - box[2]
        gap = max(abs(d0) - w0 - box[3], abs(d1) - w1 - box[4], abs(d2) - w2 - box[5])
        if gap < best:  # along the box's own axes
            for i in range(3):
                u0, u1, u2 = rot[i], rot[3 + i], rot[6 + i]
                reach = abs(u0) * box[3] + abs(u1) * box[4] + abs(u2) * box[5]
                gap = max(gap, abs(u0 * d0 + u1 * d1 + u2 * d2) - half[i] - reach)
        if gap >= best:
            continue
        left, right = bvh_child[node, 0], bvh_child[node, 1]
        if left < 0 and right < 0:
            if ints[compat + bvh_nodeid[node]] & bit:
                best = gap
                if best <= 0.0:
                    return best
            continue
        if left >= 0:
            ints[stack + count] = root + left
            count += 1
        if right >= 0:
            ints[stack + count] = root + right
            count += 1
    return best


@kernel
def body_clearance(
    k: int,
    cap: float,
    xipos: FloatArray,
    ximat: FloatArray,
    ints: np.ndarray,
    bvh_aabb: FloatArray,
    bvh_child: np.ndarray,
    bvh_nodeid: np.ndarray,
) -> float:
    """Gated body ``k``'s clearance as the poses in data have it: the least of its geoms' boxes'.

    MuJoCo's tree of the body (boxes in its inertial frame: a geom's box at each
    leaf) is walked from its root, each node placed in the world and its
    :func:`clearance` found up to the best so far: a node no nearer than that has
    no leaf nearer either (its box holds theirs), so the walk stops there, as it
    does at a node :data:`ENOUGH_M` clear (its clearance holds for its leaves). A
    long link's or a tool's own box holds much room its geoms do not.
    """
    row = INT_HEADER + BODY * k
    body, first = ints[row + BODY_ID], ints[row + BODY_NODE]
    rot, pos = ximat[body], xipos[body]
    stack = ints[INT_BODY_STACK]
    best = cap
    ints[stack] = first
    count = 1
    while count:
        count -= 1
        node = ints[stack + count]
        box = bvh_aabb[node]
        c0 = rot[0] * box[0] + rot[1] * box[1] + rot[2] * box[2] + pos[0]
        c1 = rot[3] * box[0] + rot[4] * box[1] + rot[5] * box[2] + pos[1]
        c2 = rot[6] * box[0] + rot[7] * box[1] + rot[8] * box[2] + pos[2]
        found = clearance(
            (c0, c1, c2), rot, (box[3], box[4], box[5]), 1 << k, best, ints, bvh_aabb, bvh_child, bvh_nodeid
        )
        if found >= best:
            continue
        left, right = bvh_child[node, 0], bvh_child[node, 1]
        if (left < 0 and right < 0) or found >= ENOUGH_M:
            best = found
            if best <= 0.0:
                return best
            continue
        if left >= 0:
            ints[stack + count] = first + left
            count += 1
        if right >= 0:
            ints[stack + count] = first + right
            count += 1
    return best


@kernel
def release_into(contype: np.ndarray, conaffinity: np.ndarray, ints: np.ndarray) -> None:
    """Restore every gated body's compiled contype and conaffinity."""
    for k in range(ints[INT_BODIES]):
        row = INT_HEADER + BODY * k
        body = ints[row + BODY_ID]
        contype[body], conaffinity[body] = ints[row + BODY_CONTYPE], ints[row + BODY_CONAFFINITY]


@kernel
def moved_since_found(state: FloatArray, ints: np.ndarray, qpos: FloatArray, k: int) -> float:
    """How far body ``k``'s geoms may have moved since its clearance was found [m]."""
    joints = ints[INT_JOINTS]
    first_joint = INT_HEADER + BODY * ints[INT_BODIES]
    at = STATE_Q + joints + k * ints[INT_BODY_STATE]
    found, reach = at + STATE_FOUND_Q, at + STATE_FOUND_Q + joints
    moved = 0.0
    for j in range(joints):
        if state[reach + j] > 0.0:
            moved += abs(qpos[ints[first_joint + j]] - state[found + j]) * state[reach + j]
    return moved


@kernel
def gate_into(
    contype: np.ndarray,
    conaffinity: np.ndarray,
    xipos: FloatArray,
    ximat: FloatArray,
    qpos: FloatArray,
    time_s: float,
    version: FloatArray,
    state: FloatArray,
    ints: np.ndarray,
    bvh_aabb: FloatArray,
    bvh_child: np.ndarray,
    bvh_nodeid: np.ndarray,
) -> int:
    """Switch off (``contype = conaffinity = 0``) each body clear of the world for the coming step.

    Every other gated body gets its compiled flags back. Only when exactly one
    step was taken since the last call (``time_s`` is the last time plus the time
    step): then ``data``'s poses are at the kept joint angles, and the step
    collides at ``qpos``; else every body gets its flags back and every clearance
    is forgotten, as when the world's tree changed (``version[0]`` raised). Returns
    how many bodies were switched off.
    """
    joints, bodies = ints[INT_JOINTS], ints[INT_BODIES]
    size = ints[INT_BODY_STATE]
    seen = state[STATE_SEEN] > 0.0 and abs(time_s - state[STATE_TIME] - state[STATE_DT]) <= 1e-9
    if not seen or version[0] != state[STATE_VERSION]:
        state[STATE_VERSION] = version[0]
        for k in range(bodies):
            at = STATE_Q + joints + k * size
            state[at + STATE_CLEARANCE], state[at + STATE_RETRY] = -1.0, -1.0
    if not seen:
        release_into(contype, conaffinity, ints)
    slack, cap = state[STATE_SLACK], state[STATE_CAP]
    gated = 0
    for k in range(bodies if seen else 0):
        at = STATE_Q + joints + k * size
        moved = moved_since_found(state, ints, qpos, k)
        if moved >= state[at + STATE_RETRY]:  # spent, or not shown clear and moved enough: look again
            found = body_clearance(k, cap, xipos, ximat, ints, bvh_aabb, bvh_child, bvh_nodeid)
            for j in range(joints):  # the poses in data are those of the last step seen
                state[at + STATE_FOUND_Q + j] = state[STATE_Q + j]
            moved = moved_since_found(state, ints, qpos, k)
            state[at + STATE_CLEARANCE] = found
            if moved + slack < found:
                state[at + STATE_RETRY] = found - slack
            else:
                state[at + STATE_RETRY] = moved + max(-found, RETRY_M)
        row = INT_HEADER + BODY * k
        body = ints[row + BODY_ID]
        if moved + slack < state[at + STATE_CLEARANCE]:
            contype[body], conaffinity[body] = 0, 0
            gated += 1
        else:
            contype[body], conaffinity[body] = ints[row + BODY_CONTYPE], ints[row + BODY_CONAFFINITY]
    first_joint = INT_HEADER + BODY * bodies  # the time and the joint angles of the coming step, kept
    for j in range(joints):
        state[STATE_Q + j] = qpos[ints[first_joint + j]]
    state[STATE_TIME], state[STATE_SEEN] = time_s, 1.0
    return gated


@kernel
def engage_into(ints: np.ndarray, time_s: float) -> int:
    """:func:`gate_into` on the arrays listed in ``ints`` (``ARRAY_*``) for a step at ``time_s`` [s].

    At a ``time_s`` of NaN no step follows the last one seen, now or at the next call:
    every body gets its compiled flags back and every clearance is forgotten (a release).
    """
    at = ints[INT_ARRAYS]
    return gate_into(
        int32_rows(ints, at + ENTRY * ARRAY_CONTYPE)[0],
        int32_rows(ints, at + ENTRY * ARRAY_CONAFFINITY)[0],
        float_rows(ints, at + ENTRY * ARRAY_XIPOS),
        float_rows(ints, at + ENTRY * ARRAY_XIMAT),
        float_rows(ints, at + ENTRY * ARRAY_QPOS)[0],
        time_s,
        float_rows(ints, at + ENTRY * ARRAY_VERSION)[0],
        float_rows(ints, at + ENTRY * ARRAY_STATE)[0],
        ints,
        float_rows(ints, at + ENTRY * ARRAY_BVH_AABB),
        int32_rows(ints, at + ENTRY * ARRAY_BVH_CHILD),
        int32_rows(ints, at + ENTRY * ARRAY_BVH_NODEID)[0],
    )
