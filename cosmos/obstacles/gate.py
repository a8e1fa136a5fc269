"""MuJoCo's contact test switched off, for one physics step, for the arm's bodies clear of the world.

Every step MuJoCo walks the world body's tree of boxes (the fixtures and the
obstacles, :mod:`cosmos.obstacles.hierarchy`) for each body of the arm; among
the bench's 50 obstacles that walk is most of what the obstacles cost a step
(about 100 box tests), though in most steps most bodies are centimetres from
every box. :class:`ContactGate` is engaged by the runtime right before each
tick's step (:attr:`cosmos.runtime.loop.Runtime.contact_gate`): it switches off
(``body_contype = body_conaffinity = 0``) each body it proves cannot touch any
world geom in that step, so MuJoCo skips it, and gives the others their flags
back; the proof is in :mod:`cosmos.obstacles.kernels.gate`. The flags hold until
the next tick: whoever collides or steps the plant otherwise (adding an obstacle
checks it is not placed through the arm) releases the gate first. The contacts are MuJoCo's own, unchanged
(``tests/obstacles/test_obstacles_gate.py`` compares them step by step with the
gate off).

A body is gated only if nothing but the world's geoms can touch it (no other
body, by contype and conaffinity: a finger and a held object never are), all
the joints carrying it are revolute, and the step follows the one the gate last
saw by exactly one time step (a tick of several steps, a reset or a jump in time
gates nothing).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from cosmos.obstacles.kernels import gate as gk
from cosmos.obstacles.kernels.arrays import ArrayTable
from cosmos.plant import Plant

SLACK_M = 1e-4
"""Added to the proven bound on the bodies' motion: rounding, with room to spare [m]."""
CAP_M = 0.1
"""A body's clearance is looked for up to this distance [m]: enough for dozens of steps."""


def reach_m(model: mujoco.MjModel, body: int, joint: int) -> float:
    """How far any point of ``body``'s geoms can be from hinge ``joint``'s axis, in any configuration [m].

    At most its distance from the joint's anchor: the anchor's offset in the joint's
    body, the bodies' offsets down to ``body``, and the farthest reach of a geom's
    bounding sphere in ``body``'s frame; 0 if the joint does not carry ``body``.
    """
    if joint not in _chain_joints(model, body):
        return 0.0
    holder = int(model.jnt_bodyid[joint])
    first, count = int(model.body_geomadr[body]), int(model.body_geomnum[body])
    geoms = range(first, first + count)
    bound = max((float(np.linalg.norm(model.geom_pos[g]) + model.geom_rbound[g]) for g in geoms), default=0.0)
    bound += float(np.linalg.norm(model.jnt_pos[joint]))
    while body != holder:
        bound += float(np.linalg.norm(model.body_pos[body]))
        body = int(model.body_parentid[body])
    return bound


def _chain_joints(model: mujoco.MjModel, body: int) -> list[int]:
    """The joints on the way from the world to ``body``."""
    joints: list[int] = []
    while body > 0:
        first, count = int(model.body_jntadr[body]), int(model.body_jntnum[body])
        joints.extend(range(first, first + count))
        body = int(model.body_parentid[body])
    return joints


class ContactGate:
    """Engaged before each tick's physics step; its flags hold until the next engage or :meth:`release`.

    Args:
        plant: The plant whose steps are gated.
        version: A counter the owner of the world's tree raises whenever it changes a box of it
            (:attr:`cosmos.obstacles.scene.ObstacleScene.version`). # (1,)
    """

    def __init__(self, plant: Plant, version: np.ndarray) -> None:
        model, data = plant.model, plant.data
        self._model, self._data = model, data
        hinge = int(mujoco.mjtJoint.mjJNT_HINGE)
        contype, conaffinity = model.body_contype.copy(), model.body_conaffinity.copy()
        bodies = []
        for body in range(1, model.nbody):
            if int(model.body_weldid[body]) == 0 or not (contype[body] or conaffinity[body]):
                continue
            chain = _chain_joints(model, body)
            if not chain or any(int(model.jnt_type[j]) != hinge for j in chain):
                continue
            others = [b for b in range(1, model.nbody) if b != body]
            if any((contype[body] & conaffinity[b]) or (contype[b] & conaffinity[body]) for b in others):
                continue  # it can touch another body: its contacts are not the world's alone
            bodies.append(body)
        bodies = [b for b in bodies if int(model.body_bvhadr[b]) >= 0][:62]  # a bit each in an int64
        joints = sorted({j for body in bodies for j in _chain_joints(model, body)})
        world_first, world_count = int(model.body_geomadr[0]), int(model.body_geomnum[0])
        compat = [
            sum(
                1 << k
                for k, b in enumerate(bodies)
                if (model.geom_contype[g] & conaffinity[b]) or (contype[b] & model.geom_conaffinity[g])
            )
            for g in range(world_first, world_first + world_count)
        ]
        size = gk.STATE_FOUND_Q + 2 * len(joints)  # a body's floats of state: found q and reach per joint
        header = [len(bodies), int(model.body_bvhadr[0]), len(joints), size, 0, 0, 0]
        ints: list[int] = header + [
            int(value)
            for b in bodies
            for value in (b, model.body_bvhadr[b], model.body_bvhnum[b], contype[b], conaffinity[b])
        ]
        ints += [int(model.jnt_qposadr[j]) for j in joints]
        ints += compat
        ints[gk.INT_STACK] = len(ints)
        ints += [0] * int(model.body_bvhnum[0])  # a walk's stack: at most every node of the world's tree
        ints[gk.INT_BODY_STACK] = len(ints)
        ints += [0] * max((int(model.body_bvhnum[b]) for b in bodies), default=0)  # and of a body's
        margins = float(np.max(model.geom_margin + model.geom_gap)) if model.ngeom else 0.0
        state = np.zeros(gk.STATE_Q + len(joints) + size * len(bodies))
        for k, body in enumerate(bodies):
            at = gk.STATE_Q + len(joints) + k * size + gk.STATE_FOUND_Q + len(joints)
            state[at : at + len(joints)] = [reach_m(model, body, j) for j in joints]
        state[gk.STATE_DT] = plant.dt_s
        state[gk.STATE_SLACK] = SLACK_M + 2.0 * margins
        state[gk.STATE_CAP] = CAP_M
        # MuJoCo's arrays (never moved while the model and data live) and the gate's, by address
        self._arrays = ArrayTable(
            model.body_contype,
            model.body_conaffinity,
            data.qpos,
            data.xipos,
            data.ximat,
            model.bvh_aabb,
            model.bvh_child,
            model.bvh_nodeid,
            version,
            state,
        )
        ints[gk.INT_ARRAYS] = len(ints)
        self._ints = np.array(ints + self._arrays.entries.tolist(), dtype=np.int64)
        self._state = state
        self.gated = 0
        """How many bodies the last :meth:`engage` switched off."""

    @property
    def bodies(self) -> int:
        """How many of the plant's bodies the gate may switch off."""
        return int(self._ints[gk.INT_BODIES])

    @property
    def body_ids(self) -> tuple[int, ...]:
        """The plant's bodies the gate may switch off (MuJoCo's body ids)."""
        rows = range(gk.INT_HEADER + gk.BODY_ID, gk.INT_HEADER + gk.BODY * self.bodies, gk.BODY)
        return tuple(int(self._ints[row]) for row in rows)

    def engage(self) -> None:
        """Before a tick's step: switch off the bodies clear of the world for it, the others on.

        The flags hold until the next :meth:`engage` or :meth:`release`: call
        :meth:`release` before colliding or stepping the plant otherwise.
        """
        self.gated = gk.engage_into(self._ints, self._data.time)

    def release(self) -> None:
        """Every body's compiled contype and conaffinity again; the next :meth:`engage` gates nothing."""
        gk.engage_into(self._ints, math.nan)  # no step follows: every flag back, every clearance forgotten
        self.gated = 0
