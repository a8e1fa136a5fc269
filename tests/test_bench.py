"""cosmos bench: the figures issue 3 asks for, and a floor that moves as the workload does."""

import numpy as np

from cosmos.commands.bench import _floor_tick_us, _workload_setpoint, _workload_torques, measure
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.runtime.loop import Runtime
from cosmos.runtime.rates import Rates


def test_floor_replays_the_workload_motion():
    """Open loop, the workload's torques give the workload's trajectory (MuJoCo is deterministic):
    the floor times the same physics, not an arm fallen onto the table."""
    robot = build_robot_model()
    torques = _workload_torques(robot, 400)
    controlled = Runtime(Plant(), robot, Rates())
    controlled.set_setpoint(_workload_setpoint(controlled))
    for _ in range(400):
        controlled.tick()
    replay = Plant()
    assert _floor_tick_us(replay, robot, torques, 100) > 0.0
    np.testing.assert_array_equal(replay.data.qpos, controlled.plant.data.qpos)
    assert replay.data.ncon == 0


def test_measure_reports_the_phases_and_the_floor():
    figures = measure(ticks=300, repeats=2)
    assert len(figures["tick_us_runs"]) == len(figures["floor_tick_us_runs"]) == 2
    assert figures["tick_us"] == min(figures["tick_us_runs"])
    assert figures["floor_tick_us"] == min(figures["floor_tick_us_runs"])
    assert set(figures["phases_us"]) == {"sense", "parameters", "servo", "physics", "record"}
    assert all(cost > 0.0 for cost in figures["phases_us"].values())
    assert figures["timed_tick_us"] >= sum(figures["phases_us"].values())
    assert figures["ticks_per_second"] == 1e6 / figures["tick_us"]
    assert figures["ratio_to_floor"] == figures["tick_us"] / figures["floor_tick_us"]
