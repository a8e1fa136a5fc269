"""The servo level of the two-level architecture (seed section 3, Figure 2).

Every servo tick, from the encoders, the wrist sensor and the latest parameter
evaluation, it estimates the operational position (the seed's estimator:
``x = x_e + J (q - q_e)`` between evaluations), forms the motion command
F*_m (eq. 19 or 20-21) on the motion-controlled axes and the active force
command on the force-controlled ones (setpoint fed forward, PI on the force
error, velocity damping), and maps them to joint torques with the folded
matrices of eq. 29, adding the null-space damping of eq. 34, the joint-limit
potential of section 6 and friction compensation, saturated to the drives.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cosmos.osc.force import Selection, selection
from cosmos.osc.limits import saturate_torque
from cosmos.osc.motion import goal_command, tracking_command
from cosmos.osc.orientation import pose_error
from cosmos.osc.unified import (
    ForceGains,
    ServoMatrices,
    force_feedback,
    integrate_force_error,
)
from cosmos.runtime.parameters import Evaluation, fold_for_servo
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

FloatArray = np.ndarray


@dataclass(frozen=True)
class ServoGains:
    """Gains of the servo level that do not change from segment to segment.

    Attributes:
        force: Force-loop gains on force-controlled axes.
        xi_q: Null-space joint damping of eq. 34, in [1/s].
        contact_threshold_n: Sensed force on the force-controlled axes above which the
            tool counts as touching for the rest of the segment: from then on the force
            error is integrated (in free space it would wind up), [N].
        coulomb_velocity_rad_s: Joint speed over which the Coulomb friction
            compensation ramps from 0 to its full value, in [rad/s].
        coulomb_lookahead_s: How far ahead the commanded joint acceleration counts
            toward the direction of motion, in [s].
        coulomb_filter_s: Time constant of the low-pass on the Coulomb compensation, [s].
    """

    force: ForceGains = ForceGains(k_f=0.6, k_i=12.0, k_vf=30.0, integral_limit=5.0)
    xi_q: float = 20.0
    contact_threshold_n: float = 1.0
    coulomb_velocity_rad_s: float = 0.01
    coulomb_lookahead_s: float = 0.02
    coulomb_filter_s: float = 0.005


_NO_FORCE = np.zeros(6)
_NO_FORCE.setflags(write=False)
_ONE = np.ones(1)


def _rotate_blocks(rotation: FloatArray, vector: FloatArray) -> FloatArray:
    return np.concatenate((rotation.dot(vector[:3]), rotation.dot(vector[3:])))


class ServoLevel:
    """Computes joint torques every servo tick; holds the force integral."""

    def __init__(
        self,
        gains: ServoGains,
        torque_limits: FloatArray,
        viscous: FloatArray,
        coulomb: FloatArray,
        servo_dt_s: float,
    ):
        self.gains = gains
        self._torque_limits = torque_limits
        self._viscous = viscous
        self._coulomb = coulomb
        self._dt_s = servo_dt_s
        self._coulomb_blend = min(1.0, servo_dt_s / gains.coulomb_filter_s)
        self._coulomb_torque = np.zeros(6)
        self._intent_scale = 1.0 / gains.coulomb_velocity_rad_s
        self._integral = np.zeros(6)
        self._setpoint: ServoSetpoint | None = None
        self._evaluation: Evaluation | None = None
        self._selection: Selection | None = None
        self._touching = False
        self._has_force_axes = False
        self._force_to_acceleration = np.zeros((6, 6))  # Lambda^-1 Omega_bar
        self._base_error = np.zeros(6)
        self.last_error = np.zeros(6)  # x - x_d of the last tick, world, [m, rad]
        self.last_displacement = np.zeros(6)  # J (q - q_e): motion since the evaluation
        self.last_velocity = np.zeros(6)  # J qd of the last tick, world, [m/s, rad/s]
        self._field_torque = np.zeros(6)
        self._matrices: ServoMatrices | None = None
        # (6, 25): [J^T Lambda Omega | J^T Omega_bar | -k_vf J^T Omega_bar Lambda Omega_bar |
        # bias + held potentials | null-space and viscous damping], one product per tick.
        self._stacked = np.zeros((6, 25))
        self._jbar_lookahead = np.zeros((6, 6))

    @property
    def field_torque(self) -> FloatArray:
        """Joint torques of the potential fields (obstacles), held between evaluations."""
        return self._field_torque

    @field_torque.setter
    def field_torque(self, torque: FloatArray) -> None:
        self._field_torque = torque
        if self._evaluation is not None and self._matrices is not None:
            self._stacked[:, 18] = self._matrices.bias_torque + self._evaluation.joint_limit_torque + torque

    @property
    def selection(self) -> Selection | None:
        """Omega and Omega_bar of the current segment, world axes."""
        return self._selection

    def set_setpoint(self, setpoint: ServoSetpoint) -> None:
        """Start a segment; the force integral restarts when the selection changes."""
        previous = self._setpoint
        if previous is None or (
            previous.motion_axes != setpoint.motion_axes
            or not np.array_equal(previous.rotation_task_to_world, setpoint.rotation_task_to_world)
        ):
            self._integral = np.zeros(6)
            self._selection = selection(setpoint.motion_axes, setpoint.rotation_task_to_world)
            self._has_force_axes = not all(setpoint.motion_axes)
        self._setpoint = setpoint
        self._touching = False  # latched by the first push felt on a force axis
        self._refold()

    def set_evaluation(self, evaluation: Evaluation) -> None:
        """Take a new parameter evaluation (the lower-rate level's output)."""
        self._evaluation = evaluation
        self._refold()

    def _refold(self) -> None:
        ev, sp, sel = self._evaluation, self._setpoint, self._selection
        if ev is None or sp is None or sel is None:
            return
        self._force_to_acceleration = ev.dynamics.lambda_inv.dot(sel.omega_bar)
        matrices, null_damping = fold_for_servo(ev, sel, self.gains.force, self.gains.xi_q)
        self._matrices = matrices
        # Per-tick joint-space terms folded in too: null-space damping (eq. 34) with the
        # viscous friction, and the potentials held since the last evaluation.
        stacked = np.empty((6, 25))
        stacked[:, :19] = matrices.stacked
        stacked[:, 18] += ev.joint_limit_torque + self._field_torque
        stacked[:, 19:] = null_damping
        stacked[:, 19:] += np.diag(self._viscous)
        self._stacked = stacked
        self._jbar_lookahead = self.gains.coulomb_lookahead_s * ev.dynamics.jbar
        self._base_error = pose_error(
            ev.position, ev.rotation_tool_to_world, sp.position, sp.rotation_to_world
        )

    def command(self, t_s: float, q: FloatArray, qd: FloatArray, wrench_env: FloatArray) -> FloatArray:
        """Joint torques for this tick.

        Args:
            t_s: Simulated time, in [s].
            q: Joint positions from the encoders, in [rad]. # (6,)
            qd: Joint velocities, in [rad/s]. # (6,)
            wrench_env: Sensed wrench the tool applies to the environment, world, [N, N m]. # (6,)

        Returns:
            Joint torques within the drive limits, in [N m]. # (6,)
        """
        ev, sp, matrices, sel = self._evaluation, self._setpoint, self._matrices, self._selection
        if ev is None or sp is None or matrices is None or sel is None:
            raise RuntimeError("servo level used before a setpoint and an evaluation were given")
        jacobian = ev.jacobian
        velocity = jacobian.dot(qd)
        displacement = jacobian.dot(q - ev.q)
        self.last_velocity, self.last_displacement = velocity, displacement
        motion = self._motion_command(t_s, sp, ev, displacement, velocity)
        acceleration = motion
        if self._has_force_axes:
            feedback = self._force_feedback(t_s, sp, sel, wrench_env)
            if not self._touching:
                acceleration = motion + self._force_to_acceleration.dot(feedback)
        else:
            feedback = _NO_FORCE
        torque = self._stacked.dot(np.concatenate((motion, feedback, velocity, _ONE, qd)))
        # Coulomb friction is compensated in the direction the joint is moving or, from rest,
        # is being told to move: qd plus the commanded joint acceleration (Jbar F*_m, and in
        # free space Jbar Lambda^-1 F_a on the force axes) over a short look-ahead, so a joint
        # starting to move is not held back by its friction. In contact the force loop's
        # integral takes up the friction instead: switching friction torques on the sensed
        # force would chatter.
        intent = (qd + self._jbar_lookahead.dot(acceleration)) * self._intent_scale
        # Low-passed, so that a new segment's setpoint (or a sign change) never steps it.
        target = self._coulomb * np.minimum(np.maximum(intent, -1.0), 1.0)
        self._coulomb_torque += self._coulomb_blend * (target - self._coulomb_torque)
        torque += self._coulomb_torque
        saturated, _ = saturate_torque(torque, self._torque_limits, keep=ev.gravity)
        return saturated

    def _force_feedback(
        self, t_s: float, sp: ServoSetpoint, sel: Selection, wrench_env: FloatArray
    ) -> FloatArray:
        """F_d + k_f (F_d - F_s) + k_i integral: the setpoint ramped from the sensed force."""
        elapsed = t_s - sp.start_s
        if elapsed >= sp.ramp_s:
            force_setpoint = sp.force_world
        else:
            force_setpoint = sp.force_start_world + (elapsed / sp.ramp_s) * (
                sp.force_world - sp.force_start_world
            )
        gains = self.gains.force
        # Integral action only once something pushes back (latched for the segment): in
        # free space the force error cannot be closed and would wind up into an impact.
        if not self._touching:
            pushed = float(np.abs(sel.omega_bar.dot(wrench_env)).max())
            self._touching = pushed > self.gains.contact_threshold_n
        if self._touching:
            self._integral = integrate_force_error(
                self._integral, force_setpoint, wrench_env, sel.omega_bar, self._dt_s, gains.integral_limit
            )
        return force_feedback(force_setpoint, wrench_env, self._integral, gains)

    def _motion_command(
        self,
        t_s: float,
        sp: ServoSetpoint,
        ev: Evaluation,
        displacement: FloatArray,
        velocity: FloatArray,
    ) -> FloatArray:
        velocity_desired = acceleration_desired = None
        if sp.mode is MotionMode.TRAJECTORY and sp.trajectory is not None:
            sample = sp.trajectory.sample(t_s - sp.start_s)
            error = pose_error(
                ev.position, ev.rotation_tool_to_world, sample.position, sample.rotation_to_world
            )
            error += displacement
            self.last_error = error
            velocity_desired, acceleration_desired = sample.velocity, sample.acceleration
        else:
            error = self._base_error + displacement
        self.last_error = error
        if sp.uniform_gains:
            return self._unit_mass_command(
                sp,
                error,
                velocity,
                velocity_desired,
                acceleration_desired,
                sp.kp_task[0],
                sp.kv_task[0],
            )
        r_t = sp.rotation_task_to_world.T
        command_task = self._unit_mass_command(
            sp,
            _rotate_blocks(r_t, error),
            _rotate_blocks(r_t, velocity),
            None if velocity_desired is None else _rotate_blocks(r_t, velocity_desired),
            None if acceleration_desired is None else _rotate_blocks(r_t, acceleration_desired),
            sp.kp_task,
            sp.kv_task,
        )
        return _rotate_blocks(sp.rotation_task_to_world, command_task)

    @staticmethod
    def _unit_mass_command(
        sp: ServoSetpoint,
        error: FloatArray,
        velocity: FloatArray,
        velocity_desired: FloatArray | None,
        acceleration_desired: FloatArray | None,
        kp: float | FloatArray,
        kv: float | FloatArray,
    ) -> FloatArray:
        if sp.mode is MotionMode.GOAL:
            return goal_command(error, velocity, kp, kv, sp.max_speed, sp.max_angular_speed)
        if velocity_desired is None or acceleration_desired is None:
            return -kp * error - kv * velocity  # eq. 19 with a constant x_d
        return tracking_command(error, velocity, velocity_desired, acceleration_desired, kp, kv)
