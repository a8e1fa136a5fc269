"""A goal motion's compiled "on its way" test against the judge's float arithmetic it replaced (issue 20).

Most ticks of a goal motion the monitor's judge finds the tool too fast, or slow but off its goal
point, and looks no further (:meth:`cosmos.execution.monitor.SegmentMonitor._goal_reached`);
that test is compiled now (:mod:`cosmos.execution.goal_gate`). Written out below in Python
floats as the judge computed it before (a speed's square root against the speed tolerance,
the squared error on the motion axes against the squared position tolerance), it must give the
same answer at every tick of real goal motions on both arms, and at the tolerances themselves:
the same answer at every tick is the same judgement at every tick, so the same arrival tick,
outcome and reason.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from run_support import run_in_process, write_program

import cosmos.execution.monitor as monitor_module
from cosmos.execution.goal_gate import GoalGate
from cosmos.execution.monitor import JUDGE_MOVING_EVERY, SETTLE_S, SegmentMonitor, Snapshot
from cosmos.lang import compile_program
from cosmos.workcell import fixture_frames


def _on_its_way_in_floats(
    position: list[float],
    velocity: list[float],
    goal: tuple[float, ...],
    speed_mps: float,
    tolerance_m: float,
    axes: list[tuple[float, ...]],
) -> bool:
    """The judge's test as it was in Python: too fast, or off the goal point on the motion axes."""
    vx, vy, vz = velocity[:3]
    if math.sqrt(vx * vx + vy * vy + vz * vz) > speed_mps:
        return True
    ex, ey, ez = position[0] - goal[0], position[1] - goal[1], position[2] - goal[2]
    total = 0.0
    for ax, ay, az in axes:
        component = ax * ex + ay * ey + az * ez
        total += component * component
    return total > tolerance_m * tolerance_m


PUMA_MOVES = """\
SPEED 0.2 m/s
MOVE TO table + (-50 mm, 0, 30 mm)
CONTACT DOWN FORCE 10 N SPEED 20 mm/s TIMEOUT 5 s
SLIDE +X BY 20 mm SPEED 10 mm/s
MOVE TO (550 mm, 50 mm, 400 mm) RPY (180 deg, -20 deg, 0)
"""
PANDA_MOVES = """\
ROBOT panda
SPEED 0.25 m/s
MOVE BY (0, 0, 40 mm)
MOVE BY (0, 60 mm, -20 mm) IN 1 s
"""


@pytest.mark.parametrize("source", [PUMA_MOVES, PANDA_MOVES], ids=["puma", "panda"])
def test_the_gate_answers_as_the_judges_floats_at_every_tick_of_real_moves(
    source: str, tmp_path: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every tick a goal motion's gate is asked, on the executor's live arrays (listed by address),
    it must pass the tick by exactly when the judge's former test did on the same snapshot: not one
    of every ``JUDGE_MOVING_EVERY`` ticks counted, and on its way by the floats above. Catches an
    array listed in another's place (the twist read as the tool point), a stale address after a new
    segment's snapshot, the angular speed counted in the speed, an axis of the task frame left out,
    a tolerance compared unsquared, or the count off by one: each changes the tick a motion
    arrives at, or its reason."""
    answers: list[tuple[bool, bool]] = []

    class Recorded(GoalGate):
        def __init__(self, *gate: Any) -> None:
            super().__init__(*gate)
            compiled, counted = self.listed, [0]

            def listed(table: np.ndarray) -> bool:
                counted[0] += 1
                snap = self.snapshot
                on_its_way = _on_its_way_in_floats(snap.position.tolist(), snap.velocity.tolist(), *gate[:4])
                answers.append((bool(compiled(table)), bool(counted[0] % JUDGE_MOVING_EVERY) and on_its_way))
                return answers[-1][0]

            self.listed = listed

    monkeypatch.setattr(monitor_module, "GoalGate", Recorded)
    run = run_in_process(write_program(tmp_path, "moves", source), tmp_path / "moves.mcap")
    assert run.returncode == 0, run.describe()
    assert [i for i, (answer, expected) in enumerate(answers) if answer != expected] == []
    judged = sum(not answer for answer, _ in answers)
    assert len(answers) / JUDGE_MOVING_EVERY + 40 < judged < len(answers) - 300  # arrivals among them


def test_the_gate_at_its_tolerances_and_on_any_array() -> None:
    """At the tolerances themselves the tool is not "on its way" (speed equal to the speed
    tolerance, error equal to the position tolerance); a NaN speed is not "too fast" and goes on to
    the position, as the float comparisons do. The same answers on listed arrays (the executor's)
    and on arrays numba must convert (a strided view). Catches ``>=`` for ``>``, the tolerance's
    square taken after the sum, or the two call paths parting."""
    rng = np.random.default_rng(7)
    axes = [(1.0, 0.0, 0.0), (0.0, 0.6, 0.8)]
    goal, speed_mps, tolerance_m = (0.0, -0.1, 0.3), 0.005, 0.001  # x: its error is exact
    cases = [
        ([tolerance_m, -0.1, 0.3], [speed_mps, 0.0, 0.0, 3.0, 0.0, 0.0]),  # at both tolerances
        ([tolerance_m * 1.0000001, -0.1, 0.3], [0.0] * 6),  # just off
        ([0.0, -0.1, 0.3], [speed_mps * 1.0000001, 0.0, 0.0, 0.0, 0.0, 0.0]),  # just too fast
        ([0.0, -0.1, 0.3], [math.nan, 0.0, 0.0, 0.0, 0.0, 0.0]),
        ([0.0, -0.1 + 0.8, 0.3 - 0.6], [0.0] * 6),  # off along the axis the task frame leaves free
    ]
    for _ in range(300):
        position = np.add(goal, rng.normal(0.0, 0.001, 3))
        cases.append((position.tolist(), rng.normal(0.0, 0.004, 6).tolist()))
    listed, strided = (
        GoalGate(goal, speed_mps, tolerance_m, axes, 7),
        GoalGate(goal, speed_mps, tolerance_m, axes, 7),
    )
    answers = []
    for k, (position, velocity) in enumerate(cases, start=1):
        expected = (
            _on_its_way_in_floats(position, velocity, goal, speed_mps, tolerance_m, axes) and k % 7 != 0
        )
        snap = SimpleNamespace(position=np.array(position), velocity=np.array(velocity))
        assert listed.list(snap) and listed.snapshot is snap  # the ticks after call the compiled function
        answer = bool(listed.listed(listed.table))
        other = SimpleNamespace(position=np.repeat(position, 2)[::2], velocity=np.repeat(velocity, 2)[::2])
        assert answer == strided.passes(other) == expected, (k, position, velocity)
        assert listed.ticks == strided.ticks == k
        assert listed.settling_broken() == strided.settling_broken() == expected
        answers.append(expected)
    assert answers[:5] == [False, True, True, False, False]
    assert 50 < sum(answers) < len(answers) - 50


def test_a_tick_passed_by_breaks_the_settling_as_a_judged_one_does() -> None:
    """A goal motion at its goal and at rest for 10 ticks, off it by 2 mm for one, back from the
    next: it arrives ``SETTLE_S`` after it came back, asked every tick (:attr:`judge`) or through
    its gate as the executor's loop asks it (:attr:`judged` on the ticks the gate lets through).
    Catches the settling started before the tick passed by kept (an arrival 10 ticks early), or
    the gate's counts and the judge's parting."""
    plan = compile_program("MOVE TO (0.5, 0.1, 0.4) RPY (180 deg, 0, 0)\n", "m.cos", fixture_frames())
    goal = (np.array([0.5, 0.1, 0.4]), np.diag([1.0, -1.0, -1.0]))
    arrivals = []
    for through_gate in (False, True):
        monitor = SegmentMonitor(plan.segments[0], 0.0, goal[0], 0.0, goal[0], None, goal, lambda: "")
        assert monitor.gate is not None and monitor.idle_until_s == -math.inf
        position = goal[0].copy()
        snap = Snapshot(0.0, position, goal[1], np.zeros(6), np.zeros(6))
        assert monitor.gate.list(snap)
        for tick in range(1, 100):
            snap.t_s = 0.001 * tick
            position[2] = goal[0][2] + (0.002 if tick == 11 else 0.0)
            if through_gate:
                gate = monitor.gate
                outcome = None if gate.listed(gate.table) else monitor.judged(snap)
            else:
                outcome = monitor.judge(snap)
            if outcome is not None:
                arrivals.append((tick, outcome.reason))
                break
    back, settle_ticks = 12, round(SETTLE_S / 0.001)
    assert arrivals == [(back + settle_ticks, "arrived: 0.0 mm and 0.0 deg from its goal")] * 2
