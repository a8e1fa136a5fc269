"""MuJoCo's own contact force on the hand, an independent figure to judge the wrist sensor and the law by.

:class:`ToolContactProbe` sums, at every physics step of the runs made inside ``with``, the
contact forces between the bodies of the ``tool`` subtree (the peg, or the gripper's housing and
fingers) and everything else (``mujoco.mj_contactForce``): the force the tool applies, world [N].
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
from run_support import StepProbe, write_program

from cosmos.runlog.reader import RunRecord, read_log


def _subtree(model: mujoco.MjModel, root: int) -> frozenset[int]:
    """The bodies of ``root``'s subtree, ``root`` included."""
    bodies = set()
    for body in range(model.nbody):
        parent = body
        while parent > 0 and parent != root:
            parent = int(model.body_parentid[parent])
        if parent == root:
            bodies.add(body)
    return frozenset(bodies)


class ToolContactProbe(StepProbe):
    """The force the tool's subtree applies through its contacts, world [N], every physics step."""

    def __init__(self) -> None:
        super().__init__()
        self.t: list[float] = []
        self.force: list[np.ndarray] = []
        self._hand: tuple[Any, frozenset[int]] | None = None

    def sample(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> None:
        """Sum the tool's contacts now."""
        if self._hand is None or self._hand[0] is not model:
            tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tool")
            self._hand = (model, _subtree(model, tool))
        hand = self._hand[1]
        total = np.zeros(3)
        for i in range(data.ncon):
            contact = data.contact[i]
            first = int(model.geom_bodyid[contact.geom[0]]) in hand
            if first == (int(model.geom_bodyid[contact.geom[1]]) in hand):
                continue  # the hand on itself, or two other bodies
            mujoco.mj_contactForce(model, data, i, self._force)
            on_second = contact.frame.reshape(3, 3).T.dot(self._force[:3])  # geom 1 pushes geom 2
            total += on_second if first else -on_second
        self.t.append(t)
        self.force.append(total)

    def mean_between(self, start_s: float, end_s: float) -> np.ndarray:
        """The mean contact force over ``(start_s, end_s]``, world [N]. # (3,)"""
        t = np.asarray(self.t)
        window = (t > start_s) & (t <= end_s)
        assert window.any(), (start_s, end_s)
        return np.asarray(self.force)[window].mean(axis=0)


def run_with_probe(
    tmp_path: Path, name: str, source: str, seed: int, ideal: bool
) -> tuple[RunRecord, ToolContactProbe]:
    """Run ``source`` as ``cosmos run`` does (it must succeed): its log, and the tool's contact forces."""
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates

    program, log = write_program(tmp_path, name, source), tmp_path / f"{name}.mcap"
    err = io.StringIO()
    with (
        ToolContactProbe() as probe,
        contextlib.redirect_stdout(io.StringIO()),
        contextlib.redirect_stderr(err),
    ):
        returncode = run_program(program, log, Rates(), seed, ideal=ideal)
    assert returncode == 0, err.getvalue()
    return read_log(log), probe
