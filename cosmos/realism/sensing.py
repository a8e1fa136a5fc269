"""The realistic plant's sensing state, stepped with the physics (:class:`cosmos.plant.Plant`).

Holds the encoder readings, the velocity observer's state and the wrist sensor's filter
as arrays that :meth:`cosmos.plant.Plant.live_signals` hands to the servo loop, and
updates them after every physics step with one compiled call
(:func:`cosmos.realism.kernel.sense_step`), which also sets the friction's asymmetric part
in MuJoCo's ``qfrc_applied`` for the next step.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.realism.arm_error import ASYMMETRY_SPEED_RAD_S
from cosmos.realism.kernel import ASYMMETRY_SPEED, DT, OMEGA, SCALARS, WRENCH_GAIN, sense_step
from cosmos.realism.plant_realism import PlantRealism
from cosmos.realism.wrist_sensor import low_pass_gain


class Sensing:
    """The realistic plant's sensing state: encoder readings, observer, sensor filter.

    Args:
        realism: The run's realistic plant.
        model: The compiled scene (its joints, time step).
        wrench_index: Where the wrist sensor's force then torque are in ``sensordata``
            (a slice, six indices, or None without a sensor).

    Raises:
        CosmosError: If ``realism`` was drawn for another number of joints.
    """

    def __init__(self, realism: PlantRealism, model: mujoco.MjModel, wrench_index: slice | np.ndarray | None):
        n = model.nq
        if len(realism.encoder_resolution_rad) != n or len(realism.arm.joints) != n:
            raise CosmosError(
                f"the realistic plant is drawn for {len(realism.arm.joints)} joints, the arm has {n}"
            )
        self.resolution = np.array(realism.encoder_resolution_rad)
        self.asymmetry = realism.arm.asymmetry_nm()
        dt = float(model.opt.timestep)
        self.scalars = np.zeros(SCALARS)
        self.scalars[OMEGA] = 2.0 * np.pi * realism.observer_hz
        self.scalars[DT] = dt
        self.scalars[WRENCH_GAIN] = low_pass_gain(realism.wrist_cutoff_hz, dt)
        self.scalars[ASYMMETRY_SPEED] = ASYMMETRY_SPEED_RAD_S
        self.sensed_q = np.zeros(n)
        self.estimate = np.zeros((2, n))  # rows: the observer's angles, its velocities
        self.wrench_filtered = np.zeros(6)
        self._wrench_index = wrench_index
        self._wrench_true = np.zeros(6)

    def _true_wrench(self, data: mujoco.MjData) -> np.ndarray:
        index = self._wrench_index
        if isinstance(index, slice):
            return data.sensordata[index]
        if index is not None:
            self._wrench_true[:] = data.sensordata[index]
        return self._wrench_true

    def reset(self, data: mujoco.MjData) -> None:
        """At rest: the observer on the encoders' reading, the sensor's filter settled."""
        self.estimate[:] = 0.0
        self.wrench_filtered[:] = self._true_wrench(data)
        self.sense(data)
        self.estimate[0] = self.sensed_q
        self.estimate[1] = 0.0
        data.qfrc_applied[:] = 0.0

    def sense(self, data: mujoco.MjData) -> None:
        """After a physics step: read the encoders, update the observer and the filter."""
        sense_step(
            data.qpos,
            data.qvel,
            self._true_wrench(data),
            self.resolution,
            self.asymmetry,
            self.scalars,
            self.sensed_q,
            self.estimate,
            self.wrench_filtered,
            data.qfrc_applied,
        )
