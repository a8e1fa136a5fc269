"""A live arm in its workcell with a run log: what ``cosmos run``, the REPL and ``--verify`` share."""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

import mujoco
import numpy as np

from cosmos import __version__
from cosmos.execution.executor import Executor, ProgressCallback
from cosmos.execution.fixtures import fixture_primitives
from cosmos.execution.obstacles import ObstacleWorld
from cosmos.execution.recording import LogRecorder
from cosmos.hand.gripper_scene import FINGERS, mount_gripper
from cosmos.hand.hand_log import HandRunLog
from cosmos.hand.holder_scene import add_holder
from cosmos.hand.object_scene import add_objects
from cosmos.hand.tool import Tool
from cosmos.hand.work_object import WorkObject
from cosmos.obstacles import obstacle_scene_xml
from cosmos.plant import Plant, SensorNoise
from cosmos.realism.plant_realism import PlantRealism, ideal_metadata
from cosmos.robot_model import build_robot_model
from cosmos.robots import DEFAULT_ROBOT, Robot
from cosmos.runlog.arm_scene import arm_entities
from cosmos.runlog.writer import RunLog
from cosmos.runtime.loop import DEFAULT_GAINS, Runtime
from cosmos.runtime.rates import Rates
from cosmos.runtime.servo import ServoGains

MODEL_NAME = DEFAULT_ROBOT.source
"""The default arm's model, as the log's metadata names it."""


class Variation(Protocol):
    """How the real workcell differs from the program's (``cosmos.sweep.variation.WorkcellVariation``)."""

    @property
    def model_error(self) -> float | None: ...  # noqa: D102
    @property
    def ideal(self) -> bool: ...  # noqa: D102
    def sensor_noise(self) -> SensorNoise: ...  # noqa: D102
    def apply_to_spec(self, spec: mujoco.MjSpec) -> None: ...  # noqa: D102
    def arguments(self) -> str: ...  # noqa: D102


class Session:
    """Plant, controller, executor and log, opened together and closed together.

    Args:
        program: The program's path as the user gave it (``<repl>`` for a REPL).
        source: Its text, stored in the log as an attachment (None: none yet).
        log_path: Where the MCAP log goes.
        rates: Servo, parameter and state rates.
        seed: Seed of the wrist sensor's noise and of the realistic plant's drawn arm and
            sensor bias (:mod:`cosmos.realism`); recorded in the log's metadata.
        progress: Called now and then with the statement running.
        variation: A sweep's changes to the real workcell (the program's frames stay nominal);
            its noise seed replaces ``seed``; recorded in the log's metadata.
        ros2: Also log the ROS 2 channels (joint states, wrench, transforms).
        gains: The servo's gains (tests: the null-space damping off).
        ideal: Run the ideal plant (the controller's own model, exact encoders) instead of
            the realistic one; recorded in the log's metadata (``plant``).
        model_error: The realistic plant's model-error scale (None: the variation's, else
            the default 0.05, :mod:`cosmos.realism.arm_error`).
        robot: The arm (the program's ``ROBOT``; the PUMA 560 by default); recorded in the
            log's metadata (``robot``, ``joints``, ``model``, ``scene``). The realistic plant
            is drawn for it (its published friction and its encoders, :class:`Robot`).
        tool: The hand on the flange (the program's ``TOOL``): the scene's peg, or the gripper
            mounted below the wrist sensor (:mod:`cosmos.hand`); recorded in the log's
            metadata (``tool``).
        objects: The program's objects (``OBJECT``), free bodies of the workcell from the start.
    """

    def __init__(
        self,
        program: str,
        source: str | None,
        log_path: Path,
        rates: Rates,
        seed: int = 0,
        progress: ProgressCallback | None = None,
        variation: Variation | None = None,
        ros2: bool = False,
        gains: ServoGains = DEFAULT_GAINS,
        ideal: bool = False,
        model_error: float | None = None,
        robot: Robot = DEFAULT_ROBOT,
        tool: Tool = Tool.PEG,
        objects: tuple[WorkObject, ...] = (),
    ):
        noise, vary, varied = SensorNoise(seed), None, {}
        if variation is not None:
            noise, vary = variation.sensor_noise(), variation.apply_to_spec
            seed = noise.seed
            varied = {"variation": variation.arguments()}
            ideal = ideal or variation.ideal
            if model_error is None:
                model_error = variation.model_error
        realism = None
        if not ideal:
            realism = (
                PlantRealism.drawn(seed, robot)
                if model_error is None
                else PlantRealism.drawn(seed, robot, model_error)
            )
        plant_metadata = ideal_metadata() if realism is None else realism.metadata()
        self.robot = robot
        self.tool = tool

        def edit(spec: mujoco.MjSpec) -> None:
            if tool is Tool.GRIPPER:
                mount_gripper(spec, robot.name)
                add_holder(spec)
            add_objects(spec, objects)  # after the fingers: the keyframe holds the arm's and theirs
            if vary is not None:
                vary(spec)

        self.plant = Plant(obstacle_scene_xml(scene_xml=robot.scene_xml), noise, edit, realism)
        self.runtime = Runtime(self.plant, build_robot_model(robot, tool), rates, gains)
        # The bodies on /tf and drawn on /scene: the arm's, the fingers', the objects'.
        frames = (*robot.frames, *(FINGERS if tool is Tool.GRIPPER else ()), *(item.name for item in objects))
        log_class = RunLog if tool is Tool.PEG else HandRunLog
        self.log = log_class(
            log_path,
            program=program,
            source=source,
            servo_hz=rates.servo_hz,
            param_hz=rates.param_hz,
            state_hz=rates.state_hz,
            model=robot.source,
            seed=seed,
            metadata={
                "scene": robot.scene_xml.name,
                "robot": robot.name,
                "tool": tool.value,
                "cosmos_version": __version__,
            }
            | plant_metadata
            | varied,
            frames=frames,
            ros2_joints=robot.joint_names if ros2 else None,
            joints=robot.dof,
        )
        arm = arm_entities(self.plant.model, self.plant.geom_owners, frames)
        self.log.scene(0.0, add=[*fixture_primitives(self.plant), *arm])
        self.obstacles = ObstacleWorld(self.runtime, self.log)
        self.executor = Executor(self.runtime, self.log, progress, obstacles=self.obstacles)
        if tool is Tool.GRIPPER:
            self._mount_hand(objects, frames)
        elif frames != robot.frames:
            self.executor.recorder = self.runtime.recorder = LogRecorder(self.log, self.plant, frames)
        self.executor.hold()

    def _mount_hand(self, objects: tuple[WorkObject, ...], frames: tuple[str, ...]) -> None:
        """The executor's GRASP and RELEASE, its supervision watching for slip, the hand's log."""
        from cosmos.hand.grasping import Hand
        from cosmos.hand.hand_log import HandRecorder
        from cosmos.hand.supervision import GraspSupervisor
        from cosmos.hand.tool import gripper_of

        executor = self.executor
        hand = executor.hand = Hand(self.runtime, objects, executor.hold, gripper_of(self.robot.name))
        robot = self.runtime.robot
        executor.supervisor = GraspSupervisor(
            self.plant,
            np.minimum(-robot.tau_lower_nm, robot.tau_upper_nm),
            1.0 / self.runtime.rates.servo_hz,
            hand,
        )
        executor.supervisor.watch_joint_speeds(robot.description.joint_speed_limits_rad_s)

        def held() -> str:
            return "" if hand.held is None else hand.held.item.name

        assert isinstance(self.log, HandRunLog)
        executor.recorder = self.runtime.recorder = HandRecorder(self.log, self.plant, frames, held)

    @property
    def log_path(self) -> Path:
        """Path of the MCAP log."""
        return self.log.path

    def close(self) -> None:
        """Close the log (writes its summary); safe to call twice."""
        self.log.close()

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
