"""The bench loop: the cost of the servo loop, per phase, against a floor measured in the same run.

The workload is representative of a contact task: goal motion with a speed
limit on five axes while z is force-controlled (at 0 N in free space), with the
state recorded at its fixed rate into a real MCAP file. The floor is a Python
loop of only ``mj_step`` plus Pinocchio's ``computeAllTerms`` and the tool
Jacobian, replaying the workload's torques open loop: the same motion, no
control logic. Ratios are reported, not asserted.

The loop is timed as runs use it, without clocks inside the tick, in three runs
of the workload from the start, and the floor in three replays; each figure is
the best of its runs, as :mod:`timeit` reports (on a shared machine the slower
runs measure the neighbours; all runs are in the JSON). The cost of each phase
comes from the first run's second half: as many ticks again with a clock
around each phase (``timed_tick_us`` is their cost per tick, clocks included).
The language figure is the best of three compiles too. The
servo's compiled call copies the encoders and the wrist sensor from the plant's
live buffers itself, so ``sense`` is only reading the clock and taking the
sensor sample's noise row; the copies are counted in ``servo``.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from cosmos.execution.recording import LogRecorder
from cosmos.plant import Plant
from cosmos.robot_model import RobotModel, build_robot_model
from cosmos.runlog.writer import RunLog
from cosmos.runtime.loop import PhaseTimes, Runtime
from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

TICKS = 6000
WARMUP_TICKS = 500
REPEATS = 3


def _floor_tick_us(plant: Plant, robot: RobotModel, torques: np.ndarray, timed: int) -> float:
    """Replay ``torques`` open loop; the cost per step of the last ``timed`` steps, in [us].

    Each step is only: set the torques, ``mj_step``, ``computeAllTerms`` and the tool
    Jacobian. Replaying the workload's own torques gives the floor the workload's
    motion (an arm left without torques would fall onto the table, and the contact
    would make every step dearer than the workload's).
    """
    model, data = robot.model, robot.model.createData()
    mj_model, mj_data = plant.model, plant.data
    ctrl = mj_data.ctrl
    frame = robot.tool_frame
    step, all_terms, jacobian = mujoco.mj_step, pin.computeAllTerms, pin.getFrameJacobian
    world = pin.LOCAL_WORLD_ALIGNED
    untimed = len(torques) - timed
    for tau in torques[:untimed]:
        ctrl[:] = tau
        step(mj_model, mj_data)
    start = time.perf_counter_ns()
    for tau in torques[untimed:]:
        ctrl[:] = tau
        step(mj_model, mj_data)
        all_terms(model, data, mj_data.qpos, mj_data.qvel)
        jacobian(model, data, frame, world)
    return (time.perf_counter_ns() - start) / timed / 1e3


def _workload_torques(robot: RobotModel, ticks: int) -> np.ndarray:
    """The joint torques of the workload, tick by tick, in [N m] (an untimed run). # (ticks, 6)."""
    plant = Plant()
    runtime = Runtime(plant, robot, Rates())
    runtime.set_setpoint(_workload_setpoint(runtime))
    torques = np.empty((ticks, 6))
    for row in torques:
        runtime.tick()
        row[:] = runtime.tau
    return torques


def _workload_setpoint(runtime: Runtime) -> ServoSetpoint:
    ev = runtime.evaluation
    target = ev.position + np.array((0.15, -0.10, -0.05))
    return ServoSetpoint(
        mode=MotionMode.GOAL,
        position=target,
        rotation_to_world=ev.rotation_tool_to_world,
        motion_axes=(True, True, False, True, True, True),
        start_s=runtime.time_s,
        max_speed=0.25,
    )


def _timed_workload(
    robot: RobotModel, rates: Rates, ticks: int, phases: PhaseTimes | None
) -> tuple[float, float]:
    """Run the workload from the start on a fresh plant; its cost per tick, in [us].

    After the warm-up, ``ticks`` ticks are timed without clocks inside them; with
    ``phases``, as many ticks again follow with a clock around each phase, and the
    second figure is their cost per tick, clocks included (else 0).
    """
    plant = Plant()
    with tempfile.TemporaryDirectory() as tmp:
        log = RunLog(
            Path(tmp) / "bench.mcap",
            program="bench",
            source=None,
            servo_hz=rates.servo_hz,
            param_hz=rates.param_hz,
            state_hz=rates.state_hz,
            model="puma560",
            seed=0,
        )
        runtime = Runtime(plant, robot, rates)
        runtime.recorder = LogRecorder(log, plant)
        runtime.set_setpoint(_workload_setpoint(runtime))
        for _ in range(WARMUP_TICKS):
            runtime.tick()
        start = time.perf_counter_ns()
        for _ in range(ticks):
            runtime.tick()
        elapsed_ns = time.perf_counter_ns() - start
        start = time.perf_counter_ns()
        if phases is not None:
            for _ in range(ticks):
                runtime.timed_tick(phases)
        timed_ns = time.perf_counter_ns() - start if phases is not None else 0
        log.close()
    return elapsed_ns / ticks / 1e3, timed_ns / ticks / 1e3


def measure(ticks: int = TICKS, repeats: int = REPEATS) -> dict[str, object]:
    """Run the workload and the floor ``repeats`` times each; return the figures (times in [us]).

    The loop's and the floor's costs are the best of their runs (as :mod:`timeit`
    reports): on a shared machine the slower runs measure the neighbours.
    """
    robot = build_robot_model()
    rates = Rates()
    phases = PhaseTimes()  # from the first run, in as many ticks again, with clocks around each phase
    runs = [_timed_workload(robot, rates, ticks, phases if i == 0 else None) for i in range(repeats)]
    runs_us = [tick for tick, _ in runs]
    torques = _workload_torques(robot, WARMUP_TICKS + ticks)
    floors_us = [_floor_tick_us(Plant(), robot, torques, ticks) for _ in range(repeats)]
    tick_us, floor_us = min(runs_us), min(floors_us)
    return {
        "ticks": ticks,
        "repeats": repeats,
        "servo_hz": rates.servo_hz,
        "param_hz": rates.param_hz,
        "ticks_per_second": 1e6 / tick_us,
        "real_time_factor": 1e6 / tick_us / rates.servo_hz,
        "tick_us": tick_us,
        "tick_us_runs": runs_us,
        "floor_tick_us": floor_us,
        "floor_tick_us_runs": floors_us,
        "ratio_to_floor": tick_us / floor_us,
        "phases_us": {name: ns / phases.ticks / 1e3 for name, ns in phases.ns.items()},
        "timed_tick_us": runs[0][1],
    }
