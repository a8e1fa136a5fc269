"""The servo level of the two-level architecture (seed section 3, Figure 2).

Every servo tick, from the encoders, the wrist sensor and the latest parameter evaluation,
it estimates the operational position (the seed's estimator: ``x = x_e + J (q - q_e)``
between evaluations), forms the motion command F*_m (eq. 19 or 20-21) on the
motion-controlled axes and the active force command on the force-controlled ones (setpoint
fed forward, PI on the force error, velocity damping; on force-controlled moment axes, once
in contact, admittance control: the moment error sets a rotation speed that a velocity servo
tracks), and maps them to joint torques with the folded matrices of eq. 29, adding the
null-space damping of eq. 34, the potentials of section 6 and the posture (through the
task's null space where it has one: :mod:`cosmos.runtime.null_space`) and friction
compensation, saturated to the drives. The arithmetic is compiled
(:mod:`cosmos.runtime.kernels.servo`, :mod:`cosmos.runtime.kernels.parameter`).
"""

from __future__ import annotations

import numpy as np

from cosmos.osc.dynamics import DEFAULT_POLICY, SingularityPolicy
from cosmos.osc.force import Selection, selection
from cosmos.osc.null_space import DEFAULT_ABSORPTION, AbsorptionPolicy
from cosmos.osc.orientation import pose_error
from cosmos.osc.push_speed import approach_speed, push_aim
from cosmos.plant import LiveSignals
from cosmos.robot_model import GRAVITY
from cosmos.runtime.goal_line import goal_line, kept_line
from cosmos.runtime.kernels import cruise as cruise_kernel
from cosmos.runtime.kernels import live as live_kernel
from cosmos.runtime.kernels import servo as kernel
from cosmos.runtime.kernels.cruise import CRUISE_INTEGRAL, TRACKED_UNTIL, cruise_gains, tracked_until
from cosmos.runtime.kernels.evaluation import LIMIT_MARGIN
from cosmos.runtime.kernels.parameter import LIMITS_OFFSET, refold
from cosmos.runtime.null_space import LinkField, NullSpaceTerms
from cosmos.runtime.parameters import Evaluation
from cosmos.runtime.rotation_plan import ranges_for_goal
from cosmos.runtime.servo_gains import (
    LIMIT_PROJECTION_MARGIN_RAD,
    LIMIT_PROJECTION_WHOLE_RAD,
    held_push_at,
    touch_damping_for,
)
from cosmos.runtime.servo_gains import ServoGains as ServoGains  # the servo's gains, named here too
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

FloatArray = np.ndarray

_MODES = {MotionMode.HOLD: kernel.MODE_HOLD, MotionMode.GOAL: kernel.MODE_GOAL}


class ServoLevel:
    """Computes joint torques every servo tick; holds the force integral."""

    def __init__(
        self,
        gains: ServoGains,
        torque_limits: FloatArray,
        viscous: FloatArray,
        coulomb: tuple[FloatArray, FloatArray],
        servo_dt_s: float,
        tool_weight_z_n: float,
        policy: SingularityPolicy = DEFAULT_POLICY,
        joint_limits: tuple[FloatArray, FloatArray] | None = None,
        absorption: AbsorptionPolicy = DEFAULT_ABSORPTION,
        speed_noise_rad_s: FloatArray | None = None,
        joint_speed_limits_rad_s: FloatArray | float = 0.0,
    ):
        """Set up the buffers.

        Args:
            gains: Gains that hold for every segment.
            torque_limits: Drive limits, symmetric, in [N m]. # (n,)
            viscous: Viscous friction per joint, in [N m s/rad]. # (n,)
            coulomb: Coulomb friction per joint turning positively, then negatively, in [N m]. # 2 x (n,)
            servo_dt_s: Servo period, in [s].
            tool_weight_z_n: World z component of the weight below the wrist sensor, in [N].
            policy: Section 5's singularity thresholds.
            joint_limits: Lower and upper joint limits, in [rad]: a joint within
                LIMIT_PROJECTION_MARGIN_RAD of one that the goal drives it into gives up
                the rotation that needs it (cosmos.osc.limits.joint_limit_task_projection).
            absorption: When the potentials act through the task's null space only.
            speed_noise_rad_s: The sensed joint speed's noise, which the friction's intent
                ignores (:mod:`cosmos.osc.friction`), in [rad/s]; None: read exactly. # (n,)
            joint_speed_limits_rad_s: Kept by goal motions (:mod:`cosmos.osc.joint_speed`) [rad/s]; 0: none.
        """
        self.gains = gains
        self._fold_constants = np.array(
            (
                gains.force.k_vf,
                gains.xi_q,
                gains.coulomb_lookahead_s,
                policy.max_effective_mass_kg,
                policy.blend_width,
                policy.length_scale_m,
            )
        )
        if joint_limits is not None:  # then the limit projection's margins (kernels.parameter)
            margins = (LIMIT_PROJECTION_MARGIN_RAD, LIMIT_PROJECTION_WHOLE_RAD)
            self._fold_constants = np.concatenate((self._fold_constants, *joint_limits, margins))
        self._joint_limits: FloatArray | None = None  # the arm's ranges, as _limits_for_goal widens them
        self._viscous = np.array(viscous, dtype=float)
        n = self._dof = len(self._viscous)
        # One flat workspace holds every block the kernel reads and writes (servo_tick_live).
        vectors, matrices, jacobian, jbar, stacked, state, sensed, end, w = live_kernel.workspace_layout(n)
        workspace = self._workspace = np.zeros(end)
        scalars = workspace[:vectors]
        force = gains.force
        scalars[kernel.K_F : kernel.INTEGRAL_LIMIT + 1] = force.k_f, force.k_i, force.integral_limit
        scalars[kernel.CONTACT_THRESHOLD_N] = gains.contact_threshold_n
        scalars[kernel.DT_S] = servo_dt_s
        scalars[kernel.INTENT_SCALE] = 1.0 / gains.coulomb_velocity_rad_s
        scalars[kernel.COULOMB_BLEND] = min(1.0, servo_dt_s / gains.coulomb_filter_s)
        scalars[kernel.TOOL_WEIGHT_Z_N] = tool_weight_z_n
        scalars[kernel.ADMITTANCE_GAIN] = gains.admittance_gain
        scalars[kernel.ADMITTANCE_MAX_SPEED] = gains.admittance_max_speed_rad_s
        scalars[kernel.ADMITTANCE_KV] = gains.admittance_kv
        scalars[kernel.MOMENT_BLEND] = min(1.0, servo_dt_s / gains.moment_filter_s)
        scalars[kernel.LOOKAHEAD_S] = gains.coulomb_lookahead_s
        scalars[kernel.K_VF : kernel.FORCE_SPEED_KV + 1] = gains.force.k_vf, gains.force_speed_kv
        scalars[kernel.PUSH_SPEED_RATE] = gains.push_speed_rate  # cosmos.osc.push_speed
        scalars[kernel.MOTION_KI : kernel.MOTION_KI + 2] = gains.motion_ki, gains.motion_integral_limit_ms
        scalars[kernel.TILT_WINDOW :] = gains.insert_compliance
        scalars[kernel.HELD_PUSH : kernel.HELD_PUSH + 4] = held_push_at(gains.held_push, servo_dt_s)
        scalars[kernel.GOAL_INTEGRAL : kernel.GOAL_INTEGRAL + 5] = gains.goal_integral
        scalars[kernel.HELD_PUSH + 5] = tool_weight_z_n / float(GRAVITY[2])  # the tool's mass
        self._scalars = scalars
        # Rows of w = max(6, n): task-space rows use six entries, joint-space rows n (kernels.servo).
        self._vectors = workspace[vectors:matrices].reshape((kernel.VECTORS, w))
        self._vectors[kernel.COULOMB_NM, :n], self._vectors[kernel.COULOMB_NEGATIVE_NM, :n] = coulomb
        if speed_noise_rad_s is not None:
            self._vectors[kernel.COULOMB_DEAD_BAND, :n] = speed_noise_rad_s
        self._vectors[kernel.TORQUE_MAX, :n] = torque_limits
        self._vectors[kernel.JOINT_SPEED_MAX, :n] = joint_speed_limits_rad_s
        self._matrices = workspace[matrices:jacobian].reshape((kernel.MATRICES, 6, 6))
        self._jacobian = workspace[jacobian:jbar].reshape((6, n))
        self._jbar_lookahead = workspace[jbar:stacked].reshape((n, 6))
        self._null_space_t = np.zeros((n, n))  # N^T of the task, read by the null space's terms
        self._state = workspace[state:sensed].reshape((kernel.STATE_ROWS, w))
        self._sensed = workspace[sensed:end].reshape((live_kernel.SENSED_ROWS, w))
        self._setpoint: ServoSetpoint | None = None
        self._evaluation: Evaluation | None = None
        self._selection: Selection | None = None  # as the plan says
        self._servo_selection: Selection | None = None  # moment axes counted as motion (admittance)
        self._field_torque = np.zeros(n)
        self._field = LinkField(self._field_torque, self._field_torque)
        self._goal_line = np.zeros(3)  # a goal motion's line (cosmos.runtime.goal_line)
        self.null_space = NullSpaceTerms.of(gains, absorption)  # its dimension, the links' share
        self._correction = np.zeros(n)  # column 18: the raw potentials plus the null space's
        # (n, 19 + n): [J^T Lambda Omega | J^T Omega_bar | -k_vf J^T Omega_bar Lambda Omega_bar |
        # bias + held potentials | null-space and viscous damping], one product per tick.
        self._stacked = workspace[stacked:state].reshape((n, live_kernel.STACKED_COLUMNS + n))

    def set_tool_weight(self, tool_weight_z_n: float) -> None:
        """The world z component of the weight below the wrist sensor from now on [N] (a held payload)."""
        self._scalars[kernel.TOOL_WEIGHT_Z_N] = tool_weight_z_n
        self._scalars[kernel.HELD_PUSH + 5] = tool_weight_z_n / float(GRAVITY[2])  # osc.contact.touch_braking

    @property
    def torque(self) -> FloatArray:
        """Joint torques of the last tick, within the drive limits, in [N m]. # (n,)."""
        return self._state[kernel.TORQUE, : self._dof]

    @property
    def sensed_q(self) -> FloatArray:
        """Joint positions the last :meth:`command` sensed, in [rad]. # (n,)."""
        return self._sensed[live_kernel.SENSED_Q, : self._dof]

    @property
    def sensed_qd(self) -> FloatArray:
        """Joint velocities the last :meth:`command` sensed, in [rad/s]. # (n,)."""
        return self._sensed[live_kernel.SENSED_QD, : self._dof]

    @property
    def wrench(self) -> FloatArray:
        """The wrench the tool applied to the environment at the last tick, world [N, N m]. # (6,)."""
        return self._state[kernel.WRENCH, :6]

    @property
    def last_error(self) -> FloatArray:
        """``x - x_d`` of the last tick, world, [m, rad]. # (6,)."""
        return self._state[kernel.ERROR, :6]

    @property
    def last_velocity(self) -> FloatArray:
        """``J qd`` of the last tick, world, [m/s, rad/s]. # (6,)."""
        return self._state[kernel.VELOCITY, :6]

    @property
    def last_displacement(self) -> FloatArray:
        """``J (q - q_e)``: the motion since the evaluation, world, [m, rad]. # (6,)."""
        return self._state[kernel.DISPLACEMENT, :6]

    @property
    def field_torque(self) -> FloatArray:
        """Joint torques of the potential fields (obstacles), held between evaluations, as computed."""
        return self._field_torque

    @field_torque.setter
    def field_torque(self, torque: FloatArray) -> None:  # all on the tool's link: acts whole
        self.link_field = LinkField(torque, np.zeros_like(torque))

    @property
    def link_field(self) -> LinkField:
        """The obstacle field split into the tool's link and the others (cosmos.runtime.null_space)."""
        return self._field

    @link_field.setter
    def link_field(self, field: LinkField) -> None:
        torque = field.tool + field.links
        self._stacked[:, 18] += torque - self._field_torque
        self._field, self._field_torque = field, torque
        self._reshape()
        self._vectors[kernel.GOAL_LINE, :3] = kept_line(self._goal_line, field, self.null_space)

    @property
    def null_space_t(self) -> FloatArray:
        """``N^T = I - J^T Jbar^T`` of the task at the last evaluation (eq. 28, 34). # (n, n)."""
        return self._null_space_t

    def _reshape(self) -> None:
        """Shape the held potentials (and add the posture) through the null space, if there is one."""
        ev, sp, used = self._evaluation, self._setpoint, self._correction.any()
        if ev is None or sp is None or not (sp.orientation_free or self._dof > 6 or used):
            self.null_space.clear()  # the hold observer and the friction's intent with it
            return self.null_space.write(self._scalars, self._vectors, self._dof)  # no null space to use
        limit_margin, nst, field = float(ev.values[LIMIT_MARGIN]), self.null_space_t, self._field
        correction = self.null_space.correction(
            nst, ev, limit_margin, field, self._field_torque, sp.posture_rad
        )
        self._stacked[:, 18] += correction - self._correction
        self._correction = correction
        self.null_space.write(self._scalars, self._vectors, self._dof)

    @property
    def selection(self) -> Selection | None:
        """Omega and Omega_bar of the current segment, world axes."""
        return self._selection

    def set_setpoint(
        self,
        setpoint: ServoSetpoint,
        rotation_error: FloatArray | None = None,
        goal_q: FloatArray | None = None,
    ) -> None:
        """Start a segment; the force integral restarts when the selection changes.

        Args:
            setpoint: The segment's command.
            rotation_error: The orientation error ``x - x_d`` to start from, world, in [rad]
                (:mod:`cosmos.runtime.rotation_plan`: norm above pi to turn the long way
                round); None for the shortest rotation. # (3,)
            goal_q: The goal's configuration, where a planned path within the joints' ranges
                ends (:mod:`cosmos.runtime.rotation_plan`), in [rad]; None: none planned. # (n,)
        """
        self._limits_for_goal(goal_q)
        previous, state = self._setpoint, self._state
        if previous is None or (
            previous.motion_axes != setpoint.motion_axes
            or previous.orientation_free != setpoint.orientation_free
            or not np.array_equal(previous.rotation_task_to_world, setpoint.rotation_task_to_world)
        ):
            state[kernel.INTEGRAL] = 0.0
            self._selection = selection(setpoint.motion_axes, setpoint.rotation_task_to_world)
            # Force-controlled moment axes run admittance control: for the servo they are
            # motion axes whose speed the moment error sets (kernels.servo.servo_tick).
            axes = tuple(setpoint.motion_axes[:3]) + (True, True, True)
            self._servo_selection = selection(axes, setpoint.rotation_task_to_world)
            self._servo_selection.omega[3:, 3:] *= not setpoint.orientation_free  # FREE: Lambda_r
            self._matrices[kernel.OMEGA_ADMITTANCE] = (
                self._selection.omega_bar - self._servo_selection.omega_bar
            )
        state[kernel.MOMENT_FILTERED] = state[kernel.WRENCH]  # both task rows: w long, six used
        state[kernel.FLAGS] = 0.0  # the latches, the held push's integral, the hold observer's start
        state[kernel.MOTION_INTEGRAL] = 0.0
        scalars, vectors = self._scalars, self._vectors
        tracking = setpoint.mode is MotionMode.TRAJECTORY and setpoint.trajectory is not None
        scalars[kernel.MODE] = (
            kernel.MODE_TRAJECTORY if tracking else _MODES.get(setpoint.mode, kernel.MODE_HOLD)
        )
        scalars[kernel.UNIFORM] = float(setpoint.uniform_gains)
        # A touch is looked for where gains are given per axis (a COMPLY spring expects contact),
        # and from its first felt push in a CONTACT's approach (cosmos.osc.contact.touch_braking).
        touch_n, touch_damping, landing_speed = touch_damping_for(self.gains, setpoint, scalars[kernel.DT_S])
        scalars[kernel.HELD_PUSH + 4], scalars[kernel.HELD_PUSH + 6] = touch_n, touch_damping
        scalars[kernel.TOUCH_FREE_SPEED] = landing_speed
        scalars[kernel.HAS_FORCE] = float(not all(setpoint.motion_axes[:3]))
        scalars[kernel.ADMITTANCE] = float(not all(setpoint.motion_axes[3:]))
        speed = approach_speed(setpoint.max_speed, self.gains.approach_speed_margin_mps)  # osc.push_speed
        scalars[kernel.MAX_SPEED] = speed if setpoint.insert_approach else setpoint.max_speed
        gains, dt_s, sp = self.gains, scalars[kernel.DT_S], setpoint
        scalars[CRUISE_INTEGRAL : kernel.PUSH_SPEED_RATE] = cruise_gains(gains.cruise_integral, dt_s, sp)
        scalars[TRACKED_UNTIL] = tracked_until(sp)  # a slow MOVE's reference (kernels.cruise)
        aim = push_aim(setpoint.max_speed, gains.push_speed_aim, gains.push_speed_margin_mps)
        scalars[kernel.PUSH_SPEED] = aim if setpoint.limit_push_speed else 0.0  # cosmos.osc.push_speed
        scalars[kernel.MAX_ANGULAR_SPEED] = setpoint.max_angular_speed
        accelerations = setpoint.acceleration, setpoint.angular_acceleration
        scalars[kernel.GOAL_ACCELERATION : kernel.GOAL_ANGULAR_ACCELERATION + 1] = accelerations
        scalars[kernel.TRAJECTORY_END_S] = sp.start_s + (sp.trajectory.duration_s if sp.trajectory else 0.0)
        scalars[kernel.START_S], scalars[kernel.RAMP_S] = setpoint.start_s, setpoint.ramp_s
        vectors[kernel.KP, :6], vectors[kernel.KV, :6] = setpoint.kp_task, setpoint.kv_task
        vectors[kernel.SPRINGS, :6] = setpoint.spring_masses  # a COMPLY spring's (kernels.spring)
        vectors[kernel.FORCE_WORLD, :6] = setpoint.force_world
        vectors[kernel.FORCE_START, :6] = setpoint.force_start_world
        vectors[kernel.REFERENCE_VELOCITY : kernel.REFERENCE_ACCELERATION + 1] = 0.0
        start = None if self._evaluation is None else self._evaluation.position
        line = self._goal_line = goal_line(start, setpoint.position, setpoint.mode is MotionMode.GOAL)
        # The goal motion's speed limits ramp up from the tool's speeds; the cruise's integral restarts
        # or, on a MOVE ... VIA's next leg, carries on (kernels.cruise.restart).
        speeds = cruise_kernel.restart(state, previous, sp, vectors[kernel.GOAL_LINE, :3], line, scalars)
        scalars[kernel.GOAL_START_SPEED : kernel.GOAL_START_ANGULAR_SPEED + 1] = speeds
        vectors[kernel.GOAL_LINE] = 0.0
        vectors[kernel.GOAL_LINE, :3] = kept_line(self._goal_line, self._field, self.null_space)
        # refold unwraps the orientation error against the row's content: the way round to start.
        vectors[kernel.REFERENCE_ERROR, 3:6] = 0.0 if rotation_error is None else rotation_error
        self._matrices[kernel.ROTATION_TASK, :3, :3] = setpoint.rotation_task_to_world
        self._setpoint = setpoint
        self._refold()

    @property
    def singular_projection(self) -> FloatArray:
        """Section 5's task projection P of the last evaluation (I far from singularities). # (6, 6)."""
        return self._matrices[kernel.SINGULAR_PROJECTION]

    def set_evaluation(self, evaluation: Evaluation) -> None:
        """Take a new parameter evaluation (the lower-rate level's output)."""
        self._evaluation = evaluation
        self._refold()

    def _limits_for_goal(self, goal_q: FloatArray | None) -> None:
        """Set the joint ranges the task's limit projection sees.

        The arm's, widened for a goal within the projection's margin of a limit
        (:func:`cosmos.runtime.rotation_plan.ranges_for_goal`).
        """
        constants, n = self._fold_constants, self._dof
        if constants.shape[0] <= LIMITS_OFFSET:
            return
        if self._joint_limits is None:
            self._joint_limits = constants[LIMITS_OFFSET : LIMITS_OFFSET + 2 * n].copy()
        ranges = self._joint_limits[:n], self._joint_limits[n:]
        lower, upper = ranges_for_goal(*ranges, goal_q, LIMIT_PROJECTION_MARGIN_RAD)
        constants[LIMITS_OFFSET : LIMITS_OFFSET + n] = lower
        constants[LIMITS_OFFSET + n : LIMITS_OFFSET + 2 * n] = upper

    def _refold(self) -> None:
        ev, sp, sel = self._evaluation, self._setpoint, self._servo_selection
        if ev is None or sp is None or sel is None:
            return
        refold(
            ev.values,
            ev.joint_limit_torque + self._field_torque,
            sel.omega,
            sel.omega_bar,
            sp.position,
            np.ascontiguousarray(sp.rotation_to_world),
            self._fold_constants,
            self._viscous,
            self._stacked,
            self._vectors,
            self._matrices,
            self._jacobian,
            self._jbar_lookahead,
            self._null_space_t,
        )
        self._correction[:] = 0.0  # the column holds the raw potentials again
        self.null_space.link_share_to_tool = 0.0
        self._reshape()

    def command(self, t_s: float, live: LiveSignals, noise_row: int) -> None:
        """Compute the tick's joint torques from the plant's live signals; write them to its drives.

        What it sensed stays in :attr:`sensed_q`, :attr:`sensed_qd`, the torque (within
        the drive limits) in :attr:`torque`, until the next tick.

        Args:
            t_s: Simulated time, in [s].
            live: The plant's encoders, wrist sensor and drives (:meth:`Plant.live_signals`).
            noise_row: The row of ``live.noise`` this tick's sensor reading takes.
        """
        ev, sp = self._evaluation, self._setpoint
        if ev is None or sp is None:
            raise RuntimeError("servo level used before a setpoint and an evaluation were given")
        if sp.trajectory is not None and sp.mode is MotionMode.TRAJECTORY:
            sample = sp.trajectory.sample(t_s - sp.start_s)
            vectors = self._vectors
            vectors[kernel.REFERENCE_ERROR, :6] = pose_error(
                ev.position, ev.rotation_tool_to_world, sample.position, sample.rotation_to_world
            )
            vectors[kernel.REFERENCE_VELOCITY, :6] = sample.velocity
            vectors[kernel.REFERENCE_ACCELERATION, :6] = sample.acceleration
        live_kernel.servo_tick_live(
            t_s,
            live.positions,
            live.velocities,
            live.wrench_raw,
            live.noise,
            noise_row,
            live.ctrl,
            self._workspace,
        )
