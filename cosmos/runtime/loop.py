"""The runtime loop: sense -> estimate -> command -> physics -> record.

The controller side sees only what a real arm's controller sees: joint
encoders and the wrist force/torque sensor, read from the plant. Its model is
the Pinocchio one (:mod:`cosmos.robot_model`); the plant is the MuJoCo
workcell (:mod:`cosmos.plant`). Each call of :meth:`Runtime.tick` is one servo
period: it re-evaluates the parameters when their (lower) rate is due, runs
the servo level, then steps the physics until the next servo instant, holding
the torque (zero-order hold), recording the state at its fixed rate: a
sample due at a tick's start is what that tick sensed and commanded (the
wrench as the servo derived it from the sensor); one due inside a hold is
sensed on its own.
"""

from __future__ import annotations

import math
import time
from typing import Protocol

import numpy as np

from cosmos.obstacles import ObstacleField
from cosmos.obstacles.gate import ContactGate
from cosmos.plant import Plant
from cosmos.robot_model import GRAVITY, RobotModel
from cosmos.runtime.field_split import FieldSplit
from cosmos.runtime.kernels.commands import environment_wrench_into
from cosmos.runtime.null_space import LinkField
from cosmos.runtime.parameters import ParameterLevel
from cosmos.runtime.rates import Rates
from cosmos.runtime.rotation_plan import RotationPlan, plan_rotation, ranges_for_goal
from cosmos.runtime.servo import ServoGains, ServoLevel
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

FloatArray = np.ndarray


DEFAULT_RATES = Rates()
DEFAULT_GAINS = ServoGains()


class Recorder(Protocol):
    """Receives the state at the state rate (:class:`cosmos.execution.recording.LogRecorder`)."""

    def record(
        self,
        t_s: float,
        q: FloatArray,
        qd: FloatArray,
        tau: FloatArray,
        wrench: FloatArray,
        twist: FloatArray,
    ) -> None:
        """Record the state at ``t_s`` (world axes); the arrays are valid only during the call.

        Args:
            t_s: Simulated time since start, in [s].
            q: Joint positions, in [rad]. # (n,)
            qd: Joint velocities, in [rad/s]. # (n,)
            tau: Joint torques being applied, in [N m]. # (n,)
            wrench: Wrench the tool applies to the environment, [N, N m]. # (6,)
            twist: Tool twist ``J qd`` (J of the model's last evaluation), linear then
                angular, [m/s, rad/s]. # (6,)
        """
        ...


class PotentialField(Protocol):
    """An artificial potential field (seed section 6) acting on the arm through joint torques."""

    def torque(self, q: FloatArray, qd: FloatArray, t_s: float) -> FloatArray:
        """Joint torques of the field at this state, in [N m]. # (n,)."""
        ...


class PhaseTimes:
    """Accumulated wall-clock nanoseconds per phase of the loop (for ``cosmos bench``)."""

    names = ("sense", "parameters", "servo", "physics", "record")

    def __init__(self) -> None:
        self.ns = dict.fromkeys(self.names, 0)
        self.ticks = 0


def _compensated_coulomb(robot: RobotModel, plant: Plant) -> tuple[FloatArray, FloatArray]:
    """The Coulomb friction the servo compensates, turning positively and negatively [N m].

    The published values by direction (:attr:`RobotModel.coulomb_positive_nm`), which a
    real arm of the type has; on the ideal plant (``--ideal``), which is the model file
    itself and holds only their mean (MuJoCo's symmetric ``frictionloss``), that mean.
    """
    if plant.realism is None:
        return robot.coulomb_nm, robot.coulomb_nm
    return robot.coulomb_positive_nm, robot.coulomb_negative_nm


def _speed_noise(plant: Plant) -> FloatArray | None:
    """The sensed joint speed's noise (the observer's answer to one encoder count) [rad/s], None if exact."""
    return None if plant.realism is None else plant.realism.one_count_speed_rad_s(plant.dt_s)


class Runtime:
    """A controller (parameter + servo levels) closed around a plant."""

    def __init__(
        self,
        plant: Plant,
        robot: RobotModel,
        rates: Rates = DEFAULT_RATES,
        gains: ServoGains = DEFAULT_GAINS,
        recorder: Recorder | None = None,
    ):
        self.plant = plant
        self.robot = robot
        self._tool_weight_z_n = float(GRAVITY[2]) * robot.tool.mass_kg
        self.rates = rates
        self.parameters = ParameterLevel(robot)
        self.servo = ServoLevel(
            gains,
            np.minimum(-robot.tau_lower_nm, robot.tau_upper_nm),
            robot.viscous_nms_per_rad,
            _compensated_coulomb(robot, plant),
            1.0 / rates.servo_hz,
            self._tool_weight_z_n,
            joint_limits=(robot.q_lower_rad, robot.q_upper_rad),
            speed_noise_rad_s=_speed_noise(plant),
            joint_speed_limits_rad_s=np.array(robot.description.joint_speed_limits_rad_s),
        )
        self.recorder = recorder
        self._live = plant.live_signals()
        self.fields: list[PotentialField] = []
        """Potential fields (obstacles), evaluated at the parameter rate like the model."""
        self._field_split = FieldSplit(robot.model.nv)
        self.contact_gate: ContactGate | None = None
        """Engaged before the physics steps of each tick (cosmos.obstacles.gate)."""
        self._servo_period_s = 1.0 / rates.servo_hz
        self._param_period_s = 1.0 / rates.param_hz
        self._state_period_s = 1.0 / rates.state_hz
        self._eps_s = 0.25 * plant.dt_s
        self._next_state_s = plant.time_s + plant.dt_s  # one fixed grid from the first step on
        self.rotation_plan: RotationPlan | None = None
        """The way round the current goal motion turns (None outside goal motions)."""
        self.setpoint: ServoSetpoint | None = None
        """The segment's command the servo runs (None before the first)."""
        self.record_ns = 0
        """Wall-clock nanoseconds the ticks spent recording, all told (``cosmos bench``)."""
        self.reset_clocks()

    def carry(self, robot: RobotModel) -> None:
        """Take ``robot`` as the controller's model from now on: this arm, its tool changed.

        A GRASP's held object (:func:`cosmos.hand.payload.holding`) and its RELEASE: the
        parameter level is rebuilt on the new tool frame and mass, and the servo compensates
        the wrist sensor for the new weight below it.
        """
        self.robot = robot
        self._tool_weight_z_n = float(GRAVITY[2]) * robot.tool.mass_kg
        self.parameters = ParameterLevel(robot)
        self.servo.set_tool_weight(self._tool_weight_z_n)

    def reset_clocks(self) -> None:
        """Sense once, evaluate the model now and restart the parameter schedule from here."""
        now = self.plant.time_s
        self._next_param_s = now
        live, servo = self._live, self.servo
        servo.sensed_q[:] = live.positions
        servo.sensed_qd[:] = live.velocities
        self.evaluation = self.parameters.evaluate(live.positions, live.velocities)
        servo.set_evaluation(self.evaluation)
        servo.wrench[:] = self._sense_wrench()

    @property
    def q(self) -> FloatArray:
        """Joint positions as the last tick sensed them, in [rad]; rewritten every tick. # (n,)."""
        return self.servo.sensed_q

    @property
    def qd(self) -> FloatArray:
        """Joint velocities as the last tick sensed them, in [rad/s]; rewritten every tick. # (n,)."""
        return self.servo.sensed_qd

    @property
    def tau(self) -> FloatArray:
        """Joint torques the last tick commanded, in [N m]; rewritten every tick. # (n,)."""
        return self.servo.torque

    @property
    def wrench(self) -> FloatArray:
        """The wrench the tool applied to the environment, as last sensed, world [N, N m]. # (6,)."""
        return self.servo.wrench

    def _evaluate_fields(self, now: float) -> None:
        """The fields' torques, the obstacle field's split by link (the servo projects the links')."""
        fields = self.fields
        if not fields:
            return
        live = self._live
        field, split = fields[0], self._field_split
        if len(fields) == 1 and isinstance(field, ObstacleField):  # the executor's: one split
            link_field = split.link_field(field, live.positions, live.velocities, now)
            # A field of no torque the servo holds already is folded in as it is (set_evaluation).
            if split.pushing or link_field is not self.servo.link_field:
                self.servo.link_field = link_field
            return
        torque = np.zeros(self.robot.model.nv)
        links = np.zeros(self.robot.model.nv)
        nearest: tuple[float, str, str] = (math.inf, "", "")
        for field in fields:
            torque += field.torque(live.positions, live.velocities, now)
            if isinstance(field, ObstacleField):
                links += field.link_torque
                nearest = min(nearest, field.nearest_link)
        self.servo.link_field = LinkField(torque - links, links, *nearest)

    @property
    def time_s(self) -> float:
        """Simulated time, in [s]."""
        return self.plant.time_s

    def set_setpoint(self, setpoint: ServoSetpoint) -> None:
        """Hand the servo level a new segment's command.

        A goal motion first has its way round chosen (:func:`plan_rotation`): the
        shortest rotation unless the joints' ranges forbid it; :attr:`rotation_plan`
        keeps the choice, and the joint that stops it if none is free. The protective
        zones near the joints' limits (the task's limit projection, the joint-limit field)
        start no nearer than the goal's configuration, or, for any other segment, the
        configuration it starts from (:func:`ranges_for_goal`).
        """
        rotation_error = None
        self.rotation_plan = None
        ev = self.evaluation
        goal_q: FloatArray | None = ev.q
        if setpoint.mode is MotionMode.GOAL:
            plan = plan_rotation(
                self.robot,
                ev.q,
                ev.position,
                ev.rotation_tool_to_world,
                setpoint.position,
                setpoint.rotation_to_world,
            )
            self.rotation_plan = plan
            rotation_error = -plan.rotation_vector
            goal_q = None if plan.blocked_by is not None else plan.goal_q
        robot, rho_0 = self.robot, self.parameters.limit_field.rho_0_rad
        self.parameters.field_ranges = ranges_for_goal(robot.q_lower_rad, robot.q_upper_rad, goal_q, rho_0)
        self.servo.set_setpoint(setpoint, rotation_error, goal_q)
        self.setpoint = setpoint

    def _sense_wrench(self) -> FloatArray:
        ev = self.evaluation
        wrench = np.empty(6)
        environment_wrench_into(
            wrench,
            self.plant.read_wrench_sensor(),
            ev.rotation_sensor_to_world,
            ev.sensor_to_tool_m,
            ev.sensor_to_com_m,
            self._tool_weight_z_n,
        )
        return wrench

    def tick(self) -> float:
        """One servo period: sense, evaluate if due, command, step the physics, record.

        Returns:
            The simulated time after it, in [s] (:attr:`time_s`, which costs the executor's
            loop a read of MuJoCo's data every tick).
        """
        now, noise_row = self._sense()
        if now + self._eps_s >= self._next_param_s:
            self._evaluate(now)
        self.servo.command(now, self._live, noise_row)
        return self._advance(now)

    def timed_tick(self, phases: PhaseTimes) -> None:
        """:meth:`tick`, adding the wall-clock time of each phase to ``phases`` (``cosmos bench``).

        The clocks cost time of their own, so :meth:`tick` runs without them.
        """
        clock = time.perf_counter_ns
        t0 = clock()
        now, noise_row = self._sense()
        t1 = clock()
        if now + self._eps_s >= self._next_param_s:
            self._evaluate(now)
        t2 = clock()
        self.servo.command(now, self._live, noise_row)
        t3 = clock()
        recorded_ns = self.record_ns
        self._advance(now)
        t4 = clock()
        record_ns = self.record_ns - recorded_ns
        ns = phases.ns
        ns["sense"] += t1 - t0
        ns["parameters"] += t2 - t1
        ns["servo"] += t3 - t2
        ns["physics"] += t4 - t3 - record_ns
        ns["record"] += record_ns
        phases.ticks += 1

    def _sense(self) -> tuple[float, int]:
        """The simulated time, in [s], and the noise row of this tick's sensor reading.

        The encoders and the sensor are read inside the servo's compiled call, from the
        plant's live buffers (:meth:`ServoLevel.command`).
        """
        plant = self.plant
        return plant.time_s, plant.next_noise_row()

    def _evaluate(self, now: float) -> None:
        """The parameter level (model, potential fields), then the next evaluation's time."""
        live = self._live
        self.evaluation = self.parameters.evaluate(live.positions, live.velocities)
        self.servo.set_evaluation(self.evaluation)
        self._evaluate_fields(now)
        self._next_param_s += self._param_period_s

    def _advance(self, now: float) -> float:
        """Record a sample due now, then step the physics to the next servo instant.

        The torque is held (zero-order hold); a sample due inside the hold is sensed
        on its own. Returns the simulated time reached, in [s]; the wall-clock
        nanoseconds spent recording are added to :attr:`record_ns`.
        """
        clock = time.perf_counter_ns
        record_ns = 0
        recorder = self.recorder
        if recorder is not None and now + self._eps_s >= self._next_state_s:
            r0 = clock()
            # The state as this tick sensed it; the wrench and the twist as the servo made them.
            servo = self.servo
            recorder.record(
                now, servo.sensed_q, servo.sensed_qd, servo.torque, servo.wrench, servo.last_velocity
            )
            self._next_state_s += self._state_period_s
            record_ns = clock() - r0
        plant = self.plant
        end = now + self._servo_period_s - self._eps_s
        t_s = now
        if self.contact_gate is not None:
            self.contact_gate.engage()
        while t_s < end:  # the servo wrote its torque to the drives: held until the next tick
            t_s = plant.advance()
            if recorder is not None and t_s < end and t_s + self._eps_s >= self._next_state_s:
                r0 = clock()
                self._record()
                self._next_state_s += self._state_period_s
                record_ns += clock() - r0
        if record_ns:
            self.record_ns += record_ns
        return t_s

    def _record(self) -> None:
        assert self.recorder is not None
        q, qd = self.plant.read_encoders()
        twist = self.evaluation.jacobian.dot(qd)
        self.recorder.record(self.plant.time_s, q, qd, self.tau, self._sense_wrench(), twist)
