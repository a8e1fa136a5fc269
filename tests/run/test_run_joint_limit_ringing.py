"""A rotation into a joint limit turns smoothly or fails cleanly: no wrist ringing (issue 14, item 2).

The Panda: from tool down, a 175 deg turn about z takes joint 7 from 1 deg toward its -166 deg
limit. The task kept driving joint 7 (its limit projection used J^+'s row while the controller
moves the joints by Jbar), the joint-limit potential threw it back, and for 8 s the wrist rang in
a 0.26 s limit cycle (joint 7 between -153 and -162 deg, the tool's angular velocity reversing
by 1.4 rad/s) until the elbow had crept out of the way: the turn took 11.4 s. The PUMA: a tilt
that needs joint 5 past its limit rang the same way (the task's damping of the joint it gave up
was given up with it) before failing. Judged from the runs' own logs.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from run_support import ProgramRun, run_in_process, write_program

TURN = """\
ROBOT panda
MOVE TO (0.5, 0, 0.4) RPY (180 deg, 0, 0)
MOVE TO (0.5, 0, 0.4) RPY (180 deg, 0, 175 deg)
"""
TURN_RAD = math.radians(175.0)
ANGULAR_SPEED_LIMIT = 1.0
"""The goal motion's default angular speed limit [rad/s]."""
TURN_BOUND_S = TURN_RAD / ANGULAR_SPEED_LIMIT + 1.5
"""3.05 s at the speed limit, plus 1.5 s to speed up, hand joint 7's share to the other joints
and settle within 1 deg (the unbounded turn of line 2's kind takes 0.2-0.4 s more than its
angle over the limit)."""
REVERSAL_BOUND_RAD_S = 0.2
"""The most the tool may turn back along the way it turned a moment before [rad/s]."""


def largest_reversal(run: ProgramRun, line: int, window_s: float = 0.25) -> float:
    """The largest speed [rad/s] at which the tool turns back along a direction it turned at
    (faster than 0.2 rad/s) within the previous ``window_s``, during ``line``."""
    state = run.log.state
    rows = np.flatnonzero(state.line == line)
    t, omega = state.t[rows], state.v[rows, 3:]
    worst = 0.0
    for i in range(len(t)):
        speed = float(np.linalg.norm(omega[i]))
        if speed < 0.2:
            continue
        later = omega[i : np.searchsorted(t, t[i] + window_s)]
        worst = max(worst, float(-(later @ omega[i]).min() / speed))
    return worst


def _outcome(run: ProgramRun, line: int) -> tuple[str, str]:
    event = next(e for e in run.log.events if e.line == line and e.kind in ("done", "stopped", "failed"))
    return event.kind, event.reason


def test_a_turn_past_joint_7s_reach_is_smooth_on_the_panda(tmp_path: Path) -> None:
    """Line 3 arrives within TURN_BOUND_S (main: 11.4 s), the tool never turns back faster than
    REVERSAL_BOUND_RAD_S (main: 1.45 rad/s, the ringing), and joint 7 stays inside its range
    (-2.8973 rad, Franka's datasheet)."""
    run = run_in_process(write_program(tmp_path, "turn", TURN), tmp_path / "turn.mcap")
    assert run.returncode == 0, run.describe()
    kind, _ = _outcome(run, 3)
    assert kind == "done", run.describe()
    state = run.log.state
    times = state.t[state.line == 3]
    assert times[-1] - times[0] < TURN_BOUND_S, f"line 3 took {times[-1] - times[0]:.2f} s"
    reversal = largest_reversal(run, 3)
    assert reversal < REVERSAL_BOUND_RAD_S, f"the tool turned back at {reversal:.2f} rad/s"
    assert state.q[:, 6].min() > -2.8973, f"joint 7 reached {math.degrees(state.q[:, 6].min()):.1f} deg"


def test_a_tilt_joint_5_forbids_fails_without_ringing_on_the_puma(tmp_path: Path) -> None:
    """From home, 130 deg about world y needs joint 5 past its 100 deg limit: the MOVE fails
    naming joint 5, and on the way the tool never turns back faster than REVERSAL_BOUND_RAD_S
    (main: 1.18 rad/s, joint 5 ringing at its limit before the failure)."""
    program = "MOVE TO (0.5963, -0.15005, 0.4575) RPY (180 deg, -130 deg, 0)\n"
    run = run_in_process(write_program(tmp_path, "joint5", program), tmp_path / "joint5.mcap")
    assert run.returncode == 1, run.describe()
    kind, reason = _outcome(run, 1)
    assert kind == "failed" and reason.endswith("joint 5 at its limit of 100 deg"), reason
    reversal = largest_reversal(run, 1)
    assert reversal < REVERSAL_BOUND_RAD_S, f"the tool turned back at {reversal:.2f} rad/s"
