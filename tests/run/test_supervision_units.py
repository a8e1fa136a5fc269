"""The protective stops' and the stall diagnosis' pieces, without a run; and the checker's limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.errors import ProgramError
from cosmos.execution.arrival import stall_cause
from cosmos.execution.expected import path_deviation
from cosmos.execution.supervision import SATURATION_S, Supervisor
from cosmos.lang import compile_program
from cosmos.obstacles import obstacle_scene_xml
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.workcell import HOME_Q, fixture_frames

ROBOT = build_robot_model()
TOOL_DOWN = np.diag([1.0, -1.0, -1.0])


def test_path_deviation_is_the_distance_to_the_segment_on_the_given_axes() -> None:
    """A tool pushed sideways off its line must be measured as off it, not along it."""
    start, end = np.zeros(3), np.array([1.0, 0.0, 0.0])
    axes = np.eye(3)
    assert path_deviation(np.array([0.5, 0.03, 0.04]), start, end, axes) == pytest.approx(0.05)
    assert path_deviation(np.array([1.5, 0.0, 0.0]), start, end, axes) == pytest.approx(0.5)  # past the end
    only_y = np.array([[0.0, 1.0, 0.0]])  # z force-controlled: not the path's business
    assert path_deviation(np.array([0.5, 0.03, 0.04]), start, end, only_y) == pytest.approx(0.03)


def _cause(q: np.ndarray, goal: np.ndarray, push_n: float = 0.0) -> str:
    jacobian = np.eye(6)
    return stall_cause(q, ROBOT.q_lower_rad, ROBOT.q_upper_rad, jacobian, push_n, goal, TOOL_DOWN)


def test_a_joint_at_its_limit_is_named() -> None:
    """A goal blocked by a joint limit was reported as "out of the arm's reach"."""
    q = np.array(HOME_Q)
    q[5] = ROBOT.q_upper_rad[5] - math.radians(0.5)
    assert _cause(q, np.array([0.5, 0.0, 0.4])) == "joint 6 at its limit of 266 deg"


def test_the_wrist_singularity_is_named() -> None:
    """A roll at q5 = 1 deg that could not progress was reported as out of reach."""
    q = np.array(HOME_Q)
    q[4] = math.radians(1.0)
    assert "wrist is at its singularity (joint 5 at 1.0 deg" in _cause(q, np.array([0.5, 0.0, 0.4]))


def test_out_of_reach_only_when_it_is() -> None:
    """ "Out of reach" must come from the goal's distance, not from any stall."""
    assert "out of the arm's reach" in _cause(np.array(HOME_Q), np.array([2.0, 0.0, 0.5]))
    assert "blocked, pushing 9.0 N" in _cause(np.array(HOME_Q), np.array([0.5, 0.0, 0.4]), push_n=9.0)


def _supervising_a_wait() -> tuple[Supervisor, np.ndarray, np.ndarray]:
    """A supervisor started on a WAIT at home; the drives' limits [N m] and the tool point [m]."""
    plant = Plant(obstacle_scene_xml())
    limits = np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm)
    supervisor = Supervisor(plant, limits, 0.001)
    plan = compile_program("WAIT 1 s\n", "w.cos", fixture_frames())
    position = plant.data.site_xpos[-1].copy()
    supervisor.start(plan.segments[0], position, position)
    return supervisor, limits, position


def test_a_drive_at_its_limit_for_50_ms_is_a_protective_stop() -> None:
    """Three drives sat at their torque limits while an obstacle pushed the arm, without a word."""
    supervisor, limits, position = _supervising_a_wait()
    torque = np.zeros(6)
    torque[2] = -limits[2]
    ticks = round(SATURATION_S / 0.001)
    stops = [supervisor.check(i * 0.001, np.zeros(6), torque, position) for i in range(ticks + 5)]
    first = next(i for i, stop in enumerate(stops) if stop is not None) + 1
    assert ticks <= first <= ticks + 4, first  # looked at every 4th tick: 50 to 54 ms
    stop = stops[first - 1]
    assert stop is not None
    assert stop.message.startswith("protective stop: drive 3 at its torque limit of 89.4 N m for 52 ms")


def test_a_drive_that_leaves_its_limit_starts_counting_again() -> None:
    """Catches the drives' count surviving a drive's dip below its limit: the look at the drives is
    skipped while every torque is below the lowest limit, and a count left standing then would stop
    the arm 50 ms after the *first* of two short saturations (30 ms, a dip of 8 ms, 30 ms)."""
    supervisor, limits, position = _supervising_a_wait()
    at_limit = np.zeros(6)
    at_limit[0] = limits[0]
    pattern = [at_limit] * 30 + [np.zeros(6)] * 8 + [at_limit] * 30 + [np.zeros(6)] * 8
    stops = [supervisor.check(i * 0.001, np.zeros(6), tau, position) for i, tau in enumerate(pattern)]
    assert stops == [None] * len(pattern)
    stops = [supervisor.check(i * 0.001, np.zeros(6), at_limit, position) for i in range(60)]
    first = next(i for i, stop in enumerate(stops) if stop is not None) + 1
    assert 50 - 4 <= first <= 50 + 4, first
    assert str(stops[first - 1]).count("drive 1 at its torque limit") == 1


@pytest.mark.parametrize(
    ("program", "message"),
    [
        ("CONTACT DOWN FORCE 5000 N\n", "FORCE 5000 N is out of its range: at most 130 N (the wrist sensor"),
        ("SPEED 1e-300 m/s\n", "SPEED 1e-300 m/s is out of its range: at least 0.1 mm/s"),
        ("MOVE BY (1e305 mm, 0, 0)\n", "MOVE BY (1e305 mm, 0, 0) is out of its range: at most 2000 mm"),
        ("WAIT 1e308 s\n", "WAIT 1e308 s is out of its range: at most 3600 s (one hour)"),
        ("WAIT UNTIL FORCE > 2 N TIMEOUT 120 min\n", "TIMEOUT 120 min is out of its range: at most 3600 s"),
        ("MOVE BY (0, 0, 100 mm) IN 1e-300 s\n", "IN 1e-300 s is out of its range: at least 0.001 s"),
        ("MOVE BY (0, 0, 100 mm) IN 0.1 s\n", "the shortest feasible duration is 0.34 s"),
        (
            "MOVE BY (0, 0, -10 mm) UNTIL FORCE > 500 N\n",
            "UNTIL FORCE 500 N is out of its range: at most 130 N",
        ),
    ],
)
def test_requests_beyond_the_workcell_are_check_errors(program: str, message: str) -> None:
    """``CONTACT DOWN FORCE 5000 N`` was a warning and pressed 405 N; ``WAIT 1e308 s`` ran for ever."""
    with pytest.raises(ProgramError) as error:
        compile_program(program, "limits.cos", fixture_frames())
    assert message in error.value.message


def test_the_declared_home_pose_is_the_scenes() -> None:
    """The checker judges a first timed MOVE TO from a declared home pose: it must be the scene's."""
    from cosmos.capabilities import HOME_TOOL
    from cosmos.workcell import HOME_TOOL_POSITION, HOME_TOOL_ROTATION

    assert np.allclose(HOME_TOOL.position, HOME_TOOL_POSITION, atol=1e-9)
    assert np.allclose(HOME_TOOL.rotation, HOME_TOOL_ROTATION, atol=1e-9)


def test_limit_force_reaches_the_segments_after_it() -> None:
    """LIMIT FORCE must set the limit of the statements after it, and only those."""
    program = "WAIT 0.1 s\nLIMIT FORCE 40 N\nMOVE BY (0, 0, 10 mm)\nLIMIT FORCE 5 N\nWAIT 0.1 s\n"
    plan = compile_program(program, "limit.cos", fixture_frames())
    assert [s.force_limit_n for s in plan.segments] == [None, 40.0, 5.0]


def test_a_peg_pulled_out_of_its_hole_may_graze_the_bore() -> None:
    """After an INSERT, the MOVE that pulls the peg out grazes the 0.24 mm clearance bore after
    more than 50 ms free of it: that is no collision while the tool is within 50 mm of where the
    MOVE began; beyond, a touch is one. Catches the stop that failed 5 of 40 runs of
    peg_in_hole.cos ("tool hit fixture 'hole'" on its final MOVE BY: named as programs name it,
    not as the scene's body 'hole_fixture')."""
    import pinocchio as pin

    from tests.arm_helpers import solve_ik

    plant = Plant()
    limits = np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm)
    supervisor = Supervisor(plant, limits, 0.001)
    plan = compile_program(
        "CONTACT DOWN FORCE 5 N\nINSERT DOWN DEPTH 20 mm FORCE 10 N\nMOVE BY (0, 0, 40 mm)\n",
        "pull.cos",
        fixture_frames(),
    )
    insert, pull = plan.segments[-2], plan.segments[-1]
    hole = fixture_frames()["hole"]

    def put_tip(offset_m: float) -> np.ndarray:
        """The peg 10 mm into the hole, its tip ``offset_m`` off the axis along x; contacts found."""
        target = hole.position + np.array([offset_m, 0.0, -0.010])
        plant.reset(solve_ik(ROBOT, pin.SE3(hole.rotation, target), np.array(HOME_Q)))
        return target

    centred = put_tip(0.0)
    assert plant.data.ncon == 0  # the clearance: free in the bore
    supervisor.start(insert, centred, centred)
    supervisor.start(pull, centred, centred + np.array([0.0, 0.0, 0.04]))
    for i in range(80):  # 80 ms free of the walls
        assert supervisor.check(i * 0.001, np.zeros(6), np.zeros(6), centred) is None
    grazing = put_tip(0.0002)  # against the wall: 0.2 mm off the axis, 0.12 mm of radial clearance
    assert plant.data.ncon > 0
    assert supervisor.check(0.08, np.zeros(6), np.zeros(6), grazing) is None
    put_tip(0.0)
    for i in range(81, 160):  # free again, the tool 60 mm up (as if): clear of the hole
        supervisor.check(i * 0.001, np.zeros(6), np.zeros(6), centred + np.array([0.0, 0.0, 0.06]))
    put_tip(0.0002)
    stop = supervisor.check(0.16, np.zeros(6), np.zeros(6), centred + np.array([0.0, 0.0, 0.06]))
    assert stop is not None and "tool hit fixture 'hole'" in stop.message


def test_a_contacts_hold_keeps_the_statements_force_limit() -> None:
    """A CONTACT's hold starts touching what its own approach touched: that is no contact the
    statement began in, so its range stays twice its FORCE plus 30 N (docs/language.md,
    Protective stops). Catches the hold given the sensor's 130 N: a peg that slid off the
    hole's chamfer into the bore struck its bottom at 130 N, "above this statement's limit of
    130 N", for a CONTACT of 8 N."""
    import pinocchio as pin

    from tests.arm_helpers import solve_ik

    plant = Plant()
    limits = np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm)
    supervisor = Supervisor(plant, limits, 0.001)
    plan = compile_program("CONTACT DOWN FORCE 5 N\n", "c.cos", fixture_frames())
    approach, hold = plan.segments
    table = fixture_frames()["table"]
    start = plant.data.site_xpos[-1].copy()
    supervisor.start(approach, start, start)
    touching = table.position + np.array([0.0, 0.0, -0.0002])  # 0.2 mm into the table top
    plant.reset(solve_ik(ROBOT, pin.SE3(table.rotation, touching), np.array(HOME_Q)))
    assert plant.data.ncon > 0
    supervisor.start(hold, touching, touching)
    pressing = np.array([0.0, 0.0, -60.0, 0.0, 0.0, 0.0])  # over 2 x 5 + 30 N, under the rating
    stops = [supervisor.check(i * 0.001, pressing, np.zeros(6), touching) for i in range(3)]
    assert stops[-1] is not None and "above this statement's limit of 40 N" in stops[-1].message, stops


def test_the_kept_contact_view_reads_mujocos_own_contact_list() -> None:
    """The supervisor keeps its view of the contacts' geom pairs while their count stays the same
    (the bindings' list costs 0.5-1 us a tick in contact). Catches a view kept after MuJoCo wrote
    its contacts elsewhere, or one whose rows no longer match the count: every step of an arm
    falling limp onto the hole fixture's chamfer, its pairs must be MuJoCo's own, in order."""
    import mujoco
    import pinocchio as pin

    from cosmos.execution.contact_pairs import ContactPairs
    from cosmos.execution.supervision_kernel import TABLE_SIZE
    from tests.arm_helpers import solve_ik

    plant = Plant()
    pairs = ContactPairs(plant.data, np.zeros(TABLE_SIZE, dtype=np.int64))
    hole = fixture_frames()["hole"]
    counts = set()
    for offset in (0.0002, 0.003, -0.002):
        target = hole.position + np.array([offset, 0.0, -0.004])
        plant.reset(solve_ik(ROBOT, pin.SE3(hole.rotation, target), np.array(HOME_Q)))
        for _ in range(150):  # the drives off: it sags into the fixture, touching in changing places
            mujoco.mj_step(plant.model, plant.data)
            ncon = plant.data.ncon
            counts.add(ncon)
            assert pairs.update(ncon).tolist() == plant.data.contact.geom.tolist()
    assert len(counts) > 2  # the count changed, and held: both ways of the view were read


def test_the_compiled_slow_look_measures_as_the_path_stop_does() -> None:
    """The drives' and the path's looks every 4th tick are one compiled call. Catches its distance
    from the line differing from the float one's (:func:`off_line`, which the field's events report)
    or from NumPy's :func:`path_deviation`, the ends of the line not clamped, or a torque as large
    as the lowest limit (either sign) missed."""
    from cosmos.execution.expected import off_line
    from cosmos.execution.supervision_kernel import slow_look

    rng = np.random.default_rng(3)
    for _ in range(200):
        start, end, position = rng.normal(0.0, 0.2, 3), rng.normal(0.0, 0.2, 3), rng.normal(0.0, 0.3, 3)
        axes = np.linalg.qr(rng.normal(size=(3, 3)))[0][: rng.integers(1, 4)]
        line = end - start
        packed = np.array([*start, *line, float(line @ line)])
        torque = rng.normal(0.0, 10.0, 6)
        at_lowest, off = slow_look(torque, 15.0, position, packed, axes, True)
        floats = off_line(
            position.tolist(), tuple(start.tolist()), tuple(line.tolist()), float(line @ line), axes.tolist()
        )
        assert off == floats
        assert off == pytest.approx(path_deviation(position, start, end, axes), abs=1e-12)
        assert at_lowest == bool(np.any(np.abs(torque) >= 15.0))
    assert slow_look(np.array([0.0, -20.0]), 15.0, np.ones(3), np.zeros(7), np.eye(3), False) == (True, 0.0)
