"""The plant: the simulated PUMA 560 workcell in MuJoCo.

The controller talks to the plant only through what a real arm offers: joint
torques in (:meth:`Plant.step`), encoders and the wrist force/torque sensor out
(:meth:`Plant.read_encoders`, :meth:`Plant.read_wrench_sensor`); the servo loop
takes the same signals as live buffers (:meth:`Plant.live_signals`, no copy per tick).

Two plants. The **realistic** one (``realism``, :class:`cosmos.realism.PlantRealism`,
the default of ``cosmos run``) is the published arm changed by a drawn model error
(link masses and inertias, rotor inertia, friction with the published asymmetry), read
through quantised encoders, a velocity observer instead of ``qvel``, and a wrist sensor
with a 200 Hz bandwidth and a bias (:mod:`cosmos.realism`). The **ideal** one
(``realism=None``, ``--ideal``) is the controller's own model read exactly: ``qpos``,
``qvel`` and the sensor's wrench plus its noise.
:meth:`Plant.contacts` reports contacts for collision events, and
:attr:`Plant.model` / :attr:`Plant.data` exist for rendering and logging only.

Wrist sensor sign convention (MuJoCo ``force``/``torque`` sensors on the
``ft_sensor`` site of the tool body, checked in ``tests/test_plant.py``): the
reading is the wrench that link 6 (the parent) exerts on the tool (the child),
in the sensor frame, the torque taken about the sensor origin. Held still in
free air the sensor reads the tool's weight as an upward force: in world axes
``f = -m g`` with ``g = (0, 0, -9.81) m/s^2``. Quasi-statically, the force the
tool applies to the environment is ``R f + m g`` in world axes (``R``: sensor
axes in world coordinates), and the moment about the sensor origin is
``R tau + (c - o) x m g`` (``c``: tool centre of mass, ``o``: sensor origin).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.hand.fingers import Fingers
from cosmos.hand.gripper_scene import DRIVE
from cosmos.plant_scene import check_arm, geom_owners, wrench_index
from cosmos.realism.plant_realism import PlantRealism
from cosmos.realism.sensing import Sensing
from cosmos.realism.tare import payload_tare
from cosmos.workcell import FORCE_SENSOR, HOME_KEY, SCENE_XML, TORQUE_SENSOR


@dataclass(frozen=True)
class Contact:
    """One contact between two geoms, named.

    Attributes:
        geom1: Name of the first geom.
        geom2: Name of the second geom.
        body1: Name of the body that carries ``geom1``.
        body2: Name of the body that carries ``geom2``.
        distance_m: Signed distance between the geoms [m]; negative when they
            penetrate.
        position: Midpoint of the contact in the world frame [m], ``(3,)``.
    """

    geom1: str
    geom2: str
    body1: str
    body2: str
    distance_m: float
    position: np.ndarray  # (3,)


@dataclass(frozen=True)
class SensorNoise:
    """White noise on the wrist sensor's readings, reproducible from a seed (``cosmos run --seed``).

    The defaults are of the order of a small industrial F/T sensor's noise
    (about 0.05 N and 2 mN m standard deviation).

    Attributes:
        seed: Seed of the noise generator.
        force_std_n: Standard deviation of each force component [N].
        torque_std_nm: Standard deviation of each torque component [N m].
        bias: Constant offset of each reading, force then torque, sensor axes [N, N m].
    """

    seed: int
    force_std_n: float = 0.05
    torque_std_nm: float = 0.002
    bias: tuple[float, float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

    @property
    def std(self) -> np.ndarray:
        """Per-component standard deviation, force then torque. # (6,)."""
        f, t = self.force_std_n, self.torque_std_nm
        return np.array((f, f, f, t, t, t))


_NOISE_BLOCK = 1024


@dataclass(frozen=True)
class LiveSignals:
    """The plant's encoders, wrist sensor and drives as live buffers, for the servo loop.

    Views into the simulation's own arrays (ideal plant) or its sensing's (realistic
    plant): they change with every step, and writing ``ctrl`` commands the drives. A
    reading of the sensor is ``wrench_raw + noise[row]`` with ``row`` from
    :meth:`Plant.next_noise_row`.

    Attributes:
        positions: Joint angles [rad] (realistic: the encoders' counts), read-only. # (n,)
        velocities: Joint velocities [rad/s] (realistic: the observer's estimate), read-only. # (n,)
        wrench_raw: The wrist sensor's noiseless reading (realistic: low-passed; see
            :meth:`Plant.read_wrench_sensor`), read-only. # (6,)
        noise: The sensor noise samples [N, N m], redrawn in place; one zero row without
            noise, read-only. # (n, 6)
        ctrl: Motor torques [N m], applied from the next step on. # (n,)
    """

    positions: np.ndarray
    velocities: np.ndarray
    wrench_raw: np.ndarray
    noise: np.ndarray
    ctrl: np.ndarray


class Plant:
    """The simulated workcell: a MuJoCo model and its state.

    Args:
        scene_xml: MJCF file of the scene. It must have the hinge joints and
            motors ``joint1`` .. ``joint<n>`` as its first degrees of freedom and
            actuators, in that order, and a keyframe ``home``; after them it may have a
            gripper's fingers and drive (:mod:`cosmos.hand`) and free objects. The wrist sensor
            (``ft_force``, ``ft_torque``) is optional: without it
            :meth:`read_wrench_sensor` raises.
        sensor_noise: Noise (and bias) of the wrist sensor; None: exact readings.
        edit_spec: Changes the scene before it is compiled (a sweep's varied workcell,
            ``cosmos.sweep.variation``).
        realism: The realistic plant's arm error and sensing (its bias adds to the noise's);
            None: the ideal plant (module docstring).

    Raises:
        CosmosError: If the scene does not have the joints and motors above.
    """

    def __init__(
        self,
        scene_xml: Path | str = SCENE_XML,
        sensor_noise: SensorNoise | None = None,
        edit_spec: Callable[[mujoco.MjSpec], None] | None = None,
        realism: PlantRealism | None = None,
    ) -> None:
        spec = mujoco.MjSpec.from_file(str(scene_xml))
        if edit_spec is not None:
            edit_spec(spec)
        if realism is not None:
            realism.arm.apply_to_spec(spec)
        model = spec.compile()
        n = check_arm(model, scene_xml)
        home = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, HOME_KEY)
        if home < 0:
            raise CosmosError(f"{scene_xml}: the scene has no keyframe '{HOME_KEY}'")
        self._model = model
        self._data = mujoco.MjData(model)
        self._home_key = int(home)
        self._wrench_index = wrench_index(model)
        self._geom_names = tuple(model.geom(i).name for i in range(model.ngeom))
        self._geom_owners = geom_owners(spec, model)
        # Views into MjData's buffers, taken once: the hot loop does not rebuild them.
        # The arm's joints come first in qpos, qvel and ctrl (check_arm): views of their n.
        self._qpos = self._data.qpos[:n]  # (n,)
        self._qvel = self._data.qvel[:n]  # (n,)
        self._ctrl = self._data.ctrl[:n]  # (n,)
        self._sensordata = self._data.sensordata
        self._noise_std = None if sensor_noise is None else sensor_noise.std
        self._noise_bias = np.zeros(6) if sensor_noise is None else np.array(sensor_noise.bias, dtype=float)
        if realism is not None:
            self._noise_bias += realism.wrist_bias
        self._rng = np.random.default_rng(None if sensor_noise is None else sensor_noise.seed)
        # Drawn in blocks (one draw per reading costs microseconds), in place: live_signals()
        # hands out this array. Without noise, one row (the bias) that every reading takes.
        self._noise = np.zeros((1 if sensor_noise is None else _NOISE_BLOCK, 6))
        if sensor_noise is None:
            self._noise[0] = self._noise_bias
        self._noise_next = _NOISE_BLOCK  # the first reading draws the first block
        self._realism = realism
        self._sensing = None if realism is None else Sensing(realism, model, self._data, self._wrench_index)
        self._fingers = (
            None
            if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, DRIVE) < 0
            else Fingers(
                model, self._data, 0 if sensor_noise is None else sensor_noise.seed, realism is not None
            )
        )
        self.reset()
        # The cell tares the sensor at home with the tool as mounted (cosmos.realism.tare).
        self._noise_bias -= payload_tare(spec, model, self._data)
        if sensor_noise is None:
            self._noise[0] = self._noise_bias

    @property
    def model(self) -> mujoco.MjModel:
        """The MuJoCo model, for rendering and logging only: the controller must not read it."""
        return self._model

    @property
    def data(self) -> mujoco.MjData:
        """The MuJoCo state, for rendering and logging only: the controller must not read it."""
        return self._data

    @property
    def realism(self) -> PlantRealism | None:
        """The realistic plant's arm error and sensing; None for the ideal plant."""
        return self._realism

    @property
    def fingers(self) -> Fingers | None:
        """The gripper's drive and pad sensors (``TOOL GRIPPER``); None with the peg."""
        return self._fingers

    @property
    def geom_owners(self) -> tuple[str, ...]:
        """Per geom: its body's name, or for a fixture's geom (world body) its frame's name."""
        return self._geom_owners

    @property
    def dt_s(self) -> float:
        """Physics time step [s]."""
        return float(self._model.opt.timestep)

    @property
    def time_s(self) -> float:
        """Simulated time since the last :meth:`reset` [s]."""
        return float(self._data.time)

    def reset(self, q: np.ndarray | None = None) -> None:
        """Put the arm at rest, at ``q`` or at the home keyframe; zero time and torques.

        Args:
            q: Joint angles [rad], ``(n,)``; ``None`` for the ``home`` keyframe.
        """
        mujoco.mj_resetDataKeyframe(self._model, self._data, self._home_key)
        if q is not None:
            self._qpos[:] = q
        self._qvel[:] = 0.0
        self._ctrl[:] = 0.0
        mujoco.mj_forward(self._model, self._data)
        # The sensors as the arm reads them held at rest (zero acceleration), not falling with
        # its drives off as mj_forward has it: the wrist then read no weight of the tool, and a
        # first statement's CONTACT DOWN felt the tool's 2.2 N as a touch at t = 0.001 s.
        self._data.qacc[:] = 0.0
        mujoco.mj_inverse(self._model, self._data)
        if self._sensing is not None:
            self._sensing.reset()
        if self._fingers is not None:
            self._fingers.reset()

    def step(self, tau: np.ndarray) -> float:
        """Apply joint torques for one time step and advance the simulation.

        Args:
            tau: Motor torques [N m], ``(n,)``, joint order; each is clipped to its
                drive's limit (the actuator's ``ctrlrange``). Must be finite: MuJoCo
                zeroes non-finite controls and records a warning.

        Returns:
            The simulated time after the step, [s] (:attr:`time_s`).
        """
        self._ctrl[:] = tau  # MuJoCo clamps to ctrlrange (every motor is ctrllimited: check_arm)
        return self.advance()

    def advance(self) -> float:
        """One time step with the torques already in the drives (:attr:`LiveSignals.ctrl`).

        Returns:
            The simulated time after the step, [s] (:attr:`time_s`).
        """
        data = self._data
        mujoco.mj_step(self._model, data)
        sensing = self._sensing
        if sensing is not None:
            sensing.sense()
        fingers = self._fingers
        if fingers is not None:
            fingers.sense()
        return float(data.time)

    def live_signals(self) -> LiveSignals:
        """The encoders, the wrist sensor and the drives as live buffers (no copies).

        Raises:
            CosmosError: If the scene has no wrist sensor, or its force and torque are
                not side by side in ``sensordata``.
        """
        index = self._wrench_index
        if not isinstance(index, slice):
            raise CosmosError(
                f"the servo loop needs the wrist sensor's force '{FORCE_SENSOR}' directly "
                f"followed by its torque '{TORQUE_SENSOR}'"
            )
        sensing = self._sensing
        sources = (
            (self._qpos, self._qvel, self._sensordata[index])
            if sensing is None
            else (sensing.sensed_q, sensing.velocity, sensing.wrench_filtered)
        )
        positions, velocities, wrench_raw, noise = (array.view() for array in (*sources, self._noise))
        for array in (positions, velocities, wrench_raw, noise):
            array.flags.writeable = False
        return LiveSignals(positions, velocities, wrench_raw, noise, self._ctrl)

    def next_noise_row(self) -> int:
        """The row of :attr:`LiveSignals.noise` that the next sensor reading takes.

        Each reading takes a fresh row, with or without :meth:`read_wrench_sensor`.
        """
        if self._noise_std is None:
            return 0
        i = self._noise_next
        if i == _NOISE_BLOCK:
            self._noise[:] = self._rng.normal(self._noise_bias, self._noise_std, size=(_NOISE_BLOCK, 6))
            i = 0
        self._noise_next = i + 1
        return i

    def zero_wrist_sensor(self, offset: np.ndarray) -> None:
        """Take ``offset`` off every later reading of the wrist sensor: the cell tares it.

        Args:
            offset: The reading's error, force then torque, sensor axes [N, N m]. # (6,)
        """
        self._noise_bias -= offset
        self._noise -= offset  # the rows drawn and not yet read (the ideal plant's one row)

    def read_encoders(self) -> tuple[np.ndarray, np.ndarray]:
        """Joint angles [rad] and velocities [rad/s], each ``(n,)``, copies.

        The realistic plant's are the encoders' counts and the observer's estimate; the
        ideal plant's MuJoCo's ``qpos`` and ``qvel``.
        """
        sensing = self._sensing
        if sensing is not None:
            return sensing.sensed_q.copy(), sensing.velocity.copy()
        return self._qpos.copy(), self._qvel.copy()

    def read_wrench_sensor(self) -> np.ndarray:
        """The wrist force/torque sensor: ``(fx, fy, fz, tx, ty, tz)`` [N, N m], ``(6,)``.

        Raw, in the sensor's own frame: the wrench that link 6 exerts on the tool,
        the torque about the sensor origin (sign convention in the module docstring);
        on the realistic plant through the sensor's low-pass, plus its bias.

        Raises:
            CosmosError: If the scene has no wrist sensor.
        """
        index = self._wrench_index
        if index is None:
            raise CosmosError(
                f"the scene has no wrist sensor (force '{FORCE_SENSOR}', torque '{TORQUE_SENSOR}')"
            )
        wrench = self._sensordata[index] if self._sensing is None else self._sensing.wrench_filtered
        return wrench + self._noise[self.next_noise_row()]

    def contacts(self) -> list[Contact]:
        """The contacts MuJoCo found at the current state, with geom and body names.

        A fixture's geoms belong to the world body, placed by a named frame; a
        contact names such a geom's frame as its body (``table``, ``hole_fixture``).
        """
        if self._data.ncon == 0:
            return []
        found = self._data.contact
        owners = self._geom_owners
        return [
            Contact(
                geom1=self._geom_names[geom1],
                geom2=self._geom_names[geom2],
                body1=owners[geom1],
                body2=owners[geom2],
                distance_m=float(distance),
                position=position.copy(),
            )
            for (geom1, geom2), distance, position in zip(found.geom, found.dist, found.pos, strict=True)
        ]
