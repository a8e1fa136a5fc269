"""The executor's obstacle world and field watch: what they tell stays right when their looks are cheap.

The world redraws only the MOVING obstacles on ``/scene`` (kept as a list when obstacles come
and go), and the field watch stays quiet while nothing nears the tool's link. Each is checked
against numbers worked out here: where the program's ball is at each drawing, and the largest
deviation fed to the watch.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from cosmos.execution.field_on_tool import FieldOnToolWatch
from cosmos.execution.obstacles import SCENE_EVERY
from cosmos.execution.session import Session
from cosmos.lang import compile_program
from cosmos.obstacles.field import Influence
from cosmos.osc.null_space import DEFAULT_ABSORPTION
from cosmos.runlog.scene import Primitive, Sphere
from cosmos.runtime.null_space import LinkField, NullSpaceTerms
from cosmos.runtime.rates import Rates
from cosmos.workcell import fixture_frames

BALL_AT_M, BALL_MPS = np.array((0.45, 0.25, 0.45)), np.array((0.0, 0.1, 0.0))
PROGRAM = """\
OBSTACLE crate BOX AT (0.3, -0.4, 0.2) SIZE (0.1, 0.1, 0.1)
OBSTACLE ball SPHERE AT (0.45, 0.25, 0.45) RADIUS 30 mm MOVING (0, 0.1 m/s, 0)
WAIT 130 ms
OBSTACLE REMOVE ball
WAIT 100 ms
OBSTACLE ball SPHERE AT (0.45, 0.25, 0.45) RADIUS 30 mm MOVING (0, 0.1 m/s, 0)
WAIT 100 ms
"""


def test_only_moving_obstacles_are_redrawn_where_they_are(tmp_path: Path) -> None:
    """Between its OBSTACLE statements the ball is redrawn every SCENE_EVERY ticks at
    ``p0 + v (t - t_added)`` (the program's numbers), the crate at rest never, and nothing while
    the ball is out of the scene. Catches the world's list of moving obstacles not refreshed when
    one is removed (the ball drawn back in) or added again (its motion no longer drawn)."""
    plan = compile_program(PROGRAM, "world.cos", fixture_frames())
    drawn: list[tuple[float, list[Primitive], list[str]]] = []
    with Session("world.cos", PROGRAM, tmp_path / "run.mcap", Rates()) as session:
        log = session.obstacles.log
        assert log is not None
        scene = log.scene

        def record(t: float, add: Sequence[Primitive] = (), remove: Sequence[str] = ()) -> None:
            drawn.append((t, list(add), list(remove)))
            scene(t, add=add, remove=remove)

        log.scene = record  # type: ignore[method-assign]
        dt_s = 1.0 / session.runtime.rates.servo_hz
        session.executor.run(plan)
    removed_s = next(t for t, _, remove in drawn if remove == ["ball"])
    added_again_s = next(t for t, add, _ in drawn if add and t > removed_s)
    assert 0.12 < removed_s < 0.14 and added_again_s > removed_s
    redraws = [(t, add) for t, add, _ in drawn if add and t > 0.0]  # the first statements' at 0 s
    for t, add in redraws:
        assert [p.id for p in add] == ["ball"], add  # never the crate
        assert not removed_s <= t < added_again_s, f"drawn at {t} s while removed"
        added_s = 0.0 if t < removed_s else added_again_s
        assert isinstance(add[0], Sphere)
        np.testing.assert_allclose(add[0].position, BALL_AT_M + BALL_MPS * (t - added_s), atol=1e-12)
    period_s = SCENE_EVERY * dt_s
    first_wait = [t for t, _ in redraws if t < removed_s]
    assert len(first_wait) == 3  # 130 ms: at 40, 80 and 120 ms
    np.testing.assert_allclose(np.diff(first_wait), period_s, atol=1e-9)
    assert [t for t, _ in redraws if t > added_again_s], "the ball added again is not redrawn"


def test_the_watch_is_quiet_until_an_obstacle_nears_the_tools_link() -> None:
    """The field acts on the tool's link (link6) while the nearest link of every obstacle is
    another: looks with the same inputs measure nothing. Then the ball is nearest link6: each look
    measures the tool's deviation, and when the field lets go the event gives the largest of those
    fed here (2.0 mm). Catches a watch left quiet when new influences name the tool's link (no
    event), or measuring at every quiet look."""
    watch = FieldOnToolWatch()
    null_space = NullSpaceTerms(1.0, DEFAULT_ABSORPTION)  # no share of the links' field on the tool
    field = LinkField(tool=np.array((0.0, 0.0, 0.0, 0.0, 0.0, 0.4)), links=np.zeros(6))
    measured: list[float] = []
    deviations_m = iter((0.0005, 0.002, 0.0015))

    def deviation_m() -> float:
        measured.append(next(deviations_m))
        return measured[-1]

    far = (Influence("lamp", "link3", 0.06, 1.0),)
    assert [watch.update(null_space, field, deviation_m, far) for _ in range(5)] == [""] * 5
    assert measured == []
    for _ in range(3):
        near = (Influence("ball", "link6", 0.02, 5.0),)  # a new evaluation: a new tuple
        assert watch.update(null_space, field, deviation_m, near) == ""
    assert len(measured) == 3
    told = watch.update(null_space, field, deviation_m, ())
    most_mm = max(measured) * 1e3
    assert told == f"the field of obstacle 'ball' moved the tool up to {most_mm:.1f} mm off its path"
    assert told.endswith("2.0 mm off its path")


def test_an_episode_measures_the_tool_at_every_look_and_tells_the_largest_deviation() -> None:
    """A link's field reaches the tool (share 20 %): the episode begins; while the share stays at or
    above 1 % every look measures the tool (the same field, or a new one at an evaluation), and when
    it falls below, the event gives the largest of the deviations fed here (3.0 mm, met mid-episode).
    Catches an episode that stops measuring, measures twice a look, or misses its end."""
    watch = FieldOnToolWatch()
    null_space = NullSpaceTerms(1.0, DEFAULT_ABSORPTION)
    field = LinkField(np.zeros(6), np.ones(6), 0.03, "link4", "ball")
    fed_m = [0.0008, 0.0012, 0.0030, 0.0021, 0.0017, 0.0009]
    measured: list[float] = []

    def deviation_m() -> float:
        measured.append(fed_m[len(measured)])
        return measured[-1]

    influences = (Influence("ball", "link4", 0.03, 9.0),)
    assert watch.update(null_space, field, deviation_m, influences) == ""  # no share on the tool yet
    told = []
    for share, new_field in (
        (0.2, False),
        (0.05, False),
        (0.02, False),
        (0.05, True),
        (0.01, False),
        (0.005, False),
    ):
        null_space.link_share_to_tool = share
        if new_field:  # an evaluation's field, the same forces
            field = LinkField(np.zeros(6), np.ones(6), 0.03, "link4", "ball")
        told.append(watch.update(null_space, field, deviation_m, influences))
    assert measured == fed_m  # one measure a look, from the episode's first to its last
    assert told[0].startswith(
        "link4 is 30 mm from ball: the null space cannot keep it clear, 20% of its field"
    )
    assert told[1:5] == [""] * 4
    assert told[5] == (
        f"link4 clear of ball through the null space again; the field moved the tool up to "
        f"{max(fed_m) * 1e3:.1f} mm off its path"
    )
