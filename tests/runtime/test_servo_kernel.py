"""The compiled servo kernels (cosmos.runtime.kernels) against the readable NumPy maths of cosmos.osc.

Every check draws seeded random inputs, runs the numba kernel and compares it
with the reference functions (each citing Khatib's equations), to ~1e-9
relative. The reference never calls the kernel module's arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from cosmos.osc.admittance import admittance_command, admittance_speed, low_pass, without_axes
from cosmos.osc.contact import LANDED_PUSH, contact_latched, push_landed, touch_latched
from cosmos.osc.dynamics import OperationalDynamics, null_space_damping, operational_dynamics
from cosmos.osc.force import Selection, selection
from cosmos.osc.friction import adapt_coulomb_error, coulomb_compensation, friction_intent
from cosmos.osc.held_push import (
    held_gains,
    held_on_steel,
    held_push,
    held_push_cap,
    steel_damping,
    touch_damping,
)
from cosmos.osc.integral_action import integrate_goal_error, integrate_motion_error, observe_hold_disturbance
from cosmos.osc.limits import saturate_torque
from cosmos.osc.motion import goal_command, ramped_speed_limit, tracking_command
from cosmos.osc.orientation import so3_exp
from cosmos.osc.push_speed import follow_the_tool, speed_reference_step
from cosmos.osc.surface_friction import (
    SURFACE_FRICTION,
    learn_surface_friction,
    surface_friction_force,
    surface_intent,
)
from cosmos.osc.tilt_window import insert_compliance, integrated_force_error
from cosmos.osc.unified import (
    ForceGains,
    force_command,
    force_feedback,
    force_goal_reached,
    integrate_force_error,
    push_commanded_speed,
    servo_matrices,
    speed_limited_push,
    unified_torque,
)
from cosmos.robot_model import GRAVITY
from cosmos.runtime.kernels import commands, linear
from cosmos.runtime.kernels import servo as sk
from cosmos.runtime.kernels.cruise import CRUISE_INTEGRAL, LANDING
from cosmos.runtime.wrench import environment_wrench

RTOL = 1e-9
MOTION_AXES_Z_FORCE = (True, True, False, True, True, True)


def assert_close(actual: np.ndarray, expected: np.ndarray, rtol: float = RTOL) -> None:
    """Elementwise within ``rtol`` of the largest entry of ``expected`` (entries near zero included)."""
    scale = float(np.max(np.abs(expected))) if np.size(expected) else 0.0
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * max(scale, 1e-12))


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    return so3_exp(rng.uniform(-3.0, 3.0, 3))


def block_rotation(rotation: np.ndarray) -> np.ndarray:
    """``blkdiag(R, R)``: a (3, 3) rotation acting on ``[linear; angular]``. # (6, 6)."""
    out = np.zeros((6, 6))
    out[:3, :3] = rotation
    out[3:, 3:] = rotation
    return out


def padded(rotation: np.ndarray) -> np.ndarray:
    """A rotation in the top-left of a (6, 6) block, as the kernel's ``matrices`` hold them."""
    out = np.zeros((6, 6))
    out[:3, :3] = rotation
    return out


# --- environment_wrench_into -------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(5))
def test_environment_wrench_matches_the_wrench_module(seed: int) -> None:
    """Catches a transposed rotation, a wrong cross-product sign or a dropped weight term."""
    rng = np.random.default_rng(seed)
    sensor = rng.normal(0.0, 20.0, 6)
    rotation = random_rotation(rng)
    to_tool, to_com = rng.normal(0.0, 0.2, 3), rng.normal(0.0, 0.1, 3)
    mass_kg = rng.uniform(0.2, 3.0)
    expected = environment_wrench(sensor, rotation, to_tool, to_com, mass_kg)
    out = np.full(6, np.nan)  # every entry must be written
    commands.environment_wrench_into(out, sensor, rotation, to_tool, to_com, float(GRAVITY[2]) * mass_kg)
    assert_close(out, expected)


# --- matvec -------------------------------------------------------------------------------------


def test_matvec_is_the_matrix_product() -> None:
    """Catches swapped indices (``M^T v``) or a dropped column in the hand-written product."""
    rng = np.random.default_rng(7)
    for rows, cols in ((6, 6), (3, 6), (6, 3)):
        matrix, vector = rng.normal(size=(rows, cols)), rng.normal(size=cols)
        assert_close(linear.matvec(matrix, vector), matrix @ vector)


# --- unit_mass_command_into --------------------------------------------------------------------


NO_LINE = np.zeros(3)


def _command(*args: object) -> np.ndarray:
    out = np.full(6, np.nan)  # every component must be written
    commands.unit_mass_command_into(out, *args)
    return out


def _gains(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    return rng.uniform(100.0, 900.0, 6), rng.uniform(10.0, 60.0, 6)


def _desired_speeds(error: np.ndarray, kp: np.ndarray, kv: np.ndarray) -> tuple[float, float]:
    desired = -kp / kv * error
    return float(np.linalg.norm(desired[:3])), float(np.linalg.norm(desired[3:]))


@pytest.mark.parametrize(
    ("linear_binds", "angular_binds"), [(False, False), (True, False), (False, True), (True, True)]
)
def test_goal_command_matches_eq_20_21(linear_binds: bool, angular_binds: bool) -> None:
    """Catches one nu for both parts, the speed limit applied to the wrong part, or a missing nu."""
    rng = np.random.default_rng(11 + 2 * linear_binds + angular_binds)
    kp, kv = _gains(rng)
    error = rng.normal(0.0, 0.05, 6)
    velocity = rng.normal(0.0, 0.2, 6)
    linear, angular = _desired_speeds(error, kp, kv)
    # Put each limit on the chosen side of the unlimited desired speed.
    max_speed = 0.4 * linear if linear_binds else 2.0 * linear
    max_angular_speed = 0.3 * angular if angular_binds else 1.5 * angular
    expected = goal_command(error, velocity, kp, kv, max_speed, max_angular_speed)
    got = _command(
        sk.MODE_GOAL, error, velocity, np.zeros(6), np.zeros(6), kp, kv, max_speed, max_angular_speed, NO_LINE
    )
    assert_close(got, expected)
    # The case does what it says: the limited desired velocity has the limit's norm.
    limited = got / kv + velocity
    assert np.isclose(np.linalg.norm(limited[:3]), max_speed) == linear_binds
    assert np.isclose(np.linalg.norm(limited[3:]), max_angular_speed) == angular_binds


@pytest.mark.parametrize("binds", [False, True])
def test_goal_command_keeps_to_its_line(binds: bool) -> None:
    """Off its line, far from the goal, the translation's desired speed has the limit's norm and
    its part across the line is ``(kp/kv)`` times the deviation, as a hold's would be; near the
    goal (the limit not binding) the line changes nothing. Catches eq. 21's nu scaling the
    correction across the line by ``V_max / |x_d - x|`` (the realistic Panda sagged 2.4 mm off a
    0.4 m line), the line taken in the wrong frame, and the reference and kernel differing."""
    rng = np.random.default_rng(31 + binds)
    kp, kv = np.full(6, 400.0), np.full(6, 40.0)
    line = np.array((0.0, 1.0, 0.0))
    error = np.array((0.002, -0.3 if binds else -0.003, -0.001, 0.0, 0.0, 0.0))  # 2 mm, 1 mm off
    velocity = rng.normal(0.0, 0.05, 6)
    expected = goal_command(error, velocity, kp, kv, 0.25, 1.0, line=line)
    got = _command(sk.MODE_GOAL, error, velocity, np.zeros(6), np.zeros(6), kp, kv, 0.25, 1.0, line)
    assert_close(got, expected)
    desired = got / kv + velocity
    across = desired[:3] - desired[:3].dot(line) * line
    assert_close(across, -(kp[:3] / kv[:3]) * (error[:3] - error[:3].dot(line) * line))
    if binds:
        assert np.isclose(np.linalg.norm(desired[:3]), 0.25)
    else:
        assert_close(got, goal_command(error, velocity, kp, kv, 0.25, 1.0))


def test_trajectory_command_matches_eq_19() -> None:
    """Catches a dropped feed-forward xdd_d or a velocity error taken without xd_d."""
    rng = np.random.default_rng(21)
    kp, kv = _gains(rng)
    error, velocity, velocity_d, accel_d = (rng.normal(0.0, 0.3, 6) for _ in range(4))
    expected = tracking_command(error, velocity, velocity_d, accel_d, kp, kv)
    got = _command(sk.MODE_TRAJECTORY, error, velocity, velocity_d, accel_d, kp, kv, 0.1, 0.1, NO_LINE)
    assert_close(got, expected)


def test_hold_command_is_a_spring_and_damper() -> None:
    """Catches HOLD using the trajectory's xd_d / xdd_d (stale after a move) or the speed limit."""
    rng = np.random.default_rng(22)
    kp, kv = _gains(rng)
    error, velocity, velocity_d, accel_d = (rng.normal(0.0, 0.3, 6) for _ in range(4))
    got = _command(sk.MODE_HOLD, error, velocity, velocity_d, accel_d, kp, kv, 1e-3, 1e-3, NO_LINE)
    assert_close(got, -kp * error - kv * velocity)


# --- saturate_about ----------------------------------------------------------------------------


def _saturated(torque: np.ndarray, torque_max: np.ndarray, keep: np.ndarray) -> np.ndarray:
    out = torque.copy()
    commands.saturate_about(out, torque_max, keep)
    return out


def test_saturation_leaves_a_feasible_command_alone() -> None:
    """Catches scaling (or clipping to the kept part) a command that is already within the limits."""
    rng = np.random.default_rng(31)
    torque_max = rng.uniform(10.0, 100.0, 6)
    torque = rng.uniform(-0.99, 0.99, 6) * torque_max
    keep = rng.normal(0.0, 5.0, 6)
    expected, scale = saturate_torque(torque, torque_max, keep=keep)
    assert scale == 1.0
    assert_close(_saturated(torque, torque_max, keep), expected)
    limit_exactly = torque_max * np.sign(rng.normal(size=6))
    assert np.array_equal(_saturated(limit_exactly, torque_max, keep), limit_exactly)


def test_saturation_scales_about_gravity() -> None:
    """Catches scaling the whole command (gravity sags), clipping per joint (direction bent), or
    dividing by zero on a joint whose command equals its kept part."""
    rng = np.random.default_rng(32)
    torque_max = rng.uniform(10.0, 100.0, 6)
    keep = rng.uniform(-0.5, 0.5, 6) * torque_max
    torque = keep + rng.normal(0.0, 1.0, 6) * torque_max
    torque[3] = keep[3]  # delta == 0 on one joint
    assert np.any(np.abs(torque) > torque_max)
    expected, scale = saturate_torque(torque, torque_max, keep=keep)
    assert 0.0 < scale < 1.0
    got = _saturated(torque, torque_max, keep)
    assert_close(got, expected)
    assert np.all(np.abs(got) <= torque_max * (1.0 + 1e-12))
    assert_close(got - keep, scale * (torque - keep))  # same direction about the kept part


def test_saturation_when_the_kept_part_itself_exceeds_a_limit() -> None:
    """Catches keeping an infeasible gravity torque instead of clipping it to the drive's limit."""
    rng = np.random.default_rng(33)
    torque_max = rng.uniform(10.0, 100.0, 6)
    keep = rng.uniform(-0.5, 0.5, 6) * torque_max
    keep[1] = 1.5 * torque_max[1]
    keep[4] = -1.2 * torque_max[4]
    for torque in (keep + rng.normal(0.0, 0.3, 6) * torque_max, keep.copy()):
        expected, _ = saturate_torque(torque, torque_max, keep=keep)
        got = _saturated(torque, torque_max, keep)
        assert_close(got, expected)
        assert np.all(np.abs(got) <= torque_max * (1.0 + 1e-12))


# --- servo_tick --------------------------------------------------------------------------------


@dataclass(frozen=True)
class TickCase:
    """One servo tick: a GOAL segment with task z force-controlled unless ``force`` is False.

    Attributes:
        touching: The latch before the tick.
        force_axis_n: Sensed force along the task's force-controlled z, [N].
        uniform: Same gains on every axis (no rotation into the task frame).
        ramp_fraction: Where in the setpoint's ramp the tick falls (>= 1: ramp done).
        integral_at_limit: Start the integral just short of its clamp, so the step clamps.
        saturate: Torque limits tight enough to bind.
        mode: The motion mode (kernel's MODE_* value).
        force: Task z force-controlled; otherwise every axis is motion-controlled.
        max_speed: The segment's speed limit, [m/s] (small: the push's speed cap binds).
        admittance: Task RX, RY compliant (admittance control once in contact).
        tangent_n: Sensed force along the task's x, [N] (contact for the admittance latch).
        admittance_max_speed: W_max of the admittance speed, [rad/s].
        held: A push held at a surface (no SPEED of its own to push at: CONTACT's hold, SLIDE, WAIT).
        landing: A held push's landing ``(s_l [m], v_l [m/s], a [m/s^2])`` (osc.held_push.held_push_cap).
    """

    touching: bool
    force_axis_n: float
    uniform: bool
    ramp_fraction: float
    integral_at_limit: bool = False
    saturate: bool = False
    mode: float = sk.MODE_GOAL
    force: bool = True
    max_speed: float = 10.0
    admittance: bool = False
    tangent_n: float = 25.0
    admittance_max_speed: float = 10.0
    held: bool = False
    landing: tuple[float, float, float] = (0.0, 0.0, 0.0)


TICK_CASES = {
    "free space, a push below the threshold": TickCase(False, 0.5, False, 0.4),
    "free space, uniform gains": TickCase(False, -0.8, True, 0.7, saturate=True),
    "the tick that latches the touch": TickCase(False, 3.0, True, 1.5),
    "the tick that latches the touch at 95 % of its goal": TickCase(False, -9.5, True, 1.5),
    "touching, light push": TickCase(True, 0.2, False, 2.0, saturate=True),
    "touching, integral clamped": TickCase(True, -2.0, False, 0.9, integral_at_limit=True),
    "touching, push capped by its speed": TickCase(True, 0.2, False, 2.0, max_speed=0.001),
    "free space, push capped by its speed": TickCase(False, 0.1, True, 2.0, max_speed=0.002),
    "with a held push under its SPEED, touching": TickCase(True, -13.0, False, 2.0, held=True),
    "with a held push, free space": TickCase(False, 0.4, True, 0.5, held=True),
    "with a held push, a slide": TickCase(True, -3.0, False, 2.0, mode=sk.MODE_TRAJECTORY, held=True),
    "with a held push past its SPEED": TickCase(
        True, -3.0, False, 2.0, mode=sk.MODE_HOLD, held=True, max_speed=1e-4
    ),
    "with a held push past its landing": TickCase(
        True, -3.0, True, 2.0, mode=sk.MODE_HOLD, held=True, max_speed=0.05, landing=(1.0, 1e-3, 0.1)
    ),
    "trajectory, motion only": TickCase(False, 3.0, False, 0.5, mode=sk.MODE_TRAJECTORY, force=False),
    "trajectory in contact (a slide)": TickCase(True, -3.0, False, 2.0, mode=sk.MODE_TRAJECTORY),
    "a free goal motion near its goal": TickCase(False, 0.3, True, 2.0, force=False, tangent_n=0.3),
    "a free goal motion pushing something": TickCase(False, 0.3, True, 2.0, force=False),
    "hold, motion only": TickCase(True, 3.0, False, 0.5, saturate=True, mode=sk.MODE_HOLD, force=False),
    "a free hold": TickCase(False, 0.3, True, 2.0, mode=sk.MODE_HOLD, force=False, tangent_n=0.3),
    "a free hold pushed": TickCase(False, 3.0, True, 2.0, mode=sk.MODE_HOLD, force=False),
    "admittance, first contact": TickCase(False, 3.0, False, 0.6, admittance=True),
    "admittance, speed bounded": TickCase(True, 2.0, True, 1.2, admittance=True, admittance_max_speed=0.05),
    "admittance, tracking": TickCase(
        True, 2.0, False, 2.0, mode=sk.MODE_TRAJECTORY, admittance=True, admittance_max_speed=0.02
    ),
    "admittance, sideways contact": TickCase(False, 0.3, False, 0.8, admittance=True, tangent_n=3.0),
    "admittance, free space": TickCase(False, 0.3, False, 0.5, admittance=True, tangent_n=0.2),
}
ADMITTANCE_GAIN, ADMITTANCE_KV, MOMENT_BLEND = 3.0, 40.0, 0.3
PUSH_SPEED_RATE = 60.0
"""The push's speed reference rises at this many aims a second (ServoGains.push_speed_rate)."""

CONTACT_THRESHOLD_N = 1.0
FORCE_GAINS = ForceGains(k_f=0.6, k_i=12.0, k_vf=30.0, integral_limit=5.0)
HELD_PUSH_GAINS = (0.4, 288.0, 50.0, 0.2)
"""The held push's (k_fh, k_ih, k_vh, limit) as cosmos.runtime.servo.ServoGains has them."""
TILT_WINDOW = (0.005, 20.0, 1.0, 0.001, 4.0, 0.6, 0.005)
"""An INSERT's compliant axes (cosmos.osc.tilt_window.insert_compliance): its tilt window [rad],
narrow, so that the cases' rotation errors (about 0.01 rad) reach beyond it, its stop's rate
[1/s], the mouth 1 m deep (every case short of it: its push across the insertion acts), the
window in the mouth [rad] and its stop's rate [1/s], the push's share and its speed [m/s]."""
GOAL_INTEGRAL = (1000.0, 0.004, 0.05, 1.0, 2.0)
"""A free goal motion's (k_i, limit, band, slow, quiet): a band and a speed wide enough for the
cases' centimetre errors; 2 N quiet, above the near-goal case's push and below the other's."""
HOLD_OBSERVER = (20.0, 3.0)
"""A free hold's disturbance observer (L, bound), as cosmos.runtime.servo.ServoGains has it."""
XI_Q = 20.0
LOOKAHEAD_S = 0.02
DT_S = 1e-3
INTENT_SCALE = 1.0 / 0.5  # gentler than the runtime's 1/0.01, so the intent is not all clipped
COULOMB_BLEND = 0.2
TOOL_MASS_KG = 0.65


def _random_model(
    rng: np.random.Generator,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A, J, b, g, h of a well-conditioned arm (Lambda in section 5's exact zone)."""
    m = rng.normal(size=(6, 6))
    inertia = 0.3 * (m @ m.T) + np.diag(rng.uniform(0.5, 3.0, 6))  # (6, 6) SPD, [kg m^2]
    jacobian = np.eye(6) * 0.6 + rng.normal(0.0, 0.1, (6, 6))  # (6, 6)
    return inertia, jacobian, rng.normal(0.0, 2.0, 6), rng.normal(0.0, 20.0, 6), rng.normal(0.0, 0.5, 6)


def _sensor_reading(
    wrench: np.ndarray, rotation: np.ndarray, to_tool: np.ndarray, to_com: np.ndarray, weight_z_n: float
) -> np.ndarray:
    """The raw sensor reading for which the tool applies ``wrench`` to the environment (inverse of
    the quasi-static balance in cosmos.runtime.wrench)."""
    force, moment = wrench[:3], wrench[3:]
    weight = np.array((0.0, 0.0, weight_z_n))
    moment_sensor = moment + np.cross(to_tool, force) - np.cross(to_com, weight)
    return np.concatenate((rotation.T @ (force - weight), rotation.T @ moment_sensor))


@dataclass(frozen=True)
class TickInputs:
    t_s: float
    q: np.ndarray
    qd: np.ndarray
    sensor: np.ndarray
    scalars: np.ndarray
    vectors: np.ndarray
    matrices: np.ndarray
    jacobian: np.ndarray
    jbar_lookahead: np.ndarray
    stacked: np.ndarray
    state: np.ndarray
    inertia: np.ndarray
    dynamics: OperationalDynamics
    selection: Selection
    held: np.ndarray
    viscous: np.ndarray


def _tick_inputs(case: TickCase, seed: int) -> TickInputs:
    rng = np.random.default_rng(seed)
    inertia, jacobian, bias, gravity, h = _random_model(rng)
    inertia_inv = np.linalg.inv(inertia)
    dynamics = operational_dynamics(inertia, jacobian, bias, gravity, h, inertia_inv=inertia_inv)
    assert dynamics.eigenvectors.shape[1] == 0, "want section 5's exact regime here"
    rotation_task = random_rotation(rng)
    sel = selection(MOTION_AXES_Z_FORCE if case.force else (True,) * 6, rotation_task)
    # Compliant RX, RY: force axes of the plan, motion axes of the servo (runtime.servo).
    omega_admittance = (
        selection((True, True, False, False, False, True), rotation_task).omega_bar - sel.omega_bar
    )
    held = rng.normal(0.0, 1.0, 6)
    viscous = rng.uniform(0.5, 5.0, 6)

    # The folded matrices, from the reference (eq. 29 with the null-space damping of eq. 34).
    stacked = np.zeros((6, 25))
    stacked[:, :19] = servo_matrices(dynamics, sel, FORCE_GAINS).stacked
    stacked[:, 18] += held
    stacked[:, 19:] = np.column_stack([null_space_damping(dynamics, inertia, e, XI_Q) for e in np.eye(6)])
    stacked[:, 19:] += np.diag(viscous)

    # The wrench the tool applies: large on motion axes, ``force_axis_n`` along task z.
    normal = rotation_task[:, 2]
    tangent = rotation_task[:, 0]
    wrench = np.concatenate((case.tangent_n * tangent + case.force_axis_n * normal, rng.normal(0.0, 2.0, 3)))
    rotation_sensor = random_rotation(rng)
    to_tool, to_com = rng.normal(0.0, 0.15, 3), rng.normal(0.0, 0.05, 3)
    weight_z_n = float(GRAVITY[2]) * TOOL_MASS_KG
    sensor = _sensor_reading(wrench, rotation_sensor, to_tool, to_com, weight_z_n)

    force_task = np.array((0.0, 0.0, -10.0, 0.4, -0.3, 0.0))  # the moments for the admittance axes
    force_world = np.concatenate((rotation_task @ force_task[:3], rotation_task @ force_task[3:]))
    start_s, ramp_s = 1.0, 0.2
    t_s = start_s + case.ramp_fraction * ramp_s

    scalars = np.zeros(sk.SCALARS)
    scalars[sk.MODE] = case.mode
    scalars[sk.UNIFORM] = float(case.uniform)
    scalars[sk.HAS_FORCE] = float(case.force)
    scalars[sk.MAX_SPEED] = case.max_speed
    scalars[sk.MAX_ANGULAR_SPEED] = 1.0
    # A goal motion's limits ramp up from these (within the cases' 0-0.2 s for some of them).
    scalars[sk.GOAL_ACCELERATION], scalars[sk.GOAL_ANGULAR_ACCELERATION] = 0.5, 5.0
    scalars[sk.GOAL_START_SPEED], scalars[sk.GOAL_START_ANGULAR_SPEED] = 0.02, 0.3
    scalars[sk.K_VF] = FORCE_GAINS.k_vf
    scalars[sk.FORCE_SPEED_KV] = 40.0
    scalars[sk.PUSH_SPEED] = 0.0 if case.held else case.max_speed
    scalars[sk.PUSH_SPEED_RATE] = PUSH_SPEED_RATE  # the speed reference's rise (cosmos.osc.push_speed)
    scalars[sk.HELD_PUSH : sk.HELD_PUSH + 4] = HELD_PUSH_GAINS
    scalars[sk.HELD_PUSH + 4] = 2.0  # the touch's force [N], below the cases' pushes
    scalars[sk.HELD_PUSH + 5] = TOOL_MASS_KG
    scalars[sk.HELD_PUSH + 6] = 200.0  # the touch's damping [1/s]
    scalars[sk.MOTION_KI] = 2000.0
    scalars[sk.MOTION_INTEGRAL_LIMIT] = 0.004
    scalars[sk.GOAL_INTEGRAL : sk.GOAL_INTEGRAL + 5] = GOAL_INTEGRAL
    scalars[sk.HOLD_OBSERVER : sk.HOLD_OBSERVER + 4] = (*HOLD_OBSERVER, GOAL_INTEGRAL[2], GOAL_INTEGRAL[4])
    scalars[sk.START_S] = start_s
    scalars[sk.RAMP_S] = ramp_s
    scalars[sk.K_F] = FORCE_GAINS.k_f
    scalars[sk.K_I] = FORCE_GAINS.k_i
    scalars[sk.INTEGRAL_LIMIT] = FORCE_GAINS.integral_limit
    scalars[sk.CONTACT_THRESHOLD_N] = CONTACT_THRESHOLD_N
    scalars[sk.DT_S] = DT_S
    scalars[sk.INTENT_SCALE] = INTENT_SCALE
    scalars[sk.COULOMB_BLEND] = COULOMB_BLEND
    scalars[sk.TOOL_WEIGHT_Z_N] = weight_z_n
    scalars[sk.LOOKAHEAD_S] = LOOKAHEAD_S
    scalars[sk.ADMITTANCE] = float(case.admittance)
    scalars[sk.ADMITTANCE_GAIN] = ADMITTANCE_GAIN
    scalars[sk.ADMITTANCE_MAX_SPEED] = case.admittance_max_speed
    scalars[sk.ADMITTANCE_KV] = ADMITTANCE_KV
    scalars[sk.MOMENT_BLEND] = MOMENT_BLEND
    scalars[sk.TILT_WINDOW :] = TILT_WINDOW
    scalars[CRUISE_INTEGRAL + 2] = 1.0  # the cruise's quiet [N]: the Coulomb errors learn under it
    scalars[LANDING : LANDING + 3] = case.landing  # a held push's landing (s_l 1 m: past it, at v_l)

    vectors = np.zeros((sk.VECTORS, 6))
    vectors[sk.KP], vectors[sk.KV] = (np.full(6, 400.0), np.full(6, 40.0)) if case.uniform else _gains(rng)
    vectors[sk.FORCE_WORLD] = force_world
    vectors[sk.FORCE_START] = 0.3 * force_world
    vectors[sk.REFERENCE_ERROR] = rng.normal(0.0, 0.01, 6)
    vectors[sk.REFERENCE_VELOCITY] = rng.normal(0.0, 0.1, 6)  # used in TRAJECTORY mode only
    vectors[sk.REFERENCE_ACCELERATION] = rng.normal(0.0, 1.0, 6)  # used in TRAJECTORY mode only
    q_e = rng.uniform(-2.0, 2.0, 6)
    vectors[sk.EVALUATION_Q] = q_e
    vectors[sk.GRAVITY] = gravity
    vectors[sk.SENSOR_OFFSETS, :3] = to_tool
    vectors[sk.SENSOR_OFFSETS, 3:] = to_com
    vectors[sk.COULOMB_NM] = rng.uniform(1.0, 8.0, 6)
    # The levels differ by direction, as the PUMA's published ones (no draw: the cases' inputs stay).
    vectors[sk.COULOMB_NEGATIVE_NM] = 0.6 * vectors[sk.COULOMB_NM]
    vectors[sk.COULOMB_DEAD_BAND] = 0.01 * (1.0 + np.arange(6)) / 6  # the encoders' noise, no draw
    vectors[sk.TORQUE_MAX] = 1e6  # replaced below when the case saturates
    vectors[sk.GOAL_LINE, :3] = (0.6, 0.0, 0.8)  # a goal motion's line (no draw: the cases' inputs stay)

    matrices = np.zeros((sk.MATRICES, 6, 6))
    matrices[sk.FORCE_TO_ACCELERATION] = dynamics.lambda_inv @ sel.omega_bar
    jbar_lookahead = LOOKAHEAD_S * dynamics.jbar
    matrices[sk.OMEGA_BAR] = sel.omega_bar
    matrices[sk.ROTATION_TASK] = padded(rotation_task)
    matrices[sk.ROTATION_SENSOR] = padded(rotation_sensor)
    matrices[sk.OMEGA_ADMITTANCE] = omega_admittance

    state = np.full((sk.STATE_ROWS, 6), np.nan)  # output rows must all be written
    state[sk.FLAGS] = 0.0
    state[sk.FLAGS, sk.TOUCHING] = float(case.touching)
    state[sk.FLAGS, sk.REACHED] = float(case.touching)  # in contact: the push has reached its goal
    state[sk.FLAGS, sk.HELD_INTEGRAL] = 0.05
    if case.integral_at_limit:
        # Along the force axis, its largest world component 1 mN s short of the clamp, on the
        # side the error drives it (F_d - F_s is negative along the normal): this step clamps.
        along = np.concatenate((normal, np.zeros(3)))
        state[sk.INTEGRAL] = -(FORCE_GAINS.integral_limit - 1e-3) * along / np.max(np.abs(normal))
    else:
        state[sk.INTEGRAL] = sel.omega_bar @ rng.normal(0.0, 0.3, 6)
    state[sk.COULOMB] = rng.uniform(-1.0, 1.0, 6)
    state[sk.CRUISE] = 0.0  # a push's speed reference: half way up its rise (cosmos.osc.push_speed)
    state[sk.CRUISE, 2:4] = 0.5 * case.max_speed, 1.0
    state[sk.MOMENT_FILTERED] = rng.normal(0.0, 1.0, 6)
    state[sk.FLAGS, sk.ADMITTING] = float(case.admittance and case.touching)
    state[sk.FRICTION_ERROR] = rng.uniform(-0.08, 0.08, 6)  # the joints' Coulomb errors learnt so far
    state[sk.MOTION_INTEGRAL] = 0.0
    state[sk.MOTION_INTEGRAL, :3] = sel.omega[:3, :3] @ rng.uniform(-0.002, 0.002, 3)  # on motion axes
    state[sk.SURFACE] = (0.3, 0.0, 0.5, -0.4, 0.2, 0.0)  # a surface's friction learnt (no draw)
    if case.mode == sk.MODE_HOLD:  # a free hold's observer: the velocity it predicted [m/s]
        state[sk.MOTION_INTEGRAL, 3:6] = rng.normal(0.0, 2e-3, 3)
        state[sk.FLAGS, sk.OBSERVING] = 1.0
        vectors[sk.HOLD_KNOWN, :3] = rng.normal(0.0, 0.5, 3)  # a field meant to reach the tool [m/s^2]
        vectors[sk.NULL_INTENT] = rng.normal(0.0, 0.5, 6)  # a posture's L A^-1 Gamma_0 [rad/s]

    q = q_e + rng.normal(0.0, 0.01, 6)
    qd = rng.normal(0.0, 2e-3, 6)
    inputs = TickInputs(
        t_s,
        q,
        qd,
        sensor,
        scalars,
        vectors,
        matrices,
        jacobian,
        jbar_lookahead,
        stacked,
        state,
        inertia,
        dynamics,
        sel,
        held,
        viscous,
    )
    if case.saturate:
        unsaturated = _reference_tick(inputs).torque_unsaturated
        limits = np.maximum(0.6 * np.abs(unsaturated), np.abs(gravity) + 1.0)
        vectors[sk.TORQUE_MAX] = limits
        assert np.any(np.abs(unsaturated) > limits), "the case should saturate"
    return inputs


@dataclass(frozen=True)
class ReferenceTick:
    """The reference's tick: state rows keyed by the kernel's row indices, the latch, Gamma unsaturated."""

    rows: dict[int, np.ndarray]
    touching: bool
    torque_unsaturated: np.ndarray
    admitting: bool = False


def _reference_tick(inputs: TickInputs, force_acceleration_always: bool | None = None) -> ReferenceTick:
    """One tick composed from cosmos.osc and cosmos.runtime.wrench.

    ``force_acceleration_always`` overrides the rule "Lambda^-1 Omega_bar F_fb counts toward the
    Coulomb intent only while not touching" (used to show the test can tell them apart).
    """
    sc, vec, mat, st = inputs.scalars, inputs.vectors, inputs.matrices, inputs.state
    dyn, sel = inputs.dynamics, inputs.selection
    rotation_sensor = mat[sk.ROTATION_SENSOR, :3, :3]
    wrench = environment_wrench(
        inputs.sensor,
        rotation_sensor,
        vec[sk.SENSOR_OFFSETS, :3],
        vec[sk.SENSOR_OFFSETS, 3:],
        TOOL_MASS_KG,
    )
    jacobian = dyn.jacobian
    velocity = jacobian @ inputs.qd
    displacement = jacobian @ (inputs.q - vec[sk.EVALUATION_Q])
    error = vec[sk.REFERENCE_ERROR] + displacement  # section 3's estimator: x = x_e + J (q - q_e)
    state_error = error

    # Compliant moment axes: the sensed wrench low-passed; in contact, no position goal on them.
    omega_a = mat[sk.OMEGA_ADMITTANCE]
    moment, admitting = st[sk.MOMENT_FILTERED], False
    velocity_d, accel_d = vec[sk.REFERENCE_VELOCITY], vec[sk.REFERENCE_ACCELERATION]
    if sc[sk.ADMITTANCE]:
        moment = low_pass(moment, wrench, sc[sk.MOMENT_BLEND])
        admitting = contact_latched(bool(st[sk.FLAGS, sk.ADMITTING]), wrench, CONTACT_THRESHOLD_N)
    tilt = omega_a @ error  # the rotation error on the compliant axes, before they drop it
    if admitting:
        error, velocity_d, accel_d = (without_axes(omega_a, v) for v in (error, velocity_d, accel_d))

    # Eq. 19 or 20-21 with gains per task axis: the command in task axes, turned back to world.
    kp, kv = vec[sk.KP], vec[sk.KV]
    rotation = block_rotation(mat[sk.ROTATION_TASK, :3, :3])
    error_task, velocity_task = rotation.T @ error, rotation.T @ velocity
    if sc[sk.MODE] == sk.MODE_GOAL:
        since = inputs.t_s - sc[sk.START_S]
        speeds = (
            ramped_speed_limit(sc[sk.MAX_SPEED], sc[sk.GOAL_START_SPEED], sc[sk.GOAL_ACCELERATION], since),
            ramped_speed_limit(
                sc[sk.MAX_ANGULAR_SPEED],
                sc[sk.GOAL_START_ANGULAR_SPEED],
                sc[sk.GOAL_ANGULAR_ACCELERATION],
                since,
            ),
        )
        line = rotation.T @ np.concatenate((vec[sk.GOAL_LINE, :3], np.zeros(3)))
        motion_task = goal_command(error_task, velocity_task, kp, kv, *speeds, line=line[:3])
    elif sc[sk.MODE] == sk.MODE_TRAJECTORY:
        velocity_d_task, accel_d_task = rotation.T @ velocity_d, rotation.T @ accel_d
        motion_task = tracking_command(error_task, velocity_task, velocity_d_task, accel_d_task, kp, kv)
    else:
        motion_task = -kp * error_task - kv * velocity_task
    motion = rotation @ motion_task
    fed_back = motion - accel_d  # F*_fb, what teaches the Coulomb levels (cosmos.osc.friction)
    if not sc[sk.HAS_FORCE]:  # a motion into something: damped along the push it meets
        motion = touch_damping(
            motion,
            wrench,
            velocity,
            float(sc[sk.HELD_PUSH + 6]),
            float(sc[sk.HELD_PUSH + 4]),
            TOOL_MASS_KG,
        )
    # A tracked trajectory's xd_d on the motion axes counts toward the Coulomb intent as itself.
    tracked = sc[sk.MODE] == sk.MODE_TRAJECTORY
    speed = sel.omega @ velocity_d if tracked else np.zeros(6)
    fraction = min(1.0, (inputs.t_s - sc[sk.START_S]) / sc[sk.RAMP_S])
    start = vec[sk.FORCE_START]
    setpoint = start + fraction * (vec[sk.FORCE_WORLD] - start)  # Figure 2's ramped setpoint
    pushed = np.zeros(6)
    if admitting:  # the moment error sets a bounded rotation speed, tracked by a velocity servo
        speed_a = admittance_speed(
            omega_a, setpoint, moment, sc[sk.ADMITTANCE_GAIN], sc[sk.ADMITTANCE_MAX_SPEED]
        )
        if sc[sk.PUSH_SPEED] > 0.0:  # an INSERT's: its window, its push across toward the lean
            window = sc[sk.TILT_WINDOW :]
            speed_a, pushed = insert_compliance(
                speed_a, tilt, state_error, velocity, vec[sk.FORCE_WORLD], wrench, sel.omega_bar, window
            )
        motion = admittance_command(omega_a, motion, speed_a, velocity, sc[sk.ADMITTANCE_KV])
        speed = speed + speed_a
    extra = {sk.MOMENT_FILTERED: moment} if sc[sk.ADMITTANCE] else {}
    if not sc[sk.HAS_FORCE]:  # every axis motion-controlled: no force loop, latch and integral kept
        motion_integral = st[sk.MOTION_INTEGRAL].copy()
        if sc[sk.MODE] == sk.MODE_GOAL and sc[sk.UNIFORM] and not sc[sk.ADMITTANCE]:  # near its goal
            gate = sc[sk.GOAL_INTEGRAL + 1 : sk.GOAL_INTEGRAL + 5]
            reach = sc[sk.MAX_SPEED] * vec[sk.KV, 0] / vec[sk.KP, 0]  # where eq. 21 lets go
            motion_integral[:3] = integrate_goal_error(
                motion_integral[:3],
                error,
                velocity,
                wrench,
                DT_S,
                (gate[0], gate[1], gate[2], gate[3]),
                reach,
            )
            motion = motion - np.concatenate((sc[sk.GOAL_INTEGRAL] * motion_integral[:3], np.zeros(3)))
        if sc[sk.MODE] == sk.MODE_HOLD and sc[sk.UNIFORM] and not sc[sk.ADMITTANCE]:  # a free hold
            gate = tuple(sc[sk.HOLD_OBSERVER : sk.HOLD_OBSERVER + 4])
            started = st[sk.FLAGS, sk.OBSERVING] != 0.0
            estimate, predicted, motion = observe_hold_disturbance(
                motion_integral[:3],
                motion_integral[3:6] if started else None,
                motion,
                velocity,
                error,
                wrench,
                DT_S,
                gate,
                vec[sk.HOLD_KNOWN, :3],
            )
            motion_integral[:3], motion_integral[3:6] = estimate, predicted
        torque = unified_torque(dyn, sel, motion, np.zeros(6)) + inputs.held
        torque += null_space_damping(dyn, inputs.inertia, inputs.qd, XI_Q) + inputs.viscous * inputs.qd
        return _finish_tick(
            inputs, wrench, state_error, velocity, displacement, motion, torque,
            motion_integral=motion_integral, speed=speed, admitting=admitting, extra=extra, fed_back=fed_back,
        )  # fmt: skip

    # Figure 2's force loop: integral latched on the first push.
    touching = touch_latched(bool(st[sk.FLAGS, sk.TOUCHING]), sel.omega_bar, wrench, CONTACT_THRESHOLD_N)
    integral = st[sk.INTEGRAL].copy()
    # A held push's goal counts only once landed, and then once its ramp is over even short of
    # it or over it (cosmos.osc.contact.push_landed).
    goal_met = force_goal_reached(vec[sk.FORCE_WORLD], wrench)
    if sc[sk.PUSH_SPEED] > 0.0:
        reached = bool(st[sk.FLAGS, sk.REACHED]) or goal_met
    else:
        landed = push_landed(
            vec[sk.FORCE_WORLD], wrench, velocity, share=np.inf if fraction >= 1.0 else LANDED_PUSH
        )
        reached = bool(st[sk.FLAGS, sk.REACHED]) or (landed and (fraction >= 1.0 or goal_met))
    if touching and reached:
        error_f = integrated_force_error(sel.omega_bar, setpoint, wrench, pushed)  # osc.tilt_window
        limit = FORCE_GAINS.integral_limit
        integral = np.clip(integral + error_f * DT_S, -limit, limit)  # osc.unified.integrate_force_error
    motion_integral = st[sk.MOTION_INTEGRAL].copy()
    arrived = inputs.t_s >= sc[sk.TRAJECTORY_END_S]
    if touching and sc[sk.MODE] == sk.MODE_TRAJECTORY and arrived:  # a slide's final approach
        motion_integral[:3] = integrate_motion_error(
            motion_integral[:3], error, sel.omega_bar, DT_S, sc[sk.MOTION_INTEGRAL_LIMIT]
        )
        motion = motion - np.concatenate((sc[sk.MOTION_KI] * motion_integral[:3], np.zeros(3)))
    integral_before_cap = integral.copy()
    feedback = force_feedback(setpoint, wrench, integral, FORCE_GAINS)
    feedback = feedback + (1.0 + FORCE_GAINS.k_f) * pushed  # an INSERT's push across, fed forward
    limited = False
    cruise = st[sk.CRUISE].copy()
    if sc[sk.PUSH_SPEED] > 0.0:  # held to its speed reference (cosmos.osc.push_speed)
        push = vec[sk.FORCE_WORLD, :3] / np.linalg.norm(vec[sk.FORCE_WORLD, :3])
        along, aim = float(push @ velocity[:3]), float(sc[sk.PUSH_SPEED])
        reference = float(cruise[2]) if cruise[3] else None
        cruise[2], rise = speed_reference_step(reference, aim, along, PUSH_SPEED_RATE, DT_S)
        cruise[3] = 1.0
        feedback, limited = speed_limited_push(
            feedback,
            vec[sk.FORCE_WORLD],
            wrench,
            velocity,
            dyn.lambda_inv @ sel.omega_bar,
            cruise[2],
            sc[sk.FORCE_SPEED_KV],
            FORCE_GAINS.k_vf,
            rise,
        )
        if not limited:  # at its force: the reference follows the tool
            cruise[2] = follow_the_tool(along, aim)
    else:  # a push held against a surface, its SPEED a limit (on a landing's profile, if any)
        gains = tuple(float(g) * touching for g in sc[sk.HELD_PUSH : sk.HELD_PUSH + 4])  # once touching
        landing = sc[LANDING : LANDING + 3]
        steel = landing[1] > 0.0 and touching and reached  # landed on steel: osc.held_push.held_gains
        damped = velocity
        if held_on_steel(landing[1], touching and reached, vec[sk.FORCE_WORLD], setpoint):
            feedback, damped = steel_damping(
                feedback, vec[sk.FORCE_WORLD], velocity, dyn.lambda_inv @ sel.omega_bar, FORCE_GAINS.k_vf
            )
        feedback, _ = held_push(
            feedback,
            vec[sk.FORCE_WORLD],
            setpoint,
            wrench,
            damped,
            dyn.lambda_inv @ sel.omega_bar,
            held_gains((gains[0], gains[1], gains[2], gains[3]), steel),
            st[sk.FLAGS, sk.HELD_INTEGRAL],
            touching and reached,
            DT_S,
        )
        feedback, held_capped = held_push_cap(
            feedback,
            vec[sk.FORCE_WORLD],
            wrench,
            velocity,
            dyn.lambda_inv @ sel.omega_bar,
            state_error,
            float(sc[sk.MAX_SPEED]),
            (float(landing[0]), float(landing[1]), float(landing[2])),
            float(sc[sk.FORCE_SPEED_KV]),
            FORCE_GAINS.k_vf,
        )
        if held_capped:  # the translations' integral held; no commanded speed: the joints' friction
            integral[:3] = st[sk.INTEGRAL, :3]  # damps the push along itself
    if limited:  # friction compensated toward the speed limit; the translations' integral held
        speed = speed + push_commanded_speed(vec[sk.FORCE_WORLD], sc[sk.PUSH_SPEED])
        integral[:3] = st[sk.INTEGRAL, :3]
    # Eq. 18's F_a, with the speed cap's cut of F_fb (zero unless it binds) carried over.
    uncapped = force_feedback(setpoint, wrench, integral_before_cap, FORCE_GAINS)
    f_a = force_command(
        setpoint, wrench, integral_before_cap, velocity, dyn.lambda_, sel.omega_bar, FORCE_GAINS
    )
    f_a = f_a + (feedback - uncapped)

    # Eq. 29 with the held potentials, eq. 34's null-space damping and viscous friction.
    torque = unified_torque(dyn, sel, motion, f_a) + inputs.held
    torque += null_space_damping(dyn, inputs.inertia, inputs.qd, XI_Q) + inputs.viscous * inputs.qd
    # A SLIDE's surface friction, added to eq. 17's F at the tool point (cosmos.osc.surface_friction).
    surface = st[sk.SURFACE].copy()
    surface[2:5] = 0.0
    if sc[sk.MODE] == sk.MODE_TRAJECTORY and not sc[sk.PUSH_SPEED] > 0.0 and touching:
        push = float(np.linalg.norm(sel.omega_bar[:3, :3] @ vec[sk.FORCE_WORLD, :3]))
        intent = surface_intent(velocity, fed_back, speed, sel.omega_bar, LOOKAHEAD_S)
        mu, slid = learn_surface_friction(
            surface[0],
            bool(surface[1]),
            wrench,
            velocity,
            intent,
            sel.omega_bar,
            push,
            DT_S,
            SURFACE_FRICTION,
        )
        force = surface_friction_force(st[sk.SURFACE, 2:5], mu, push, intent, COULOMB_BLEND, SURFACE_FRICTION)
        surface[:5] = (mu, float(slid), *force)
        torque += jacobian[:3].T @ force
    extra = {**extra, sk.SURFACE: surface}

    # The motion axes' command counts toward the intent; on the force axes the joints' own motion
    # is taken out of it, and the force loop's acceleration put in before touching.
    acceleration = sel.omega @ motion - sel.omega_bar @ velocity / LOOKAHEAD_S
    with_force = not touching if force_acceleration_always is None else force_acceleration_always
    if with_force:
        acceleration += dyn.lambda_inv @ (sel.omega_bar @ feedback)
    return _finish_tick(
        inputs,
        wrench,
        state_error,
        velocity,
        displacement,
        acceleration,
        torque,
        integral=integral,
        motion_integral=motion_integral,
        touching=touching,
        speed=speed,
        admitting=admitting,
        extra={**extra, sk.CRUISE: cruise},
        fed_back=fed_back,
    )


def _finish_tick(
    inputs: TickInputs,
    wrench: np.ndarray,
    error: np.ndarray,
    velocity: np.ndarray,
    displacement: np.ndarray,
    acceleration: np.ndarray,
    torque: np.ndarray,
    integral: np.ndarray | None = None,
    motion_integral: np.ndarray | None = None,
    touching: bool | None = None,
    speed: np.ndarray | None = None,
    admitting: bool = False,
    extra: dict[int, np.ndarray] | None = None,
    fed_back: np.ndarray | None = None,
) -> ReferenceTick:
    """Coulomb compensation toward ``qd + Jbar (L a + xd_c)`` (low-passed) and the saturation about g.

    The levels are the model's times ``1 + eps``, each joint's error learnt in free motion, from the
    torques ``J^T Lambda F*_fb`` of the command's feedback ``fed_back`` (:func:`adapt_coulomb_error`).
    """
    vec, st = inputs.vectors, inputs.state
    commanded = np.zeros(6) if speed is None else speed
    sc = inputs.scalars
    eps = st[sk.FRICTION_ERROR].copy()
    free = sc[sk.MODE] != sk.MODE_HOLD and sc[sk.UNIFORM] and not (sc[sk.HAS_FORCE] or sc[sk.ADMITTANCE])
    if free and fed_back is not None and np.linalg.norm(wrench[:3]) < sc[CRUISE_INTEGRAL + 2]:
        dyn, sel = inputs.dynamics, inputs.selection
        reference = dyn.jbar @ (fed_back / vec[sk.KV, 0] + velocity)  # qd_r = Jbar v_r (eq. 28)
        feedback_torque = unified_torque(dyn, sel, fed_back, np.zeros(6)) - unified_torque(
            dyn, sel, np.zeros(6), np.zeros(6)
        )  # J^T Lambda Omega F*_fb (eq. 29's motion part)
        eps = adapt_coulomb_error(
            eps,
            reference,
            feedback_torque,
            vec[sk.COULOMB_NM],
            vec[sk.COULOMB_NEGATIVE_NM],
            1.0 / INTENT_SCALE,
            DT_S,
        )
    moving = bool(sc[sk.MODE] != sk.MODE_HOLD or sc[sk.HAS_FORCE] or sc[sk.ADMITTANCE])
    intent = friction_intent(
        inputs.qd + vec[sk.NULL_INTENT],  # where the null space's torques turn the joints
        inputs.dynamics.jbar,
        acceleration,
        commanded,
        LOOKAHEAD_S,
        1.0 / INTENT_SCALE,
        0.0 if moving else vec[sk.COULOMB_DEAD_BAND],  # the encoders' noise: a dither there
    )
    positive, negative = (1.0 + eps) * vec[sk.COULOMB_NM], (1.0 + eps) * vec[sk.COULOMB_NEGATIVE_NM]
    coulomb = coulomb_compensation(st[sk.COULOMB], positive, negative, intent, COULOMB_BLEND)
    torque = torque + coulomb
    saturated, _ = saturate_torque(torque, vec[sk.TORQUE_MAX], keep=vec[sk.GRAVITY])
    rows = {
        sk.WRENCH: wrench,
        sk.ERROR: error,
        sk.VELOCITY: velocity,
        sk.DISPLACEMENT: displacement,
        sk.INTEGRAL: st[sk.INTEGRAL] if integral is None else integral,
        sk.MOTION_INTEGRAL: st[sk.MOTION_INTEGRAL] if motion_integral is None else motion_integral,
        sk.COULOMB: coulomb,
        sk.TORQUE: saturated,
        sk.CRUISE: st[sk.CRUISE],  # a push's speed reference at 2 and 3 (written by the caller)
        sk.FRICTION_ERROR: eps,
        sk.SURFACE: np.zeros(6),  # no held contact: its surface's friction forgotten
        **(extra or {}),
    }
    latched = bool(st[sk.FLAGS, sk.TOUCHING]) if touching is None else touching
    return ReferenceTick(rows, latched, torque, admitting)


def _run_kernel(inputs: TickInputs) -> np.ndarray:
    state = inputs.state.copy()
    sk.servo_tick(
        inputs.t_s,
        inputs.q,
        inputs.qd,
        inputs.sensor,
        inputs.scalars,
        inputs.vectors,
        inputs.matrices,
        inputs.jacobian,
        inputs.jbar_lookahead,
        inputs.stacked,
        state,
    )
    return state


ROW_NAMES = {
    sk.WRENCH: "WRENCH",
    sk.ERROR: "ERROR",
    sk.VELOCITY: "VELOCITY",
    sk.DISPLACEMENT: "DISPLACEMENT",
    sk.INTEGRAL: "INTEGRAL",
    sk.COULOMB: "COULOMB",
    sk.TORQUE: "TORQUE",
    sk.MOTION_INTEGRAL: "MOTION_INTEGRAL",
    sk.MOMENT_FILTERED: "MOMENT_FILTERED",
    sk.CRUISE: "CRUISE",
    sk.FRICTION_ERROR: "FRICTION_ERROR",
    sk.SURFACE: "SURFACE",
}


@pytest.mark.parametrize("name", list(TICK_CASES))
def test_servo_tick_matches_the_osc_composition(name: str) -> None:
    """A whole tick against sensor -> estimator -> eq. 20-21 -> Figure 2 -> eq. 29, 34 -> Coulomb ->
    saturation composed from cosmos.osc. Catches a misplaced block of ``stacked``, a wrong packed
    index, the task-frame rotation transposed, the ramp, the latch (integral moving in free space,
    or not once touching), the anti-windup clamp, the Coulomb look-ahead and the saturation; on
    compliant moment axes the moment filter, the contact latch, the admittance speed and its bound."""
    case = TICK_CASES[name]
    inputs = _tick_inputs(case, seed=sorted(TICK_CASES).index(name) + 100)
    expected = _reference_tick(inputs)
    state = _run_kernel(inputs)
    for row in expected.rows:
        try:
            assert_close(state[row], expected.rows[row])
        except AssertionError as failure:
            raise AssertionError(f"state row {ROW_NAMES[row]} differs") from failure
    assert state[sk.FLAGS, sk.TOUCHING] == float(expected.touching)
    assert state[sk.FLAGS, sk.ADMITTING] == float(expected.admitting)


@pytest.mark.parametrize("name", list(TICK_CASES))
def test_servo_tick_cases_exercise_what_they_claim(name: str) -> None:
    """Guards the cases above: each touches the latch, the integral and the Coulomb intent the way
    its name says, so a kernel that got those wrong could not pass by accident."""
    case = TICK_CASES[name]
    inputs = _tick_inputs(case, seed=sorted(TICK_CASES).index(name) + 100)
    reference = _reference_tick(inputs)
    expected, latched = reference.rows, reference.touching
    integral_before = inputs.state[sk.INTEGRAL]
    if not case.force:  # no force loop: the latch and the integral are left as they were
        assert latched == case.touching and np.array_equal(expected[sk.INTEGRAL], integral_before)
        return
    assert latched == (case.touching or abs(case.force_axis_n) > CONTACT_THRESHOLD_N)
    goal, wrench = inputs.vectors[sk.FORCE_WORLD], expected[sk.WRENCH]
    goal_met = force_goal_reached(goal, wrench)
    if inputs.scalars[sk.PUSH_SPEED] > 0.0:
        reached = case.touching or goal_met
    else:
        ramped = case.ramp_fraction >= 1.0
        landed = push_landed(goal, wrench, expected[sk.VELOCITY])
        reached = case.touching or (landed and (ramped or goal_met))
    if latched and reached:
        assert not np.array_equal(expected[sk.INTEGRAL], integral_before)
    elif latched:  # touching, the push short of its goal: the integral waits for it
        assert np.array_equal(expected[sk.INTEGRAL], integral_before)
    else:
        assert np.array_equal(expected[sk.INTEGRAL], integral_before)
        # Were it integrating, it would have moved: the latch is what holds it.
        sel = inputs.selection
        moved = integrate_force_error(
            integral_before,
            inputs.vectors[sk.FORCE_WORLD],
            expected[sk.WRENCH],
            sel.omega_bar,
            DT_S,
            FORCE_GAINS.integral_limit,
        )
        assert np.max(np.abs(moved - integral_before)) > 1e-3
    if case.integral_at_limit:
        assert np.isclose(np.max(np.abs(expected[sk.INTEGRAL])), FORCE_GAINS.integral_limit)
    # The push's speed cap binds in the cases with a small speed limit, and only there.
    inputs.scalars[sk.PUSH_SPEED] = 1e3
    uncapped = _reference_tick(inputs).rows
    inputs.scalars[sk.PUSH_SPEED] = 0.0 if case.held else case.max_speed
    capped = np.max(np.abs(uncapped[sk.TORQUE] - expected[sk.TORQUE])) > 1e-9
    assert capped == (case.max_speed < 0.01 or (case.held and latched))  # a held push, once touching
    # The free-space acceleration from the force loop changes the Coulomb term of this tick.
    other = _reference_tick(inputs, force_acceleration_always=latched).rows
    assert np.max(np.abs(other[sk.COULOMB] - expected[sk.COULOMB])) > 1e-6
    intent_unclipped = np.abs(expected[sk.COULOMB] - (1 - COULOMB_BLEND) * inputs.state[sk.COULOMB]) < (
        COULOMB_BLEND
        * np.minimum(inputs.vectors[sk.COULOMB_NM], inputs.vectors[sk.COULOMB_NEGATIVE_NM])
        * (1 - 1e-9)
    )
    assert intent_unclipped.any(), "every joint's Coulomb intent is clipped: the look-ahead goes untested"


@pytest.mark.parametrize("name", [name for name, case in TICK_CASES.items() if case.held])
def test_held_push_cases_exercise_their_speed_limit(name: str) -> None:
    """Guards the held pushes' cases: the speed limit (cosmos.osc.held_push.held_push_cap) binds in
    those past their SPEED or their landing's speed (moving along the push), and
    only there, and it changes the tick's torque and the force loop's integral (held where it binds),
    so the reference's cap is compared."""
    case = TICK_CASES[name]
    inputs = _tick_inputs(case, seed=sorted(TICK_CASES).index(name) + 100)
    reference = _reference_tick(inputs).rows
    inputs.scalars[sk.MAX_SPEED], inputs.scalars[LANDING + 1] = 1e3, 0.0
    free = _reference_tick(inputs).rows
    binds = case.max_speed < 0.01 or case.landing[1] > 0.0
    assert (np.max(np.abs(free[sk.TORQUE] - reference[sk.TORQUE])) > 1e-9) == binds
    if binds:
        assert np.array_equal(reference[sk.INTEGRAL][:3], inputs.state[sk.INTEGRAL][:3])
        assert not np.array_equal(free[sk.INTEGRAL][:3], inputs.state[sk.INTEGRAL][:3])


@pytest.mark.parametrize("name", [name for name, case in TICK_CASES.items() if case.admittance])
def test_admittance_cases_exercise_what_they_claim(name: str) -> None:
    """Guards the admittance cases: the latch is set by a contact force (not by the force axis alone),
    the bound binds where the name says, and admittance changes the tick (so the reference's
    admittance branch is compared, not skipped)."""
    case = TICK_CASES[name]
    inputs = _tick_inputs(case, seed=sorted(TICK_CASES).index(name) + 100)
    reference = _reference_tick(inputs)
    push = float(np.hypot(case.tangent_n, case.force_axis_n))
    assert reference.admitting == (case.touching or push > CONTACT_THRESHOLD_N)
    sc, mat = inputs.scalars, inputs.matrices
    moment = reference.rows[sk.MOMENT_FILTERED]
    fraction = min(1.0, (inputs.t_s - sc[sk.START_S]) / sc[sk.RAMP_S])
    start = inputs.vectors[sk.FORCE_START]
    setpoint = start + fraction * (inputs.vectors[sk.FORCE_WORLD] - start)
    unbounded = ADMITTANCE_GAIN * np.linalg.norm((mat[sk.OMEGA_ADMITTANCE] @ (setpoint - moment))[3:])
    assert (unbounded > case.admittance_max_speed) == (case.admittance_max_speed < 1.0)
    # The tilt window binds wherever the axes admit (the cases' pushes have a SPEED, as INSERT's).
    inputs.scalars[sk.TILT_WINDOW] = np.inf
    windowless = _reference_tick(inputs).rows[sk.TORQUE]
    inputs.scalars[sk.TILT_WINDOW] = TILT_WINDOW[0]
    assert (np.max(np.abs(windowless - reference.rows[sk.TORQUE])) > 1e-9) == reference.admitting
    inputs.scalars[sk.ADMITTANCE] = 0.0
    plain = _reference_tick(inputs).rows[sk.TORQUE]
    changed = np.max(np.abs(plain - reference.rows[sk.TORQUE])) > 1e-6
    assert changed == reference.admitting


@pytest.mark.parametrize("name", ["a free goal motion near its goal", "a free goal motion pushing something"])
def test_goal_integral_cases_exercise_what_they_claim(name: str) -> None:
    """Guards the free goal motion's cases: near its goal in free space the translation integral
    grows (by the error times dt) and changes the torque; pushing more than the gate's quiet force it
    is held. Catches a kernel whose goal integral never runs (the comparison above would then pass
    on an integral both sides leave alone) or that winds up against something in the way."""
    case = TICK_CASES[name]
    inputs = _tick_inputs(case, seed=sorted(TICK_CASES).index(name) + 100)
    reference = _reference_tick(inputs)
    before = inputs.state[sk.MOTION_INTEGRAL, :3]
    grown = reference.rows[sk.MOTION_INTEGRAL][:3] - before
    quiet = case.tangent_n < GOAL_INTEGRAL[4]
    if quiet:
        error = (
            inputs.vectors[sk.REFERENCE_ERROR, :3]
            + (inputs.jacobian @ (inputs.q - inputs.vectors[sk.EVALUATION_Q]))[:3]
        )
        assert_close(grown, error * DT_S)
    else:
        assert np.array_equal(grown, np.zeros(3))
    inputs.scalars[sk.GOAL_INTEGRAL] = 0.0
    plain = _reference_tick(inputs).rows[sk.TORQUE]
    assert np.max(np.abs(plain - reference.rows[sk.TORQUE])) > 1e-6  # the held integral acts too


@pytest.mark.parametrize("name", ["a free hold", "a free hold pushed"])
def test_hold_observer_cases_exercise_what_they_claim(name: str) -> None:
    """Guards the free hold's cases: quiet, the disturbance estimate moves by L times the velocity
    it did not predict, and the next prediction is ``v + dt F*``; pushed over the gate's quiet force
    the estimate is held (still applied). Catches a kernel whose observer never runs (the comparison
    above would pass on a row both sides leave alone), one that takes a contact for a disturbance,
    and one that drops the estimate from F*."""
    case = TICK_CASES[name]
    inputs = _tick_inputs(case, seed=sorted(TICK_CASES).index(name) + 100)
    reference = _reference_tick(inputs)
    before = inputs.state[sk.MOTION_INTEGRAL, :6].copy()
    after = reference.rows[sk.MOTION_INTEGRAL][:6]
    velocity = (inputs.jacobian @ inputs.qd)[:3]
    if case.tangent_n < GOAL_INTEGRAL[4]:
        assert_close(after[:3] - before[:3], HOLD_OBSERVER[0] * (velocity - before[3:6]))
    else:
        assert np.array_equal(after[:3], before[:3])
    inputs.scalars[sk.HOLD_OBSERVER : sk.HOLD_OBSERVER + 2] = 0.0  # L and the bound
    inputs.state[sk.MOTION_INTEGRAL, :3] = 0.0
    plain = _reference_tick(inputs).rows[sk.TORQUE]
    assert np.max(np.abs(plain - reference.rows[sk.TORQUE])) > 1e-6  # the estimate acts
