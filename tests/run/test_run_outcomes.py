"""Outcomes that are true (issue 14): every ending measured, every hazard stopped.

Each test runs a program in-process and judges the run on its own MCAP log: the
tool pose there is MuJoCo's tool site, and the goal orientations are computed
here from the RPY angles with the rotation written out by hand (R = Rz Ry Rx,
docs/language.md), not with the code under test.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from run_support import ProgramRun, run_in_process, write_program

from cosmos.errors import ProgramError
from cosmos.lang import compile_program
from cosmos.replay.timeline import statement_timeline
from cosmos.workcell import fixture_frames


def _rpy(roll_deg: float, pitch_deg: float, yaw_deg: float) -> np.ndarray:
    r, p, y = np.radians((roll_deg, pitch_deg, yaw_deg))
    rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


def _quat_matrix(quat_wxyz: np.ndarray) -> np.ndarray:
    w, x, y, z = quat_wxyz / np.linalg.norm(quat_wxyz)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return math.degrees(math.acos(np.clip((np.trace(a.T @ b) - 1) / 2, -1.0, 1.0)))


def _at(run: ProgramRun, t_s: float) -> int:
    """Index of the last state sample at or before ``t_s``."""
    return int(np.searchsorted(run.log.state.t, t_s + 1e-9)) - 1


def _outcome(run: ProgramRun, line: int) -> tuple[str, str, float]:
    event = next(e for e in run.log.events if e.line == line and e.kind in ("done", "stopped", "failed"))
    return event.kind, event.reason, event.t


def test_a_timed_move_the_arm_cannot_do_is_a_check_error(tmp_path: Path) -> None:
    """``MOVE TO ... IN 1 ms`` was "done" at 1 ms with the tool 515 mm from its goal, exit 0."""
    for program, shortest in (
        ("MOVE TO (0.4, 0.3, 0.3) IN 1 ms\nWAIT 0.5 s\n", "0.97 s"),  # from home: 516 mm
        ("MOVE BY (0, 0, 100 mm) IN 1e-300 s\n", "at least 0.001 s"),
        ("MOVE BY (0, 0, 100 mm) IN 0.2 s\n", "0.34 s"),
    ):
        with pytest.raises(ProgramError) as error:
            compile_program(program, "quick.cos", fixture_frames())
        assert shortest in error.value.message, error.value.message


def test_a_timed_move_the_arm_cannot_do_fails_before_moving(tmp_path: Path) -> None:
    """Where the start is only known at run time (after an UNTIL), the measured distance decides."""
    program = "MOVE BY (0, 0, -50 mm) UNTIL DISTANCE > 10 mm\nMOVE TO (0.4, 0.3, 0.3) IN 50 ms\nWAIT 0.2 s\n"
    run = run_in_process(write_program(tmp_path, "quick", program), tmp_path / "quick.mcap")
    assert run.returncode == 1, run.describe()
    kind, reason, t = _outcome(run, 2)
    assert kind == "failed" and "shortest feasible duration is" in reason, reason
    assert not run.events("done", line=2)
    start = run.events("start", line=2)[0].t
    x = run.log.state.x
    assert np.linalg.norm(x[_at(run, t + 0.2)] - x[_at(run, start)]) < 0.005  # no lunge


def _orientation_run(tmp_path: Path, name: str, program: str, goal: np.ndarray, line: int) -> None:
    run = run_in_process(write_program(tmp_path, name, program), tmp_path / f"{name}.mcap")
    kind, reason, t = _outcome(run, line)
    measured = _quat_matrix(run.log.state.quat[_at(run, t)])
    off_deg = _angle_deg(measured, goal)
    if kind == "done":
        assert off_deg < 1.0, f"'done' with the tool {off_deg:.1f} deg from its goal: {reason}"
    else:  # an honest failure names the measured orientation error
        assert kind == "failed" and "deg from its goal" in reason, run.describe()
        logged = float(reason.split(" deg from its goal")[0].split()[-1])
        assert abs(logged - off_deg) < 0.5, (logged, off_deg)


def test_done_means_the_measured_orientation_arrived_after_a_half_turn(tmp_path: Path) -> None:
    """The second MOVE was "done, settled 0.0 mm from its goal" with the tool 66 deg off."""
    program = (
        "MOVE TO (600 mm, -150 mm, 350 mm) RPY (180 deg, 0, 90 deg)\n"
        "MOVE TO (600 mm, -150 mm, 350 mm) RPY (180 deg, 0, -90 deg)\n"
    )
    _orientation_run(tmp_path, "half_turn", program, _rpy(180, 0, -90), 2)


def test_done_means_the_measured_orientation_arrived_on_a_tilt(tmp_path: Path) -> None:
    """``RPY (165 deg, -30 deg, 0)`` from tool-down was "done" 22.5 deg off its goal."""
    program = "MOVE TO (0.55, 0.0, 0.4) RPY (165 deg, -30 deg, 0)\n"
    _orientation_run(tmp_path, "tilt", program, _rpy(165, -30, 0), 1)


SPHERE = (
    "MOVE TO (0.5, 0.0, 0.4)\n"
    "OBSTACLE ball SPHERE AT (0.5, 0.6, 0.4) RADIUS 40 mm MOVING (0, -1 m/s, 0){extra}\n"
    "WAIT 1 s\n"
)


def test_a_sphere_through_the_tool_during_a_wait_is_a_protective_stop(tmp_path: Path) -> None:
    """A sphere at 1 m/s pushed the tool 160 mm while the WAIT reported "done", exit 0."""
    run = run_in_process(write_program(tmp_path, "sphere", SPHERE.format(extra="")), tmp_path / "s.mcap")
    assert run.returncode == 1, run.describe()
    kind, reason, t = _outcome(run, 3)
    assert kind == "failed" and reason.startswith("protective stop: "), reason
    assert run.events("protective_stop", line=3)
    start = run.events("start", line=3)[0].t
    # The sphere (0.6 m away, 1 m/s) reaches the tool about 0.55 s into the WAIT.
    assert 0.3 < t - start < 0.7, t - start
    x = run.log.state.x
    pushed = np.linalg.norm(x[_at(run, t)] - x[_at(run, start)])
    # The obstacle's field moves the arm aside on purpose (seed section 6); the sphere
    # pushed it 160 mm before the stops existed.
    assert pushed < 0.1, pushed


def test_a_sphere_that_touches_the_tool_is_named_as_a_collision(tmp_path: Path) -> None:
    """No collision event was logged for an obstacle running into the tool."""
    program = SPHERE.format(extra=" GAIN 0.000001")  # no repulsion to speak of
    run = run_in_process(write_program(tmp_path, "touch", program), tmp_path / "touch.mcap")
    assert run.returncode == 1, run.describe()
    kind, reason, _ = _outcome(run, 3)
    assert kind == "failed" and "hit obstacle 'ball' at" in reason, reason
    assert [e.reason for e in run.events("collision", line=3)][:1] in (
        ["tool touches ball"],
        ["link6 touches ball"],
    )
    assert run.events("protective_stop", line=3)


def test_an_until_that_fired_shows_the_value_that_fired_it(tmp_path: Path) -> None:
    """The summary said peak 0.4 N for a guarded move stopped by FORCE > 4 N, and the reason
    repeated the TIMEOUT clause."""
    program = (
        "MOVE TO table + (0, 0, 20 mm)\n"
        "MOVE BY (0, 0, -60 mm) SPEED 20 mm/s UNTIL FORCE > 4 N TIMEOUT 10 s\n"
    )  # the last statement: the run holds until the firing's sample is logged
    run = run_in_process(write_program(tmp_path, "guarded", program), tmp_path / "guarded.mcap")
    assert run.returncode == 0, run.describe()
    kind, reason, t = _outcome(run, 2)
    assert kind == "stopped", reason
    assert reason.startswith("UNTIL FORCE > 4 N: ") and "TIMEOUT" not in reason, reason
    fired_n = float(reason.split(": ")[1].split(" N")[0])
    assert fired_n >= 4.0  # the reason prints it to 0.1 N: a firing at 4.04 N reads 4.0
    row = next(r for r in statement_timeline(run.log) if r.line == 2)
    assert row.peak_force > 4.0, row.peak_force  # the sample at the firing is the stopped line's
    assert run.log.state.line[int(np.searchsorted(run.log.state.t, t - 1e-9))] == 2


def test_statement_text_keeps_its_final_parenthesis(tmp_path: Path) -> None:
    """``UNTIL (DISTANCE > 20 mm AND FORCE < 1 N)`` lost its ``)`` in plan, log and replay."""
    statement = "MOVE BY (0, 0, -50 mm) UNTIL (DISTANCE > 20 mm AND FORCE < 1 N)"
    run = run_in_process(write_program(tmp_path, "paren", statement + "\n"), tmp_path / "paren.mcap")
    assert {s.statement for s in run.log.segments} == {statement}
    assert {e.statement for e in run.log.events} == {statement}
    kind, reason, _ = _outcome(run, 1)
    assert kind == "stopped" and reason.startswith("UNTIL (DISTANCE > 20 mm AND FORCE < 1 N): "), reason


def test_a_guarded_moves_impact_after_its_firing_is_in_its_row_and_its_terms_read_whole(
    tmp_path: Path,
) -> None:
    """Catches the "stopped" event written before the arm has braked: the braking's samples carry
    the stopped line but fell outside its row, so docs/language.md's own guarded example showed
    100.2 N where its samples peaked at 209.1 N; and a parenthesised term's value read
    ``(FORCE Z -17.6 N`` in the reason."""
    program = (
        "MOVE TO table + (0, 0, 50 mm)\n"
        "MOVE BY (0, 0, -100 mm) SPEED 50 mm/s UNTIL DISTANCE > 40 mm AND FORCE > 5 N OR (FORCE Z < -3 N)\n"
        "WAIT 0.2 s\n"
    )
    run = run_in_process(write_program(tmp_path, "guard", program), tmp_path / "guard.mcap")
    kind, reason, _ = _outcome(run, 2)
    assert kind in ("stopped", "failed"), reason
    assert reason.count("(") == reason.count(")") and "(FORCE Z -" not in reason, reason
    state = run.log.state
    tagged = state.line == 2
    own_peak = float(np.max(np.linalg.norm(state.wrench[tagged, :3], axis=1)))
    row = next(r for r in statement_timeline(run.log) if r.line == 2)
    assert row.peak_force == pytest.approx(own_peak, rel=1e-9), (row.peak_force, own_peak)


def test_limit_force_sets_the_free_motion_limit(tmp_path: Path) -> None:
    """The free-motion force limit must be settable per program (``LIMIT FORCE``), and enforced.

    A move from rest puts the tool's own inertia on the wrist sensor (several N):
    within the default 20 N, beyond a LIMIT of 0.5 N.
    """
    motion = "MOVE BY (0, 0, -100 mm) SPEED 0.25 m/s\n"
    free = run_in_process(write_program(tmp_path, "free", motion), tmp_path / "free.mcap")
    assert free.returncode == 0, free.describe()
    limited = run_in_process(
        write_program(tmp_path, "lim", "LIMIT FORCE 0.5 N\n" + motion), tmp_path / "l.mcap"
    )
    assert limited.returncode == 1, limited.describe()
    kind, reason, _ = _outcome(limited, 2)
    assert kind == "failed" and "above this statement's limit of 0.5 N" in reason, reason
    assert limited.events("protective_stop", line=2)


def test_a_goal_blocked_by_a_joint_limit_names_the_joint(tmp_path: Path) -> None:
    """A goal blocked by a joint limit was reported as "out of the arm's reach".

    From home, tilting the tool 130 deg about world y needs joint 5 past its 100 deg
    limit whichever way the tool turns (turning -120 deg about the tool's own axis is
    not blocked: joint 6's 532 deg range allows it the long way round, and it arrives).
    """
    program = "MOVE TO (0.5963, -0.15005, 0.4575) RPY (180 deg, -130 deg, 0)\n"
    run = run_in_process(write_program(tmp_path, "joint5", program), tmp_path / "joint5.mcap")
    assert run.returncode == 1, run.describe()
    kind, reason, t = _outcome(run, 1)
    assert kind == "failed" and reason.endswith("joint 5 at its limit of 100 deg"), reason
    assert "reach" not in reason.split(";")[-1]
    q5_deg = math.degrees(run.log.state.q[_at(run, t), 4])
    assert 100.0 - 17.2 < q5_deg <= 100.0, q5_deg  # where the task gives up joint 5's share
    turn = "MOVE TO (0.5963, -0.15005, 0.4575) RPY (180 deg, 0, -120 deg)\n"
    run = run_in_process(write_program(tmp_path, "joint6", turn), tmp_path / "joint6.mcap")
    assert run.returncode == 0, run.describe()


def test_a_roll_at_the_wrist_singularity_is_never_called_out_of_reach(tmp_path: Path) -> None:
    """A 15 deg roll at q5 = 1 deg ran the tool 105 mm sideways and failed as "out of reach".

    The first MOVE puts the wrist 1 deg from its singularity (the pose is the forward
    kinematics of home with q5 = 1 deg, read from MuJoCo); the second rolls the tool
    15 deg about world x in place. Whatever the controller makes of it, a "done" must be
    measured true, and a failure must name the real cause, with the tool stopped near
    the 50 mm the path supervision allows.
    """
    program = (
        "MOVE TO (0.7402, -0.1500, 0.5185) RPY (180 deg, -46 deg, 0 deg)\n"
        "MOVE TO (0.7402, -0.1500, 0.5185) RPY (-158.907 deg, -44.014 deg, -15.004 deg)\n"
    )
    run = run_in_process(write_program(tmp_path, "roll", program), tmp_path / "roll.mcap")
    start = run.events("start", line=2)[0].t
    assert abs(math.degrees(run.log.state.q[_at(run, start), 4])) < 3.0  # at the singularity
    kind, reason, t = _outcome(run, 2)
    x = run.log.state.x
    travel = np.linalg.norm(x[_at(run, start) : _at(run, t) + 1] - x[_at(run, start)], axis=1).max()
    if kind == "done":
        measured = _quat_matrix(run.log.state.quat[_at(run, t)])
        assert _angle_deg(measured, _rpy(-158.907, -44.014, -15.004)) < 1.0, reason
        assert travel < 0.05, travel
    else:
        assert "out of the arm's reach" not in reason, reason
        assert "singularity" in reason, reason
        assert travel < 0.06, travel  # stopped at the path limit, not 105 mm away


INSERT_IN_AIR = """\
MOVE TO (0.5, 0.2, 0.5)
INSERT DOWN DEPTH 20 mm FORCE 10 N TIMEOUT 10 s
"""


def test_an_insert_that_touches_nothing_logs_no_contact(tmp_path: Path) -> None:
    """An INSERT in free air went its DEPTH in its approach and logged a ``contact`` event reading
    "depth 20.0 mm reached": a contact where the wrist, by the log's own samples, felt none. It
    fails, touching nothing (tests/run/test_run_insert_air.py), and logs no contact."""
    run = run_in_process(write_program(tmp_path, "air", INSERT_IN_AIR), tmp_path / "air.mcap")
    assert run.returncode == 1, run.describe()
    kind, reason, _ = _outcome(run, 2)
    assert kind == "failed" and reason.startswith("went its DEPTH of 20.0 mm touching nothing"), reason
    on_line = run.log.state.line == 2
    felt = np.linalg.norm(run.log.state.wrench[on_line, :3], axis=1).max()
    assert felt < 2.0, felt  # what the approach counts as a touch
    assert run.events("contact", line=2) == [], run.describe()


def test_a_relative_goal_out_of_reach_fails_before_the_arm_moves(tmp_path: Path) -> None:
    """A SLIDE (or MOVE BY) whose goal's wrist centre is beyond the arm's reach fails at once, saying so.

    Bug: only absolute goals were checked; ``SLIDE +X BY 30 mm`` from table + (140 mm, -230 mm)
    stretched the arm to its reach, turned the tool 7.5 deg and failed "did not arrive within 1 s
    after the 0.6 s its SPEED takes", without a cause.
    """
    program = "MOVE TO table + (140 mm, -230 mm, 30 mm)\nCONTACT DOWN FORCE 10 N\nSLIDE +X BY 30 mm\n"
    run = run_in_process(write_program(tmp_path, "edge", program), tmp_path / "edge.mcap")
    assert run.returncode == 1
    failed = [e for e in run.log.events if e.kind == "failed"]
    assert failed[0].line == 3
    assert failed[0].reason.startswith("cannot reach its goal: the pose is out of the arm's reach")
    slide = [e.t for e in run.log.events if e.line == 3 and e.kind == "start"][0]
    assert failed[0].t - slide < 0.01  # before the arm moves


def test_an_arm_swinging_about_its_goal_is_not_said_to_have_stopped(tmp_path: Path) -> None:
    """Catches the stall's message saying "stopped 0.2 mm and 0.0 deg from its goal for 2 s" of
    an arm swinging 2.5 mm either side of its goal at 90 mm/s (a model error of 0.5, past the
    controller's margins): the log's own speeds at the failure say it never stopped."""
    import cosmos

    log = tmp_path / "swing.mcap"
    run = cosmos.run("MOVE TO table + (0, 0, 150 mm)\n", log=log, vary={"model_error": 0.5})
    assert not run.ok
    reason = run.outcome.reason if run.outcome is not None else ""
    assert reason.startswith("cannot settle at its goal: ") and "stopped" not in reason, reason
    state = run.record.state
    last = state.t >= state.t[-1] - 0.5
    speeds = np.linalg.norm(state.v[last, :3], axis=1)
    assert speeds.max() > 0.02, speeds.max()  # the log's own samples: swinging, not at rest
