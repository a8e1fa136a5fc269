"""Which bodies are clear of every world geom for the coming physics step, compiled (numba).

:class:`cosmos.obstacles.gate.ContactGate` turns MuJoCo's contact test off, for
one step, for each body of the arm that provably cannot touch any geom of the
world body in that step: it has no contact to find, and MuJoCo's walk of the
world's tree (obstacles and fixtures, ``mj_collideTree``) for it is the most
expensive part of a step among obstacles. The proof, per body:

* MuJoCo collides the step at the joint angles ``q`` it starts from, with the
  geoms' poses it then computes. The poses in ``data`` are those of the
  previous step, at ``q_prev``, which the gate kept (one step before: the time
  says so). A point of a geom carried by revolute joints moves by at most
  ``sum_j |q_j - q_prev_j| * reach`` (an arc is longer than its chord; ``reach``
  bounds the distance of any point of the arm from any joint's axis).
* So the body's geoms lie, at ``q``, inside its box at ``q_prev`` (the root of
  MuJoCo's own tree of the body, in its inertial frame, turned into world axes)
  grown by that bound and MuJoCo's margins.
* If that box meets no box of the world's tree leading to a geom that can touch
  the body (contype/conaffinity), no pair of geoms can pass MuJoCo's own box
  tests: the contacts are the same with the body switched off, and none is lost.

Arrays are MuJoCo's own, read in place; the body flags are written in place
(:func:`release_into` restores the compiled ones after the step).
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray

# ``ints`` (int64): the counts, then per gated body its id, the node of its tree's root (its box in
# its inertial frame) and its compiled contype and conaffinity; the qpos indices of the arm's joints;
# per world geom (from the world's first) a bit per gated body that it can touch.
INT_BODIES, INT_WORLD_ROOT, INT_JOINTS = range(3)
INT_HEADER = 3
BODY_ID, BODY_NODE, BODY_CONTYPE, BODY_CONAFFINITY = range(4)
BODY = 4

# ``state`` (float64): the time and the joint angles of the last step seen, whether they are set,
# the physics time step [s], the reach [m], the slack [m] (MuJoCo's margins and a rounding
# allowance), the largest clearance worth finding [m], the world's tree's version when the
# clearances were found; then the joint angles, then per gated body its clearance [m] (negative:
# none known) and how far it may have moved since [m].
STATE_TIME, STATE_SEEN, STATE_DT, STATE_REACH, STATE_SLACK, STATE_CAP, STATE_VERSION, STATE_Q = range(8)


@kernel
def clearance(
    lo_x: float,
    lo_y: float,
    lo_z: float,
    hi_x: float,
    hi_y: float,
    hi_z: float,
    bit: int,
    cap: float,
    ints: np.ndarray,
    bvh_aabb: FloatArray,
    bvh_child: np.ndarray,
    bvh_nodeid: np.ndarray,
    stack: np.ndarray,
) -> float:
    """How far, along an axis, the box ``lo``..``hi`` is from every world geom that can touch body ``bit``.

    The smallest of the separations of the box from the leaves of the world's tree
    whose geom can touch it (a separation along one axis is a lower bound on the
    distance), at most ``cap``; zero or less if it meets one. Nodes farther than
    the best found so far are not opened.
    """
    root = ints[INT_WORLD_ROOT]
    compat = INT_HEADER + BODY * ints[INT_BODIES] + ints[INT_JOINTS]
    best = cap
    stack[0] = root
    count = 1
    while count:
        count -= 1
        node = stack[count]
        box = bvh_aabb[node]
        gap = max(
            box[0] - box[3] - hi_x,
            lo_x - box[0] - box[3],
            box[1] - box[4] - hi_y,
            lo_y - box[1] - box[4],
            box[2] - box[5] - hi_z,
            lo_z - box[2] - box[5],
        )
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
            stack[count] = root + left
            count += 1
        if right >= 0:
            stack[count] = root + right
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
def refind(state: FloatArray, found: int, bodies: int, moved: float) -> bool:
    """Whether some body's clearance is spent (or unknown) this step: a walk of the world's tree."""
    slack = state[STATE_SLACK]
    for k in range(bodies):
        if state[found + 2 * k] <= state[found + 2 * k + 1] + moved + slack:
            return True
    return False


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
    collides at ``qpos``; else every body gets its flags back. A body's clearance, once found, is
    spent by the bound on its motion step by step and found again when spent, or
    when the world's tree changed (``version[0]`` raised). Returns how many bodies were
    switched off.
    """
    joints = ints[INT_JOINTS]
    bodies = ints[INT_BODIES]
    first_joint = INT_HEADER + BODY * bodies
    seen = state[STATE_SEEN] > 0.0 and abs(time_s - state[STATE_TIME] - state[STATE_DT]) <= 1e-9
    turned = 0.0
    for j in range(joints):
        q = qpos[ints[first_joint + j]]
        turned += abs(q - state[STATE_Q + j])
        state[STATE_Q + j] = q
    state[STATE_TIME], state[STATE_SEEN] = time_s, 1.0
    found = STATE_Q + joints  # per body: clearance, motion since
    if not seen or version[0] != state[STATE_VERSION]:
        state[STATE_VERSION] = version[0]
        for k in range(bodies):
            state[found + 2 * k] = -1.0
        if not seen:
            release_into(contype, conaffinity, ints)
            return 0
    moved = state[STATE_REACH] * turned
    slack, cap = state[STATE_SLACK], state[STATE_CAP]
    stack = np.empty(bvh_child.shape[0] if refind(state, found, bodies, moved) else 0, dtype=np.int64)
    gated = 0
    for k in range(bodies):
        row = INT_HEADER + BODY * k
        body = ints[row + BODY_ID]
        spent = state[found + 2 * k + 1] + moved
        if state[found + 2 * k] <= spent + slack:  # spent, or none known: find it again
            box, rot, pos = bvh_aabb[ints[row + BODY_NODE]], ximat[body], xipos[body]
            # the body's box (its inertial frame) in world axes, as the poses in data have it
            c0 = rot[0] * box[0] + rot[1] * box[1] + rot[2] * box[2] + pos[0]
            c1 = rot[3] * box[0] + rot[4] * box[1] + rot[5] * box[2] + pos[1]
            c2 = rot[6] * box[0] + rot[7] * box[1] + rot[8] * box[2] + pos[2]
            h0 = abs(rot[0]) * box[3] + abs(rot[1]) * box[4] + abs(rot[2]) * box[5]
            h1 = abs(rot[3]) * box[3] + abs(rot[4]) * box[4] + abs(rot[5]) * box[5]
            h2 = abs(rot[6]) * box[3] + abs(rot[7]) * box[4] + abs(rot[8]) * box[5]
            state[found + 2 * k] = clearance(
                c0 - h0,
                c1 - h1,
                c2 - h2,
                c0 + h0,
                c1 + h1,
                c2 + h2,
                1 << k,
                cap,
                ints,
                bvh_aabb,
                bvh_child,
                bvh_nodeid,
                stack,
            )
            spent = moved  # from the poses in data to the step's
        state[found + 2 * k + 1] = spent
        if spent + slack < state[found + 2 * k]:
            contype[body], conaffinity[body] = 0, 0
            gated += 1
        else:
            contype[body], conaffinity[body] = ints[row + BODY_CONTYPE], ints[row + BODY_CONAFFINITY]
    return gated
