"""The executor's looks at the field among obstacles: at an evaluation or a new setpoint, not every tick.

Between two parameter evaluations the field, its influences and the null space's share of the
links' field on the tool stay as they are unless a setpoint changes (a VIA leg's next goal), so the
executor's loop looks at them only then (:mod:`cosmos.execution.obstacle_ticks`), and measures the
tool at every tick only while an episode of the field on the tool goes on. Both are checked against
the runtime's own evaluations and setpoints, and the log's episode, spied on.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import cosmos
from cosmos.execution.field_on_tool import FieldOnToolWatch
from cosmos.execution.obstacle_ticks import ObstacleTicks
from cosmos.execution.obstacles import MINIMUM_CHECK_EVERY, ObstacleWorld
from cosmos.execution.supervision import Supervisor
from cosmos.runtime.loop import Runtime

VIA_PROGRAM = (
    "OBSTACLE ball SPHERE AT (0.3, -0.5, 0.9) RADIUS 40 mm\n"
    "MOVE TO table + (0, 0, 150 mm) VIA table + (0, 0, 250 mm), table + (50 mm, 0, 200 mm)\n"
)
PANDA_NULL_SPACE = Path(cosmos.__file__).resolve().parents[1] / "programs" / "panda_null_space.cos"


def _us(t_s: float) -> int:
    return round(t_s * 1e6)


def test_the_field_is_looked_at_after_each_evaluation_and_each_via_legs_setpoint(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """A MOVE ... VIA two points among obstacles: the loop looks at the field at the tick after each
    of the runtime's evaluations (125 Hz), and at the tick after each VIA leg's new setpoint, which
    changes the null space's share without an evaluation; at no other tick. Catches a VIA leg's
    setpoint not looked at until the next evaluation (up to 7 ticks with a stale share), and a loop
    looking at every tick again."""
    looks: list[int] = []
    evaluated: list[int] = []
    restarted: list[int] = []
    setpoints: list[int] = []
    field, evaluate = ObstacleTicks.field, Runtime._evaluate
    reset_clocks, set_setpoint = Runtime.reset_clocks, Runtime.set_setpoint

    def spied_field(self: ObstacleTicks) -> str:
        looks.append(_us(self._world.runtime.time_s))
        return field(self)

    def spied_evaluate(self: Runtime, now: float) -> None:
        evaluated.append(_us(now + 1.0 / self.rates.servo_hz))  # the tick's end: where the loop looks
        evaluate(self, now)

    def spied_reset(self: Runtime) -> None:
        restarted.append(_us(self.time_s))
        reset_clocks(self)

    def spied_setpoint(self: Runtime, setpoint: object) -> None:
        setpoints.append(_us(self.time_s))
        set_setpoint(self, setpoint)  # type: ignore[arg-type]

    monkeypatch.setattr(ObstacleTicks, "field", spied_field)
    monkeypatch.setattr(Runtime, "_evaluate", spied_evaluate)
    monkeypatch.setattr(Runtime, "reset_clocks", spied_reset)
    monkeypatch.setattr(Runtime, "set_setpoint", spied_setpoint)
    run = cosmos.run(VIA_PROGRAM, log=tmp_path / "via.mcap")
    assert run.ok, run.outcome
    legs = [t for t in setpoints if t not in restarted]  # not a segment's first
    assert len(legs) == 2, setpoints
    after_legs = [t + 1000 for t in legs]  # the next tick (1 ms)
    assert set(after_legs) <= set(looks), (after_legs, looks)
    assert set(after_legs) - set(evaluated), "evaluations looked at every leg anyway: no test of the legs"
    assert sorted(looks) == sorted(set(evaluated) | set(after_legs))


def test_an_episode_tells_the_largest_deviation_of_all_its_ticks(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """panda_null_space: the ball's field on link 4 reaches the tool from 1.297 s to 1.889 s (the
    log's two field_on_tool events). The largest deviation the second one tells is the largest of
    the tool's distances from its path measured here, in Python, after each tick of the episode, to
    the last bit; it falls between two looks at the field. Catches an episode measured only at the
    looks (one tick in eight: the supervisor's compiled tick keeps the largest in between)."""
    after_tick: dict[int, float] = {}
    looks: list[int] = []
    told: list[float] = []
    checked: list[tuple[Supervisor, np.ndarray]] = []
    tick, checker, field, links = (
        Runtime.tick,
        Supervisor.checker,
        ObstacleTicks.field,
        FieldOnToolWatch._links,
    )

    def spied_checker(self: Supervisor, wrench: np.ndarray, torque: np.ndarray, position: np.ndarray) -> Any:
        checked[:] = [(self, position)]
        return checker(self, wrench, torque, position)

    def spied_tick(self: Runtime) -> float:
        now = tick(self)
        if checked:
            supervisor, position = checked[0]
            after_tick[_us(now)] = supervisor.path_deviation_m(position.copy())  # a copy: in Python
        return now

    def spied_field(self: ObstacleTicks) -> str:
        looks.append(_us(self._world.runtime.time_s))
        return field(self)

    def spied_links(self: FieldOnToolWatch, *args: Any) -> str:
        reason = links(self, *args)
        if reason.startswith("link4 clear of ball"):
            told.append(self._deviation_m)
        return reason

    monkeypatch.setattr(Supervisor, "checker", spied_checker)
    monkeypatch.setattr(Runtime, "tick", spied_tick)
    monkeypatch.setattr(ObstacleTicks, "field", spied_field)
    monkeypatch.setattr(FieldOnToolWatch, "_links", spied_links)
    run = cosmos.run(PANDA_NULL_SPACE, log=tmp_path / "panda.mcap")
    assert run.ok, run.outcome
    begins, ends = (_us(e.t) for e in run.events if e.kind == "field_on_tool")
    episode = {t: d for t, d in after_tick.items() if begins <= t <= ends}
    assert len(episode) == (ends - begins) // 1000 + 1
    largest_at = max(episode, key=episode.__getitem__)
    assert largest_at not in looks, "the largest at a look: this run cannot tell the ticks between"
    assert told == [episode[largest_at]]


def test_a_local_minimum_is_found_on_the_last_leg_of_a_move_via(tmp_path: Path) -> None:
    """The wall across the path (test_run_obstacles' TRAPPED) met on the last leg of a MOVE ... VIA,
    the VIA point passed at once: the move fails as stuck in the wall's local minimum, as it does
    without the VIA point, not 1.2 s later as unable to reach its goal. Catches the loop's looks
    for a minimum (every 25 ticks of the last leg, by tick number) not started when the last leg is."""
    program = (
        "SPEED 0.2 m/s\n"
        "OBSTACLE wall BOX AT (450 mm, -150 mm, 420 mm) SIZE (20 mm, 600 mm, 400 mm)\n"
        "MOVE TO (300 mm, -150 mm, 457 mm) VIA (560 mm, -150 mm, 457 mm) TIMEOUT 20 s\n"
    )
    with pytest.warns(cosmos.CosmosWarning, match="joint 3 would reach its limit"):
        run = cosmos.run(program, log=tmp_path / "trapped.mcap")
    assert not run.ok
    assert "stuck in a local minimum of the potential field near obstacle 'wall'" in str(run.outcome)


def test_a_goal_motion_looks_for_a_minimum_every_25_ticks(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """panda_null_space's MOVE among the ball (from 0 s, 2041 ticks): the local minimum is looked
    for at its 25th tick, its 50th, ... and no other (the detector's rate, MINIMUM_CHECK_EVERY),
    though the loop enters its rarer looks only from the look for collisions before each. Catches a
    look missed or doubled when the collisions' ticks (every 10th) and the minima's fall together."""
    looked: list[int] = []
    local_minimum = ObstacleWorld.local_minimum

    def spied(self: ObstacleWorld, *args: Any) -> Any:
        looked.append(_us(self.runtime.time_s))
        return local_minimum(self, *args)

    monkeypatch.setattr(ObstacleWorld, "local_minimum", spied)
    run = cosmos.run(PANDA_NULL_SPACE, log=tmp_path / "panda.mcap")
    assert run.ok, run.outcome
    assert looked == [k * MINIMUM_CHECK_EVERY * 1000 for k in range(1, 2041 // MINIMUM_CHECK_EVERY + 1)]
