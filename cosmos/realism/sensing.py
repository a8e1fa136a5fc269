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
from cosmos.realism.kernel import (
    ASYMMETRY,
    ASYMMETRY_SPEED,
    DT,
    JOINT_CONSTANTS,
    JOINT_STATE,
    OMEGA,
    Q_HAT,
    RESOLUTION,
    SCALARS,
    SENSED_Q,
    V_HAT,
    WRENCH_GAIN,
    sense_step,
)
from cosmos.realism.plant_realism import PlantRealism
from cosmos.realism.wrist_sensor import low_pass_gain

WrenchIndex = slice | np.ndarray | None


class Sensing:
    """The realistic plant's sensing state: encoder readings, observer, sensor filter.

    Args:
        realism: The run's realistic plant.
        model: The compiled scene (its joints, time step).
        data: Its state: the buffers read and written (``qpos``, ``qvel``, ``sensordata``,
            ``qfrc_applied``).
        wrench_index: Where the wrist sensor's force then torque are in ``sensordata``
            (a slice, six indices, or None without a sensor).

    Raises:
        CosmosError: If ``realism`` was drawn for another number of joints.
    """

    def __init__(
        self, realism: PlantRealism, model: mujoco.MjModel, data: mujoco.MjData, wrench_index: WrenchIndex
    ):
        n = len(realism.arm.joints)  # the arm's joints come first; a gripper's and objects' follow
        if len(realism.encoder_resolution_rad) != n or model.nq < n:
            raise CosmosError(
                f"the realistic plant is drawn for {len(realism.arm.joints)} joints, the scene has {model.nq}"
            )
        dt = float(model.opt.timestep)
        self.scalars = np.zeros(SCALARS)
        self.scalars[OMEGA] = 2.0 * np.pi * realism.observer_hz
        self.scalars[DT] = dt
        self.scalars[WRENCH_GAIN] = low_pass_gain(realism.wrist_cutoff_hz, dt)
        self.scalars[ASYMMETRY_SPEED] = ASYMMETRY_SPEED_RAD_S
        self.joint_constants = np.zeros((JOINT_CONSTANTS, n))
        self.joint_constants[RESOLUTION] = realism.encoder_resolution_rad
        self.joint_constants[ASYMMETRY] = realism.arm.asymmetry_nm()
        self.joint_state = np.zeros((JOINT_STATE, n))
        self.sensed_q = self.joint_state[SENSED_Q]
        """The encoders' readings [rad]. # (n,)"""
        self.velocity = self.joint_state[V_HAT]
        """The observer's velocity estimate [rad/s]. # (n,)"""
        self.wrench_filtered = np.zeros(6)
        """The wrist sensor's low-passed wrench [N, N m]. # (6,)"""
        if wrench_index is None:
            self._wrench_index = np.full(6, -1, dtype=np.int64)
        elif isinstance(wrench_index, slice):
            self._wrench_index = np.arange(wrench_index.start, wrench_index.stop, dtype=np.int64)
        else:
            self._wrench_index = np.asarray(wrench_index, dtype=np.int64)
        # MjData's buffers, taken once (they are updated in place, never replaced).
        self._data = data
        self._qpos, self._qvel, self._sensordata = data.qpos[:n], data.qvel[:n], data.sensordata
        self._qfrc_applied = data.qfrc_applied[:n]

    def reset(self) -> None:
        """At rest: the observer on the encoders' reading, the sensor's filter settled."""
        self._qfrc_applied[:] = 0.0
        self.joint_state[:] = 0.0
        index = self._wrench_index
        self.wrench_filtered[:] = 0.0 if index[0] < 0 else self._sensordata[index]
        self.sense()
        self.joint_state[Q_HAT] = self.sensed_q
        self.joint_state[V_HAT] = 0.0
        self._qfrc_applied[:] = 0.0

    def sense(self) -> None:
        """After a physics step: read the encoders, update the observer and the filter."""
        sense_step(
            self._qpos,
            self._qvel,
            self._sensordata,
            self._wrench_index,
            self.joint_constants,
            self.scalars,
            self.joint_state,
            self.wrench_filtered,
            self._qfrc_applied,
        )
