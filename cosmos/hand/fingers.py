"""The plant's fingers: the gripper's drive and the force sensor in each finger pad.

A real gripper offers its controller what this class offers: a commanded opening speed
and grip force setting (the drive, :meth:`Fingers.command`), the fingers' opening (the
drive's encoder) and the two pads' normal forces (:meth:`Fingers.read`). The pads' sensors
are read like the wrist sensor (:mod:`cosmos.realism.wrist_sensor`): on the realistic plant
through the same first-order low-pass (200 Hz) with a tare bias, and on both plants with
white noise of the wrist sensor's force standard deviation (0.05 N), reproducible from the
run's seed.

Per physics step the realistic plant's filter costs two multiply-adds (:meth:`Fingers.sense`);
the drive runs inside MuJoCo (an ``intvelocity`` actuator, :mod:`cosmos.hand.gripper_scene`).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.hand.gripper_scene import DRIVE, FINGERS, PADS
from cosmos.realism.wrist_sensor import (
    BIAS_FORCE_STD_N,
    CUTOFF_HZ,
    FORCE_NOISE_STD_N,
    low_pass_gain,
)

NOISE_BLOCK = 1024
"""The pads' noise is drawn this many readings at a time: the same numbers in the same order as
one draw a reading (numpy's generator fills an array in order), without a draw's 3 us each."""


@dataclass(frozen=True)
class FingerReading:
    """One reading of the gripper.

    Attributes:
        opening_m: Distance between the pads [m] (the drive's encoder).
        force_left_n: Normal force on the left pad [N], as its sensor reads it.
        force_right_n: Normal force on the right pad [N].
    """

    opening_m: float
    force_left_n: float
    force_right_n: float

    @property
    def grip_force_n(self) -> float:
        """The smaller of the two pads' forces [N]: what the grasp holds at least."""
        return min(self.force_left_n, self.force_right_n)


class Fingers:
    """The gripper's drive and pad sensors in a compiled workcell.

    Args:
        model: The compiled scene with the gripper (:func:`cosmos.hand.gripper_scene.mount_gripper`).
        data: Its state.
        seed: Seed of the pads' noise (and, realistic, their bias).
        realistic: Read the pads through the sensor's low-pass and a tare bias.

    Raises:
        CosmosError: If the scene has no gripper.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, seed: int, realistic: bool) -> None:
        drive = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, DRIVE)
        if drive < 0:
            raise CosmosError(f"the scene has no gripper (actuator '{DRIVE}')")
        self._model, self._data = model, data
        self._drive = int(drive)
        self._act = int(model.actuator_actadr[drive])
        self._finger_qpos = [int(model.jnt_qposadr[model.joint(name).id]) for name in FINGERS]
        self._pad_adr = [int(model.sensor_adr[model.sensor(f"{pad}_touch").id]) for pad in PADS]
        self._gain = low_pass_gain(CUTOFF_HZ, float(model.opt.timestep)) if realistic else 1.0
        rng = np.random.default_rng([seed, 17])
        self._rng = rng
        self._bias = rng.normal(0.0, BIAS_FORCE_STD_N, size=2) if realistic else np.zeros(2)
        self._bias_n: tuple[float, float] = (float(self._bias[0]), float(self._bias[1]))
        self._noise: list[list[float]] = []  # the block being read, a reading a row
        self._noise_row = NOISE_BLOCK
        self.filtered = np.zeros(2)
        """The pads' forces through the sensor's low-pass [N] (ideal plant: exact). # (2,)"""

    def reset(self) -> None:
        """Open, at rest: the filter settled on the current reading."""
        self._data.ctrl[self._drive] = 0.0
        self.filtered[:] = self._data.sensordata[self._pad_adr]

    def sense(self) -> None:
        """After a physics step: the pads' low-pass (two multiply-adds)."""
        sensordata, filtered, gain = self._data.sensordata, self.filtered, self._gain
        left, right = self._pad_adr
        filtered[0] += gain * (sensordata[left] - filtered[0])
        filtered[1] += gain * (sensordata[right] - filtered[1])

    def opening_m(self) -> float:
        """The distance between the pads [m] (the drive's encoder)."""
        qpos = self._data.qpos
        return float(qpos[self._finger_qpos[0]] + qpos[self._finger_qpos[1]])

    def positions_m(self) -> tuple[float, float]:
        """Each pad's distance from the gripper's centre plane, left then right [m] (the slides' encoders)."""
        qpos = self._data.qpos
        return float(qpos[self._finger_qpos[0]]), float(qpos[self._finger_qpos[1]])

    def read(self) -> FingerReading:
        """The opening and the pads' forces, each force with the sensor's bias and noise."""
        row = self._noise_row
        if row == NOISE_BLOCK:
            self._noise = self._rng.normal(0.0, FORCE_NOISE_STD_N, size=(NOISE_BLOCK, 2)).tolist()
            row = 0
        self._noise_row = row + 1
        noise_left, noise_right = self._noise[row]
        left, right = self.filtered.tolist()
        bias_left, bias_right = self._bias_n
        return FingerReading(
            self.opening_m(), left + bias_left + noise_left, right + bias_right + noise_right
        )

    def command(self, speed_mps: float, force_n: float) -> None:
        """Move the fingers at ``speed_mps`` (negative: closing) pushing with at most ``force_n``.

        The commanded opening starts from where the fingers are (a real drive's position
        loop starts from its encoder), so a RELEASE opens at once.

        Args:
            speed_mps: Opening speed [m/s]; clipped to the drive's fastest (its ``ctrlrange``).
            force_n: Grip force setting [N]: the drive's force limit on each finger.
        """
        self._data.act[self._act] = self.opening_m()
        low, high = self._model.actuator_ctrlrange[self._drive]
        self._data.ctrl[self._drive] = min(max(speed_mps, float(low)), float(high))
        self._model.actuator_forcerange[self._drive] = (-force_n, force_n)
