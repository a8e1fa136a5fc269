"""The servo level's per-tick arithmetic, compiled (numba): one call per servo tick.

The maths are those of :mod:`cosmos.osc` (the readable reference; against it
``tests/runtime/test_servo_kernel.py`` checks a whole tick on seeded random inputs): the wrench the tool
applies from the wrist sensor (:func:`cosmos.runtime.wrench.environment_wrench`), the estimator
``x = x_e + J (q - q_e)`` (section 3), the motion command (eq. 19, eq. 20-21, :mod:`cosmos.osc.motion`), the
active force command (F_d fed forward, PI on the force error with its anti-windup clamp, eq. 17-18 and Figure
2, :func:`cosmos.osc.unified.integrate_force_error` and :func:`cosmos.osc.unified.force_feedback`, integral
action only once :func:`cosmos.osc.contact.touch_latched`), a push held to its SPEED
(:func:`cosmos.osc.unified.speed_limited_push`) or at a surface (:func:`cosmos.osc.held_push.held_push`), a
slide's integral action (:func:`cosmos.osc.integral_action.integrate_motion_error`) and surface friction
(:mod:`cosmos.osc.surface_friction`), a free hold's disturbance observer while the null space is driven
(:mod:`cosmos.runtime.kernels.hold_observer`) or, on compliant moment axes in contact, admittance control
(:mod:`cosmos.osc.admittance`; an INSERT's within its tilt window, :mod:`cosmos.osc.tilt_window`), eq. 29's
single product with the folded matrix (:func:`cosmos.osc.unified.servo_torque`), Coulomb friction compensation
(:mod:`cosmos.osc.friction`; toward the null space's intent too; its levels' error learnt,
:mod:`cosmos.runtime.kernels.friction_adaptation`) and the saturation that scales the command about gravity
(:func:`cosmos.osc.limits.saturate_torque`). Pieces with a kernel of their own are in
:mod:`cosmos.runtime.kernels.commands`, :mod:`cosmos.runtime.kernels.contact` and
:mod:`cosmos.runtime.kernels.spring` (COMPLY springs). Results are written in place into the arrays passed
(``state``, ``out``), so a tick creates no Python objects.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.runtime.kernels import commands, spring
from cosmos.runtime.kernels.commands import (
    environment_wrench_into,
    saturate_about,
    slide_integral_into,
    unit_mass_command_into,
)
from cosmos.runtime.kernels.contact import (
    admittance_command,
    admittance_speed,
    contact_latched,
    coulomb_compensation_into,
    force_goal_latched,
    insert_compliance_into,
    integrated_force_error,
    low_pass_into,
    touch_braking_into,
    touch_latched,
)
from cosmos.runtime.kernels.cruise import CRUISE, CRUISE_INTEGRAL, cruise_into, landing_into, reference_speed
from cosmos.runtime.kernels.friction_adaptation import adapted_levels
from cosmos.runtime.kernels.held_push import held_push_capped_into
from cosmos.runtime.kernels.hold_observer import hold_observer_into
from cosmos.runtime.kernels.joint_speed import JOINT_SPEED_MAX, joint_speed_limited
from cosmos.runtime.kernels.linear import matvec, rotate_blocks
from cosmos.runtime.kernels.push_speed import push_at_speed_into
from cosmos.runtime.kernels.spring import SPRING_LAW, SPRING_ROWS, SPRINGS, spring_law_into
from cosmos.runtime.kernels.surface_friction import SURFACE, surface_friction_into

FloatArray = np.ndarray

# The kernel's inputs travel in a few packed arrays (a compiled call costs about 0.1 us per
# argument); these are their layouts.

# ``scalars``: segment and constant scalars.
MODE, UNIFORM, HAS_FORCE, MAX_SPEED, MAX_ANGULAR_SPEED, START_S, RAMP_S = range(7)
K_F, K_I, INTEGRAL_LIMIT, CONTACT_THRESHOLD_N, DT_S = range(7, 12)
INTENT_SCALE, COULOMB_BLEND, TOOL_WEIGHT_Z_N = range(12, 15)
ADMITTANCE, ADMITTANCE_GAIN, ADMITTANCE_MAX_SPEED, ADMITTANCE_KV, MOMENT_BLEND, LOOKAHEAD_S = range(15, 21)
K_VF, FORCE_SPEED_KV, PUSH_SPEED = range(21, 24)
MOTION_KI, MOTION_INTEGRAL_LIMIT, TRAJECTORY_END_S, HELD_PUSH = range(24, 28)
TILT_WINDOW = 63  # an INSERT's compliant axes: theta_w, k_w, d_in, theta_in, k_in, s, v_s (osc.tilt_window)
GOAL_ACCELERATION, GOAL_ANGULAR_ACCELERATION, GOAL_START_SPEED, GOAL_START_ANGULAR_SPEED = range(36, 40)
GOAL_INTEGRAL = 40  # a free goal motion's integral: k_i, then integrate_goal_error's gate (5 slots)
HOLD_OBSERVER = 45  # a free hold's disturbance observer: L [1/s], bound [m/s^2], band [m], quiet [N]
PUSH_SPEED_RATE = 56  # an INSERT's push: its speed reference's rise [1/s] (cosmos.osc.push_speed)
TOUCH_FREE_SPEED = 58  # the speed a touch's damping leaves the motion into it [m/s] (osc.contact)
SCALARS = 70  # 34-35 free; 49-55, 57, 59-62: kernels.cruise
# HELD_PUSH's seven (27-33): k_fh, k_ih, k_vh, limit; touch force, mass, k_v
MODE_HOLD, MODE_GOAL, MODE_TRAJECTORY = commands.MODE_HOLD, commands.MODE_GOAL, commands.MODE_TRAJECTORY

# Rows of ``vectors`` and ``state`` are ``w = max(6, n)`` long for an arm of n joints: the
# task-space rows (wrenches, twists, gains) use their first six entries, the joint-space rows
# (EVALUATION_Q, GRAVITY, COULOMB_NM, TORQUE_MAX, COULOMB_NEGATIVE_NM, COULOMB_DEAD_BAND; COULOMB,
# TORQUE) their first n. COULOMB_NM is the Coulomb friction turning positively, COULOMB_NEGATIVE_NM
# negatively; COULOMB_DEAD_BAND the sensed speed's noise the friction's intent ignores [rad/s].

# ``vectors``. REFERENCE_*: ``x_e - x_d`` at the evaluation (tracking: at this
# tick's trajectory sample), ``xd_d`` and ``xdd_d``. SENSOR_OFFSETS: tool point then tool
# centre of mass, minus the sensor origin, world, [m].
KP, KV, FORCE_WORLD, FORCE_START, REFERENCE_ERROR, REFERENCE_VELOCITY, REFERENCE_ACCELERATION = range(7)
EVALUATION_Q, GRAVITY, SENSOR_OFFSETS, COULOMB_NM, TORQUE_MAX, COULOMB_NEGATIVE_NM = range(7, 13)
COULOMB_DEAD_BAND = 13
GOAL_LINE = 14  # a goal motion's unit line from its start to its goal, world (zeros: none)
HOLD_KNOWN = 15  # what a free hold's observer expects of the potentials, world [m/s^2]
NULL_INTENT = 16  # joint speeds the null space's torques ask over the friction's look-ahead [rad/s]
VECTORS = max(SPRINGS, JOINT_SPEED_MAX) + 1  # kernels.spring's and kernels.joint_speed's rows

# ``matrices``, (6, 6) each; rotations in the top-left (3, 3). The Jacobian J (6, n), the
# look-ahead ``L Jbar P`` (n, 6) and the task's null space ``N^T`` (n, n) are blocks of their own.
FORCE_TO_ACCELERATION, OMEGA_BAR, ROTATION_TASK, ROTATION_SENSOR = range(4)
OMEGA_ADMITTANCE, SINGULAR_PROJECTION, MATRICES = 4, 5, 6  # see servo_tick; P (kernels.parameter)

# Rows of the servo's state and outputs (``state``, (STATE_ROWS, w)).
WRENCH, ERROR, VELOCITY, DISPLACEMENT, INTEGRAL, COULOMB, TORQUE, FLAGS, MOMENT_FILTERED = range(9)
MOTION_INTEGRAL = 9  # integral of the translation error: a slide's in contact, a goal's near it [m s]
FRICTION_ERROR = SPRING_LAW + SPRING_ROWS  # each joint's Coulomb error (kernels.friction_adaptation)
STATE_ROWS = SURFACE + 1  # CRUISE, SPRING_LAW, SURFACE: kernels.cruise's, spring's, surface_friction's rows
TOUCHING, ADMITTING = 0, 1  # columns of FLAGS: 1.0 once the tool felt a push on a force axis, any force
REACHED, HELD_INTEGRAL = 2, 3  # FLAGS: 1 once the push reached REACH_FRACTION; a held push's integral [N s]
OBSERVING = 4  # FLAGS: 1 once a free hold's disturbance observer has its first velocity

# Rows of a tick's work array (servo_tick).
MOTION, FEEDBACK, COMMANDED_SPEED, SETPOINT, ACCELERATION, SLIDE, SCRATCH_ROWS = range(7)  # and their count


@kernel
def servo_tick(
    t_s: float,
    q: FloatArray,
    qd: FloatArray,
    sensor: FloatArray,
    scalars: FloatArray,
    vectors: FloatArray,
    matrices: FloatArray,
    jacobian: FloatArray,
    jbar_lookahead: FloatArray,
    stacked: FloatArray,
    state: FloatArray,
) -> None:
    """One servo tick: sensed wrench, estimate, motion and force commands, joint torques.

    Args:
        t_s: Simulated time, in [s].
        q: Joint positions from the encoders, in [rad]. # (n,)
        qd: Joint velocities, in [rad/s]. # (n,)
        sensor: Raw wrist sensor reading (sensor frame), [N, N m]. # (6,)
        scalars: Segment and constant scalars at MODE ... LOOKAHEAD_S. # (SCALARS,)
        vectors: Gains, setpoints, reference and the evaluation's vectors at KP ... # (VECTORS, w)
        matrices: Lambda^-1 Omega_bar, Omega_bar, projections and rotations. # (MATRICES, 6, 6)
        jacobian: J at the evaluation, world. # (6, n)
        jbar_lookahead: The look-ahead ``L Jbar P``. # (n, 6)
        stacked: Eq. 29 folded: ``Gamma = stacked @ (F*_m, F_fb, xd, 1, qd)``. # (n, 19 + n)
        state: Integral, friction and moment filters and flags in; this tick's wrench,
            error, velocity, displacement and torque out (rows WRENCH ...). # (STATE_ROWS, w)
    """
    n = stacked.shape[0]
    wrench = state[WRENCH, :6]
    offsets = vectors[SENSOR_OFFSETS, :6]
    environment_wrench_into(
        wrench, sensor, matrices[ROTATION_SENSOR], offsets[:3], offsets[3:], scalars[TOOL_WEIGHT_Z_N]
    )
    work = np.empty((SCRATCH_ROWS, 6))  # this tick's work rows (one allocation; written in place below)
    velocity, displacement, error = state[VELOCITY, :6], state[DISPLACEMENT, :6], state[ERROR, :6]
    evaluation_q, reference_error = vectors[EVALUATION_Q, :n], vectors[REFERENCE_ERROR, :6]
    for i in range(6):
        v = 0.0
        d = 0.0
        for k in range(n):
            v += jacobian[i, k] * qd[k]
            d += jacobian[i, k] * (q[k] - evaluation_q[k])
        velocity[i] = v
        displacement[i] = d
        error[i] = reference_error[i] + d  # x - x_d with x = x_e + J (q - q_e)

    mode, kp, kv = scalars[MODE], vectors[KP, :6], vectors[KV, :6]
    velocity_desired = vectors[REFERENCE_VELOCITY, :6]
    acceleration_desired = vectors[REFERENCE_ACCELERATION, :6]
    max_speed, max_angular_speed = scalars[MAX_SPEED], scalars[MAX_ANGULAR_SPEED]
    if mode == MODE_GOAL:  # eq. 21's limits ramp up from the start's speeds (osc.motion.ramped_speed_limit)
        since = max(t_s - scalars[START_S], 0.0)
        max_speed = min(max_speed, scalars[GOAL_START_SPEED] + scalars[GOAL_ACCELERATION] * since)
        max_angular_speed = min(
            max_angular_speed, scalars[GOAL_START_ANGULAR_SPEED] + scalars[GOAL_ANGULAR_ACCELERATION] * since
        )
        max_speed = landing_into(max_speed, error, vectors[GOAL_LINE, :3], scalars, state)  # osc.landing
        eq21 = (error, kp, kv, matrices[ROTATION_TASK], scalars[UNIFORM] != 0.0)  # within the joints':
        joint_args = (jbar_lookahead, scalars[LOOKAHEAD_S], vectors[JOINT_SPEED_MAX, :n])  # osc.joint_speed
        max_speed, max_angular_speed = joint_speed_limited(max_speed, max_angular_speed, *eq21, *joint_args)
    admittance = False
    if scalars[ADMITTANCE] != 0.0:
        # Compliant moment axes give way to contact moments: from the first contact force
        # on (latched for the segment) they run admittance control; in free space, where
        # there is nothing to comply with, they hold the segment's orientation.
        low_pass_into(state[MOMENT_FILTERED, :6], wrench, scalars[MOMENT_BLEND])
        flags = state[FLAGS]
        if contact_latched(flags[ADMITTING] != 0.0, wrench, scalars[CONTACT_THRESHOLD_N]):
            flags[ADMITTING] = 1.0
        admittance = flags[ADMITTING] != 0.0
    tilt = np.zeros(6)
    if admittance:  # no position goal on the moment axes under admittance control
        omega_admittance = matrices[OMEGA_ADMITTANCE]
        tilt = matvec(omega_admittance, error)
        error = error - tilt
        velocity_desired = velocity_desired - matvec(omega_admittance, velocity_desired)
        acceleration_desired = acceleration_desired - matvec(omega_admittance, acceleration_desired)
    if scalars[UNIFORM] != 0.0:
        motion = work[MOTION]
        unit_mass_command_into(
            motion,
            mode,
            error,
            velocity,
            velocity_desired,
            acceleration_desired,
            kp,
            kv,
            max_speed,
            max_angular_speed,
            vectors[GOAL_LINE, :3],
        )
    else:  # per-axis gains are along the task frame's axes
        r = matrices[ROTATION_TASK]
        motion_task = np.empty(6)
        unit_mass_command_into(
            motion_task,
            mode,
            rotate_blocks(r, error, True),
            rotate_blocks(r, velocity, True),
            rotate_blocks(r, velocity_desired, True),
            rotate_blocks(r, acceleration_desired, True),
            kp,
            kv,
            max_speed,
            max_angular_speed,
            rotate_blocks(r, vectors[GOAL_LINE, :6], True)[:3],
        )
        motion = rotate_blocks(r, motion_task, False)
    fed_back = motion - acceleration_desired  # F*_fb: it teaches the Coulomb levels (osc.friction)
    if scalars[HAS_FORCE] == 0.0:  # a motion into something (cosmos.osc.contact.touch_braking)
        touch = scalars[HELD_PUSH + 4 : HELD_PUSH + 7]
        touch_braking_into(motion, wrench, velocity, touch, scalars[TOUCH_FREE_SPEED])
    spring_law_into(motion, state, vectors, matrices[ROTATION_TASK], scalars[DT_S])  # COMPLY springs' law
    if mode == MODE_GOAL and scalars[UNIFORM] != 0.0 and scalars[HAS_FORCE] + scalars[ADMITTANCE] == 0.0:
        # A free goal motion near its goal: eq. 20-21 plus integral action on the translation
        # error (cosmos.osc.integral_action.integrate_goal_error): a steady model error would hold the
        # tool Lambda^-1 f / kp, a millimetre, short of its goal.
        goal_integral, gate = state[MOTION_INTEGRAL, :3], scalars[GOAL_INTEGRAL + 1 : GOAL_INTEGRAL + 5]
        e2 = error[0] ** 2 + error[1] ** 2 + error[2] ** 2
        v2 = velocity[0] ** 2 + velocity[1] ** 2 + velocity[2] ** 2
        f2 = wrench[0] ** 2 + wrench[1] ** 2 + wrench[2] ** 2
        band = min(gate[1], scalars[MAX_SPEED] * kv[0] / kp[0])  # where eq. 21 lets go (uniform gains)
        if e2 < band**2 and v2 < gate[2] ** 2 and f2 < gate[3] ** 2:
            for i in range(3):
                goal_integral[i] = min(max(goal_integral[i] + error[i] * scalars[DT_S], -gate[0]), gate[0])
        for i in range(3):
            motion[i] -= scalars[GOAL_INTEGRAL] * goal_integral[i]
    if mode == MODE_HOLD and scalars[UNIFORM] != 0.0 and scalars[HAS_FORCE] + scalars[ADMITTANCE] == 0.0:
        # A free hold while the null space is driven (cosmos.osc.integral_action.observe_hold_disturbance).
        hold_observer_into(
            motion,
            state[MOTION_INTEGRAL],
            state[FLAGS, OBSERVING:],
            vectors[HOLD_KNOWN, :3],
            error,
            velocity,
            wrench,
            scalars[HOLD_OBSERVER : HOLD_OBSERVER + 4],
            scalars[DT_S],
        )
    feedback = work[FEEDBACK]
    feedback[:] = 0.0
    # Operational speed commanded outright, world: a tracked trajectory's xd_d on the motion axes, the
    # admittance speed on compliant moment axes, a cruise's 2 v_d - xd (eq. 20-21 made PI: kernels.cruise).
    commanded_speed = work[COMMANDED_SPEED]  # Friction is compensated toward it.
    cruising = cruise_into(motion, commanded_speed, state, vectors[GOAL_LINE, :3], max_speed, scalars)
    if mode == MODE_TRAJECTORY:
        commanded_speed = reference_speed(velocity_desired, matrices[OMEGA_BAR], velocity, scalars, t_s)
    elapsed = t_s - scalars[START_S]
    ramp = scalars[RAMP_S]
    fraction = 1.0 if elapsed >= ramp else elapsed / ramp
    start, goal = vectors[FORCE_START, :6], vectors[FORCE_WORLD, :6]
    setpoint, slide = work[SETPOINT], work[SLIDE]
    slide[:] = 0.0  # an INSERT's push across, fed forward (osc.tilt_window.insert_compliance)
    for i in range(6):
        setpoint[i] = start[i] + fraction * (goal[i] - start[i])
    if admittance:
        # Moment axes: admittance control. The moment error (sensor low-passed) sets a bounded rotation speed
        # that a unit-mass velocity servo tracks (friction compensated toward it): the seed's force loop
        # would leave a contact's aligning moment (0.02 N m, a round tip on a slope) to the wrist's friction.
        admitting = (scalars[ADMITTANCE_GAIN], scalars[ADMITTANCE_MAX_SPEED])
        speed = admittance_speed(omega_admittance, setpoint, state[MOMENT_FILTERED, :6], *admitting)
        if scalars[PUSH_SPEED] > 0.0:  # an INSERT's window and push (osc.tilt_window.insert_compliance)
            window = (error, velocity, goal, wrench, matrices[OMEGA_BAR], scalars[TILT_WINDOW:])
            insert_compliance_into(speed, slide, tilt, *window)
        motion = admittance_command(omega_admittance, motion, speed, velocity, scalars[ADMITTANCE_KV])
        commanded_speed = commanded_speed + speed
    acceleration = motion
    pushing_at_speed = False
    if scalars[HAS_FORCE] != 0.0:
        omega_bar = matrices[OMEGA_BAR]
        # The Coulomb intent (below) is the motion axes' command, not a force axis's position
        # error (an INSERT 20 mm below its start asks for no motion back up), and the joints'
        # motion along force axes is taken out of it (-xd / lookahead cancels Jbar's share of
        # qd): there the joints' friction is left to damp the push, and an impact.
        acceleration = work[ACCELERATION]
        braking = 1.0 / scalars[LOOKAHEAD_S]
        for i in range(6):
            acc = 0.0
            for k in range(6):
                acc += omega_bar[i, k] * (motion[k] + braking * velocity[k])
            acceleration[i] = motion[i] - acc
        flags = state[FLAGS]
        # Integral action only once something pushes back (latched for the segment): in
        # free space the force error cannot be closed and would wind up into an impact.
        if touch_latched(flags[TOUCHING] != 0.0, omega_bar, wrench, scalars[CONTACT_THRESHOLD_N]):
            flags[TOUCHING] = 1.0
        if flags[TOUCHING] != 0.0 and mode == MODE_TRAJECTORY and t_s >= scalars[TRAJECTORY_END_S]:
            # A SLIDE whose reference has stopped: cosmos.osc.integral_action.integrate_motion_error.
            gains = np.array((scalars[MOTION_KI], scalars[MOTION_INTEGRAL_LIMIT], scalars[DT_S]))
            slide_integral_into(motion, acceleration, state[MOTION_INTEGRAL, :6], error, omega_bar, gains)
        integral = state[INTEGRAL, :6]
        previous_integral = integral.copy()
        # ... and once the push reached most of its goal (a contact building up would wind it up);
        # a held push's landed, or its ramp over even short of it (cosmos.osc.contact.push_landed).
        held = not scalars[PUSH_SPEED] > 0.0
        if force_goal_latched(flags[REACHED] != 0.0, goal, wrench, velocity, held, fraction >= 1.0):
            flags[REACHED] = 1.0
        if flags[TOUCHING] != 0.0 and flags[REACHED] != 0.0:
            limit, dt = scalars[INTEGRAL_LIMIT], scalars[DT_S]
            force_error = integrated_force_error(omega_bar, setpoint, wrench, slide)  # osc.tilt_window
            for i in range(6):
                integral[i] = min(max(integral[i] + force_error[i] * dt, -limit), limit)
        k_f, k_i = scalars[K_F], scalars[K_I]
        for i in range(6):  # F_a without damping
            feedback[i] = (1.0 + k_f) * (setpoint[i] + slide[i]) - k_f * wrench[i] + k_i * integral[i]
        # The SPEED of a force-controlled push (cosmos.osc.unified.speed_limited_push); without one (0)
        # a push held against a surface, stiffened along itself, its SPEED a limit (cosmos.osc.held_push).
        push_speed, f2a, gate = scalars[PUSH_SPEED], matrices[FORCE_TO_ACCELERATION], flags[REACHED] != 0.0
        if not push_speed > 0.0:
            held, dt = scalars[HELD_PUSH : HELD_PUSH + 4] * flags[TOUCHING], scalars[DT_S]  # once touching
            gate = gate and flags[TOUCHING] != 0.0
            pushed = (goal, setpoint, wrench, velocity, error, f2a, held, gate, dt, scalars[MAX_SPEED])
            if held_push_capped_into(feedback, flags[HELD_INTEGRAL:], *pushed, scalars[K_VF:], scalars):
                integral[:3] = previous_integral[:3]  # at its speed limit: no windup (as INSERT's cap)
        else:
            speeds, cruise = scalars[K_VF:], state[CRUISE]  # k_vf, kv, aim; the reference at 2-3
            rate, dt = scalars[PUSH_SPEED_RATE], scalars[DT_S]
            limited = push_at_speed_into(feedback, goal, wrench, velocity, f2a, speeds, rate, cruise, dt)
            if limited:
                # At its speed limit the push is a velocity command: friction is compensated
                # toward the commanded speed, as toward a tracked trajectory's xd_d (the joints
                # would stick), and along n toward it alone: the sensed motion along n, which
                # the force axes take out of the intent (above), stays out of it
                # (cosmos.osc.unified.push_commanded_speed).
                pushing_at_speed = True
                push = math.sqrt(goal[0] ** 2 + goal[1] ** 2 + goal[2] ** 2)
                n0, n1, n2 = goal[0] / push, goal[1] / push, goal[2] / push
                for i, ni in ((0, n0), (1, n1), (2, n2)):
                    commanded_speed[i] += push_speed * ni
                # Anti-windup: the translations' integral does not grow while unused.
                integral[:3] = previous_integral[:3]
        if flags[TOUCHING] == 0.0:
            for i in range(6):
                acc = 0.0
                for k in range(6):
                    acc += f2a[i, k] * feedback[k]
                acceleration[i] += acc

    torque = state[TORQUE, :n]
    for i in range(n):
        acc = stacked[i, 18]
        for k in range(6):
            acc += stacked[i, k] * motion[k] + stacked[i, 6 + k] * feedback[k]
            acc += stacked[i, 12 + k] * velocity[k]
        for k in range(n):
            acc += stacked[i, 19 + k] * qd[k]
        torque[i] = acc
    # Coulomb friction is compensated in the direction the joint moves or, from rest, is told to move (qd plus
    # Jbar times the commanded acceleration over a look-ahead), low-passed: a new setpoint never steps it.
    if admittance or mode == MODE_TRAJECTORY or pushing_at_speed or cruising:  # no slow joint left to stick
        acceleration = acceleration + commanded_speed / scalars[LOOKAHEAD_S]
    spring.spring_intent_into(acceleration, state, vectors, matrices[ROTATION_TASK])  # its model's motion
    free = mode != MODE_HOLD and scalars[UNIFORM] != 0.0 and scalars[HAS_FORCE] + scalars[ADMITTANCE] == 0.0
    free = free and wrench[0] ** 2 + wrench[1] ** 2 + wrench[2] ** 2 < scalars[CRUISE_INTEGRAL + 2] ** 2
    adaption = np.array((kv[0], scalars[LOOKAHEAD_S], scalars[INTENT_SCALE], scalars[DT_S]))
    published = (vectors[COULOMB_NM, :n], vectors[COULOMB_NEGATIVE_NM, :n])
    levels = adapted_levels(
        state[FRICTION_ERROR, :n], fed_back, velocity, stacked, jbar_lookahead, published, free, adaption
    )
    slide = mode == MODE_TRAJECTORY and not scalars[PUSH_SPEED] > 0.0 and state[FLAGS, TOUCHING] != 0.0
    args = (matrices[OMEGA_BAR], fed_back, commanded_speed, goal, scalars[HAS_FORCE] != 0.0, slide, adaption)
    surface_friction_into(torque, state, jacobian, *args, scalars[COULOMB_BLEND])  # osc.surface_friction
    coulomb_compensation_into(  # toward where the task and the null space's torques turn the joints
        torque,
        state[COULOMB, :n],
        qd + vectors[NULL_INTENT, :n],
        jbar_lookahead,
        acceleration,
        levels[0],
        levels[1],
        vectors[COULOMB_DEAD_BAND, :n],
        mode != MODE_HOLD or scalars[HAS_FORCE] != 0.0 or scalars[ADMITTANCE] != 0.0,
        scalars[INTENT_SCALE],
        scalars[COULOMB_BLEND],
    )
    saturate_about(torque, vectors[TORQUE_MAX, :n], vectors[GRAVITY, :n])
