"""The protective stops' compiled tick, judged against the stops' documented rules (issue 20).

The force, the path and the drives are judged in one compiled call a tick
(:func:`cosmos.execution.supervision_kernel.supervise_tick`); each test here would catch a stop
that no longer fires once its check moved there, or fires at another tick.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from cosmos.execution.fixture_reach import FixtureReach
from cosmos.execution.supervision import Supervisor
from cosmos.lang import compile_program
from cosmos.obstacles import obstacle_scene_xml
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.workcell import HOME_Q, fixture_frames
from tests.arm_helpers import solve_ik

ROBOT = build_robot_model()
LIMITS = np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm)


def _started(
    program: str, goal_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
) -> tuple[Supervisor, np.ndarray]:
    """A supervisor started on the program's first segment at home; the tool point [m]."""
    plant = Plant(obstacle_scene_xml())
    supervisor = Supervisor(plant, LIMITS, 0.001)
    segment = compile_program(program, "s.cos", fixture_frames()).segments[0]
    position = plant.data.site_xpos[-1].copy()
    supervisor.start(segment, position, position + np.array(goal_offset))
    return supervisor, position


def test_the_force_stop_needs_three_ticks_in_a_row_over_the_limit() -> None:
    """A free motion's limit is 20 N: 25 N at the wrist for three ticks in a row is a stop, at the third;
    two ticks over and one under start the count again (a one-tick impact is no stop). Catches a
    force check that stopped firing, fired at once, or kept its count across a tick under the limit."""
    supervisor, position = _started("WAIT 1 s\n")
    over, under, torque = np.array([15.0, 20.0, 0.0, 0.0, 0.0, 0.0]), np.zeros(6), np.zeros(6)
    pattern = [over, over, under, over, over]
    assert [supervisor.check(i * 0.001, w, torque, position) for i, w in enumerate(pattern)] == [None] * 5
    stop = supervisor.check(0.005, over, torque, position)
    assert stop is not None
    assert (
        stop.message == "protective stop: 25.0 N at the wrist at 0.01 s, above this statement's limit of 20 N"
    )


def test_the_path_stop_fires_off_the_line_and_not_while_a_field_acts() -> None:
    """A tool 60 mm off its commanded line (beyond 50 mm) is a stop within the 4 ticks of the slow look;
    while an obstacle's field acts it is none. Catches the path's look lost from the compiled tick, or
    the field's exemption lost."""
    supervisor, position = _started("MOVE BY (100 mm, 0, 0)\n", (0.1, 0.0, 0.0))
    off = position + np.array([0.05, 0.06, 0.0])
    still, wrench = np.zeros(6), np.zeros(6)
    supervisor.field_acting = True
    assert all(supervisor.check(i * 0.001, wrench, still, off) is None for i in range(8))
    supervisor.field_acting = False
    stops = [supervisor.check(i * 0.001, wrench, still, off) for i in range(4)]
    found = [stop for stop in stops if stop is not None]
    assert len(found) == 1 and stops[-1] is found[0]
    assert found[0].message.startswith("protective stop: the tool is 60 mm off its path at 0.00 s")
    assert supervisor.check(0.01, wrench, still, position + np.array([0.05, 0.0, 0.0])) is None


def test_a_drive_at_the_negative_limit_is_counted_as_one_at_the_positive() -> None:
    """The drives' look compares |tau| with each drive's own limit: drive 5 at minus its limit stops the
    arm after 50 ms, though every other drive's limit is higher. Catches a sign or an index lost."""
    supervisor, position = _started("WAIT 1 s\n")
    torque = np.zeros(6)
    torque[4] = -LIMITS[4]
    stops = [supervisor.check(i * 0.001, np.zeros(6), torque, position) for i in range(60)]
    first = next(i for i, stop in enumerate(stops) if stop is not None) + 1
    assert 50 <= first <= 54
    assert str(stops[first - 1]).count(f"drive 5 at its torque limit of {LIMITS[4]:g} N m") == 1


@pytest.mark.parametrize("distance_m", [0.0005, 0.02, 0.1])
def test_the_tool_near_a_fixture_as_every_pairs_distance_says(distance_m: float) -> None:
    """The look for a fixture near the tool measures only the pairs whose world boxes come that close.
    Compared with MuJoCo's distance of every pair of the tool's and the fixtures' geoms, in arm
    poses from 20 cm above the table down to the peg in the hole's bore. Catches a box turned the
    wrong way, a half size left out, or a pair dropped that is near."""
    plant = Plant()
    supervisor = Supervisor(plant, LIMITS, 0.001)
    tool_fixture = supervisor._pair_kinds == 1  # TOOL_FIXTURE
    reach = FixtureReach(plant, supervisor._roles == 2, tool_fixture)  # Role.TOOL
    model, data = plant.model, plant.data
    pairs = np.argwhere(np.triu(tool_fixture)).tolist()
    rng = np.random.default_rng(7)
    hole = fixture_frames()["hole"]
    answers = []
    for _ in range(24):  # the peg's tip about the hole: in its bore, at its rim, above it, beside it
        offset = np.array([rng.uniform(-0.03, 0.03), rng.uniform(-0.03, 0.03), rng.uniform(-0.01, 0.12)])
        plant.reset(solve_ik(ROBOT, pin.SE3(hole.rotation, hole.position + offset), np.array(HOME_Q)))
        fromto = np.zeros(6)
        every = any(
            mujoco.mj_geomDistance(model, data, a, b, distance_m, fromto) < distance_m for a, b in pairs
        )
        assert reach.within(distance_m) == every
        answers.append(every)
    assert len(set(answers)) == 2  # both answers met


def test_the_compiled_tick_reads_mujocos_contacts_through_one_type_of_view() -> None:
    """The compiled tick takes the contacts as a strided view, whatever their count: numba types one
    contact's view (or none's) as contiguous and converts it in Python at every call (1 us a tick in
    free motion), and a run may compile each kernel for one signature only. Catches the rows read
    not being MuJoCo's own at every count (none, one, several), in order, or a contiguous view."""
    from numba import typeof

    plant = Plant()
    supervisor = Supervisor(plant, LIMITS, 0.001)
    hole = fixture_frames()["hole"]
    counts = set()
    for offset in (0.0002, 0.003, -0.002, 0.02):
        target = hole.position + np.array([offset, 0.0, -0.004])
        plant.reset(solve_ik(ROBOT, pin.SE3(hole.rotation, target), np.array(HOME_Q)))
        for _ in range(100):  # the drives off: it sags into the fixture, touching in changing places
            mujoco.mj_step(plant.model, plant.data)
            ncon = plant.data.ncon
            counts.add(min(ncon, 2))
            supervisor.check(0.0, np.zeros(6), np.zeros(6), plant.data.site_xpos[-1])
            view = supervisor._pairs.kernel_view
            assert typeof(view).layout == "A"
            assert view[:ncon].tolist() == plant.data.contact.geom.tolist()
    assert counts == {0, 1, 2}, counts


def test_the_tick_takes_only_arrays_of_its_declared_types() -> None:
    """The tick skips numba's dispatch only for live views of its declared types: a float32 wrench or a
    strided one is refused with numba's TypeError, as through its dispatch, and the same wrench as a
    float64 buffer then stops at the third tick over the limit with 25 N. Catches the fast call handed
    memory of another type or layout (it would read a float32 buffer's bytes as float64 values)."""
    supervisor, position = _started("WAIT 1 s\n")
    torque, wrench = np.zeros(6), np.array([15.0, 20.0, 0.0, 0.0, 0.0, 0.0])
    for unlike in (wrench.astype(np.float32), np.repeat(wrench, 2)[::2]):
        with pytest.raises(TypeError, match="No matching definition"):
            supervisor.check(0.0, unlike, torque, position)
    stops = [supervisor.check(i * 0.001, wrench, torque, position) for i in range(3)]
    assert stops[:2] == [None, None]
    assert stops[2] is not None and stops[2].message.startswith("protective stop: 25.0 N at the wrist")
