"""Shared set-up for the runtime tests: an arm at a configuration, driven by setpoints.

The arm is the realistic plant (cosmos.realism: drawn model error, quantised encoders, the
velocity observer, the wrist sensor's bandwidth, bias and noise) of seed 0 unless a test asks
for the ideal one.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from cosmos.plant import Plant, SensorNoise
from cosmos.realism import PlantRealism
from cosmos.robot_model import RobotModel, build_robot_model
from cosmos.robots import PUMA560
from cosmos.runtime.loop import Runtime
from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

ROBOT = build_robot_model()
Q_NEAR = np.radians((0.0, 33.5, -177.1, 0.0, -36.4, 180.0))
"""The PUMA's tool down in front of the arm, away from its limits and singularities [rad]."""


def tool_pose(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The controller model's tool point and orientation at ``q``, world (Pinocchio's kinematics)."""
    data = ROBOT.model.createData()
    pin.framesForwardKinematics(ROBOT.model, data, q)
    placed = data.oMf[ROBOT.tool_frame]
    return placed.translation.copy(), placed.rotation.copy()


def plant_for_tests(ideal: bool = False, seed: int = 0, robot: RobotModel | None = None) -> Plant:
    """The realistic plant of ``seed`` (as ``cosmos run --seed``), or the ideal one, noiseless.

    ``robot``: another arm's controller model; its workcell is simulated ideal (the realistic
    plant is the PUMA's).
    """
    if robot is not None and robot is not ROBOT:
        return Plant(robot.description.scene_xml)
    if ideal:
        return Plant()
    return Plant(sensor_noise=SensorNoise(seed), realism=PlantRealism.drawn(seed, PUMA560))


def runtime_at(
    q: np.ndarray | None = None,
    rates: Rates | None = None,
    ideal: bool = False,
    seed: int = 0,
    robot: RobotModel = ROBOT,
) -> Runtime:
    """A runtime on a fresh plant (:func:`plant_for_tests`), the arm at rest at ``q`` (home if None),
    holding its pose; ``robot``: the controller's model (the PUMA's by default)."""
    plant = plant_for_tests(ideal, seed, robot)
    plant.reset(q)
    runtime = Runtime(plant, robot, rates or Rates())
    hold(runtime)
    return runtime


def hold(runtime: Runtime) -> ServoSetpoint:
    """Hold the measured pose."""
    runtime.reset_clocks()
    ev = runtime.evaluation
    setpoint = ServoSetpoint(
        mode=MotionMode.HOLD,
        position=ev.position.copy(),
        rotation_to_world=ev.rotation_tool_to_world.copy(),
        start_s=runtime.time_s,
    )
    runtime.set_setpoint(setpoint)
    return setpoint


def run_for(runtime: Runtime, duration_s: float) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """Tick for ``duration_s``; return (t, true tool position, joint torque) at every tick."""
    plant = runtime.plant
    site = plant.model.site("tool").id
    samples = []
    end = runtime.time_s + duration_s - 1e-9
    while runtime.time_s < end:
        runtime.tick()
        samples.append((runtime.time_s, plant.data.site_xpos[site].copy(), runtime.tau.copy()))
    return samples
