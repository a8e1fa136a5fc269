"""A segment's tick check (:meth:`Supervisor.checker`) against :meth:`Supervisor.check` (issue 20).

The executor's loop asks ``check(t_s)``, the live views listed once at the segment's start, where
it asked ``supervisor.check(t_s, wrench, torque, position)`` every tick. Two supervisors on one
plant, one asked each way, must find the same stop at the same tick; a supervisor whose class
adds to the tick's check (the gripper's slip) must still have it asked.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin

from cosmos.execution.protective_stop import ProtectiveStop, StopKind
from cosmos.execution.supervision import Supervisor
from cosmos.lang import compile_program
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.workcell import HOME_Q, fixture_frames
from tests.arm_helpers import solve_ik

ROBOT = build_robot_model()


def _started(plant: Plant, source: str, cls: type[Supervisor] = Supervisor) -> list[Supervisor]:
    """Two supervisors of ``cls`` on ``plant``, each started on the first segment of ``source``."""
    limits = np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm)
    segment = compile_program(source, "s.cos", fixture_frames()).segments[0]
    position = plant.data.site_xpos[-1].copy()
    supervisors = [cls(plant, limits, 0.001) for _ in range(2)]
    for supervisor in supervisors:
        supervisor.start(segment, position, position)
    return supervisors


def test_the_segments_check_finds_what_check_finds_as_the_contacts_come_and_go() -> None:
    """An arm falling limp onto the hole fixture's chamfer under a guarded WAIT (its contacts
    allowed, their count changing step by step), then pressing over its force limit: each tick
    both ways give the same stop or none. Catches the contacts' view not made again when their
    count changes (a segment's check reading a stale count's records), or the views listed once
    but read as others (the torque as the wrench)."""
    plant = Plant()
    hole = fixture_frames()["hole"]
    target = hole.position + np.array([0.003, 0.0, -0.004])
    plant.reset(solve_ik(ROBOT, pin.SE3(hole.rotation, target), np.array(HOME_Q)))
    asked, each_tick = _started(plant, "WAIT 1 s UNTIL FORCE Z > 80 N\n")
    wrench, torque, position = np.zeros(6), np.zeros(6), plant.data.site_xpos[-1]
    check = asked.checker(wrench, torque, position)
    counts, found = set(), []
    for i in range(400):
        mujoco.mj_step(plant.model, plant.data)
        counts.add(plant.data.ncon)
        wrench[2] = 0.0 if i < 300 else 200.0  # over the guarded WAIT's limit from tick 300
        stop, expected = check(i * 0.001), each_tick.check(i * 0.001, wrench, torque, position)
        assert (stop and stop.message) == (expected and expected.message), i
        if stop is not None:
            found.append((i, stop.kind))
            break
    assert len(counts) > 2, counts  # the count changed, and held
    assert found == [(302, StopKind.FORCE)]  # three ticks over the limit


class _Slipping(Supervisor):
    """A supervisor whose class adds a hazard to every tick's check, as the gripper's does."""

    def check(
        self, t_s: float, wrench: np.ndarray, torque: np.ndarray, position: np.ndarray
    ) -> ProtectiveStop | None:
        return super().check(t_s, wrench, torque, position) or ProtectiveStop(StopKind.FORCE, "slipped")


def test_a_subclass_check_is_still_asked() -> None:
    """Catches the segment's check going straight to the compiled tick past a subclass's
    :meth:`check` (a held object's slip never looked at)."""
    plant = Plant()
    supervisor, _ = _started(plant, "WAIT 1 s\n", _Slipping)
    position = plant.data.site_xpos[-1]
    stop = supervisor.checker(np.zeros(6), np.zeros(6), position)(0.0)
    assert stop is not None and stop.message == "slipped"
