"""The stall progress a goal motion's monitor counts: the rotation left the way the arm turns."""

from __future__ import annotations

import numpy as np

from cosmos.execution.monitor import JUDGE_MOVING_EVERY, SegmentMonitor, Snapshot
from cosmos.lang import compile_program
from cosmos.osc.orientation import so3_exp, so3_log, unwrap_rotation_vector
from cosmos.workcell import fixture_frames


def test_the_rotation_left_is_unwraps_choice_at_every_judgement_through_pi() -> None:
    """Catches the monitor's short cut (the short way taken without asking the unwrap while both
    angles are well under pi) choosing differently from :func:`unwrap_rotation_vector`: a turn
    through 180 deg would then count its progress from the wrong side and stall, or never stall."""
    plan = compile_program("MOVE TO (0.5, 0.1, 0.4) RPY (0, 0, 0)\n", "m.cos", fixture_frames())
    segment = plan.segments[0]
    goal = (np.array([0.5, 0.1, 0.4]), np.eye(3))
    position = np.array([0.5, 0.1, 0.4])
    monitor = SegmentMonitor(segment, 0.0, position, 0.0, position, None, goal, lambda: "")
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    velocity = np.array([0.5, 0.0, 0.0, 0.0, 0.0, 1.0])  # moving: only the sampled judgement runs
    expected = None
    for k, angle in enumerate(np.linspace(0.2, 2.0 * np.pi - 0.2, 400)):
        rotation = so3_exp(axis * angle)
        log = so3_log(rotation)
        expected = log if expected is None else unwrap_rotation_vector(log, expected)
        monitor._gate.ticks = JUDGE_MOVING_EVERY - 1  # this check is a judgement
        assert monitor.check(Snapshot(0.001 * k, position, rotation, velocity, np.zeros(6))) is None
        assert monitor._turn is not None
        np.testing.assert_array_equal(monitor._turn, expected)
    assert expected is not None and np.linalg.norm(expected) > np.pi  # it kept turning the long way


def test_far_under_pi_the_unwrap_keeps_the_short_way() -> None:
    """The monitor's short cut, checked against the unwrap itself on random pairs: both angles
    together under pi - 0.1 rad, the unwrap returns the short way (``log``) itself."""
    rng = np.random.default_rng(3)
    for _ in range(2000):
        log = rng.normal(size=3)
        log *= rng.uniform(0.0, np.pi) / np.linalg.norm(log)
        previous = rng.normal(size=3)
        room = np.pi - 0.1 - np.linalg.norm(log)
        if room <= 0:
            continue
        previous *= rng.uniform(0.0, room) / np.linalg.norm(previous)
        assert unwrap_rotation_vector(log, previous) is log


def test_a_slide_s_arrival_reports_its_motion_axes_not_its_force_axis() -> None:
    """Catches the reason reporting the whole error where the judge reads the motion axes: a held
    block slid 40 mm was "arrived: 1.4 mm and 0.2 deg from its goal", over the 1 mm tolerance, the
    1.35 mm being its force axis's depth (what the force set, not a goal), 0.3 mm its motion's."""
    plan = compile_program("CONTACT DOWN FORCE 10 N\nSLIDE +X BY 40 mm\n", "s.cos", fixture_frames())
    (segment,) = [s for s in plan.segments if s.kind.value == "slide"]
    goal = (np.array([0.64, -0.25, 0.20]), np.diag([1.0, -1.0, -1.0]))
    start = goal[0] - np.array([0.04, 0.0, 0.0])
    monitor = SegmentMonitor(segment, 0.0, start, 0.0, start, None, goal, lambda: "")
    position = goal[0] + np.array([-0.0003, 0.0, -0.00135])
    outcome = None
    for k in range(100):
        outcome = monitor.check(Snapshot(0.001 * k, position, goal[1], np.zeros(6), np.zeros(6)))
        if outcome is not None:
            break
    assert outcome is not None and outcome.reason == "arrived: 0.3 mm and 0.0 deg from its goal", outcome


def test_the_arrival_in_floats_reports_numpys_error() -> None:
    """The arrival is judged in Python floats (a 3 x 3 product and a log, 3 us where arrays cost
    10-25 us). Catches its error differing from NumPy's (:func:`cosmos.execution.arrival.goal_error`
    on the task frame's motion axes): a product transposed, a row of the task frame taken for a
    column, a rotation error of the wrong sign, for goals and task frames turned every way."""
    from cosmos.execution.arrival import goal_error
    from cosmos.execution.monitor import SETTLE_S

    plan = compile_program("MOVE TO (0.5, 0.1, 0.4) RPY (0, 0, 0)\n", "m.cos", fixture_frames())
    segment = plan.segments[0]
    rng = np.random.default_rng(9)
    for _ in range(50):
        goal = (np.array([0.5, 0.1, 0.4]), so3_exp(rng.normal(0.0, 1.5, 3)))
        position = goal[0] + rng.normal(0.0, 0.0003, 3)
        rotation = so3_exp(rng.normal(0.0, 0.004, 3)).dot(goal[1])
        monitor = SegmentMonitor(segment, 0.0, position, 0.0, position, None, goal, lambda: "")
        error = goal_error(position, rotation, *goal)
        r_t = np.array(segment.frame_rotation).T
        expected = (
            f"arrived: {np.linalg.norm(r_t.dot(error.position_m)) * 1e3:.1f} mm and "
            f"{np.degrees(np.linalg.norm(r_t.dot(error.rotation_rad))):.1f} deg from its goal"
        )
        outcome = None
        for k in range(round(SETTLE_S / 0.001) + 2):
            outcome = outcome or monitor.check(
                Snapshot(0.001 * k, position, rotation, np.zeros(6), np.zeros(6))
            )
        assert outcome is not None and outcome.reason == expected


def test_a_wait_is_judged_from_its_end_on_and_ends_at_the_same_tick() -> None:
    """Catches the executor's skip of a WAIT's judge (``idle_until_s``) skipping the tick it ends
    at, or a WAIT with an UNTIL or TIMEOUT skipped at all (those are judged every tick): on the
    servo's grid from odd start times, the judge is called from the tick whose ``t - start >=
    duration`` (its own test) or one before it (rounding), finding nothing until that tick."""
    plan = compile_program("WAIT 0.3 s\nWAIT 0.3 s UNTIL FORCE Z > 5 N\n", "w.cos", fixture_frames())
    plain, until = plan.segments
    position, goal = np.zeros(3), (np.zeros(3), np.eye(3))
    for start_s in (0.0, 0.1, 1.7, 2.3, 12.345, 99.999):
        monitor = SegmentMonitor(plain, start_s, position, start_s, position, None, goal, str)
        ticks, t_s = [], start_s
        for _ in range(400):  # as the plant adds its steps
            ticks.append(t_s)
            t_s += 0.001
        called = [t for t in ticks if t >= monitor.idle_until_s]
        still = (np.eye(3), np.zeros(6), np.zeros(6))
        done = [t for t in called if monitor.judge(Snapshot(t, position, *still))]
        first_done = next(t for t in ticks if t - start_s >= 0.3)
        assert done[0] == first_done and called.index(first_done) <= 1
        waiting = SegmentMonitor(until, start_s, position, start_s, position, None, goal, str)
        assert waiting.idle_until_s == -np.inf
