"""What the servo level is asked to do during one segment, resolved to world numbers."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from cosmos.capabilities import ARM_CAPABILITY
from cosmos.osc.motion import PoseTrajectory
from cosmos.osc.search import SearchTrajectory

FloatArray = np.ndarray

DEFAULT_KP = 400.0  # 1/s^2: unit-mass stiffness, a 20 rad/s (3.2 Hz) closed loop
DEFAULT_KV = 40.0  # 1/s: critical damping for DEFAULT_KP (2 sqrt(kp))
DEFAULT_MAX_ANGULAR_SPEED = 1.0  # rad/s: speed limit of rotations in goal motion


class MotionMode(Enum):
    """How the motion-controlled axes move."""

    HOLD = "hold"  # hold a fixed pose (eq. 19 with a constant x_d)
    GOAL = "goal"  # goal position with a speed limit, straight line (eq. 20-21)
    TRAJECTORY = "trajectory"  # timed trajectory tracked with eq. 19


def _identity() -> FloatArray:
    return np.eye(3)


def _gains(value: float) -> FloatArray:
    return np.full(6, value)


@dataclass(frozen=True)
class ServoSetpoint:
    """One segment's command to the servo level; world axes unless a name says task.

    Attributes:
        mode: How motion axes move.
        position: Goal (or hold) tool point, in [m]. # (3,)
        rotation_to_world: Goal (or hold) tool orientation. # (3, 3)
        rotation_task_to_world: Task frame of the selection and the force setpoint. # (3, 3)
        motion_axes: Per task axis, True motion-controlled, False force-controlled. # (6,)
        force_task: Force setpoint, applied to the environment, task axes, [N, N m]. # (6,)
        force_start_world: Sensed force when the segment began; the setpoint ramps
            from it to ``force_task``, world axes, [N, N m]. # (6,)
        ramp_s: Duration of that ramp, in [s].
        start_s: Simulated time at which the segment began, in [s].
        max_speed: Speed limit V_max of eq. 21, in [m/s].
        max_angular_speed: Its rotational counterpart, in [rad/s].
        acceleration: The acceleration at which a goal motion's speed limit ramps up from
            the tool's speed at its start (:func:`cosmos.osc.motion.ramped_speed_limit`),
            in [m/s^2].
        angular_acceleration: Its rotational counterpart, in [rad/s^2].
        kp_task: Unit-mass position gains per task axis, in [1/s^2]. # (6,)
        kv_task: Velocity gains per task axis, in [1/s]. # (6,)
        trajectory: The timed trajectory in TRAJECTORY mode (an INSERT's search pattern too).
        limit_push_speed: Hold the force-controlled push to ``max_speed`` (INSERT: the
            insertion axis's speed limit; :func:`cosmos.osc.unified.speed_limited_push`).
        orientation_free: The task controls the tool point only (ORIENTATION FREE): the
            rotation axes are left to the null space (seed section 4).
        posture_rad: The joint configuration the null space returns the arm to
            (POSTURE), in [rad], or None for none. # (n,)
        spring_masses: Per task axis, its effective mass ``n^T Lambda n`` where COMPLY ...
            STIFFNESS makes it a spring, else 0, in [kg, kg m^2]: the spring is held to its law
            ``f = k (x_anchor - x)`` (:func:`cosmos.osc.integral_action.hold_spring_law`). # (6,)
        cruise_integral: A GOAL motion's cruise held to ``max_speed`` by integral action
            (:mod:`cosmos.osc.cruise_speed`); False leaves eq. 20-21 proportional (an INSERT's
            approach, whose insertion is tuned to the landing it had).
        touch_braking: A CONTACT's approach: the motion into the first push felt along it is damped
            (:func:`cosmos.osc.contact.touch_braking`).
        landing: A CONTACT's approach toward a stiff surface its workcell model knows
            (:mod:`cosmos.osc.landing`): ``(s_l [m], v_l [m/s], a [m/s^2])``, ``v_l`` 0 for none.
        leg: A MOVE ... VIA's goal motion after its first VIA point: the next leg of the motion
            before, which starts at ``start_s`` (:func:`cosmos.runtime.kernels.cruise.restart`).
    """

    mode: MotionMode
    position: FloatArray
    rotation_to_world: FloatArray
    rotation_task_to_world: FloatArray = field(default_factory=_identity)
    motion_axes: tuple[bool, ...] = (True,) * 6
    force_task: FloatArray = field(default_factory=lambda: np.zeros(6))
    force_start_world: FloatArray = field(default_factory=lambda: np.zeros(6))
    ramp_s: float = 0.2
    start_s: float = 0.0
    max_speed: float = 0.25
    max_angular_speed: float = DEFAULT_MAX_ANGULAR_SPEED
    acceleration: float = ARM_CAPABILITY.tool_acceleration_mps2
    angular_acceleration: float = ARM_CAPABILITY.angular_acceleration_rad_s2
    kp_task: FloatArray = field(default_factory=lambda: _gains(DEFAULT_KP))
    kv_task: FloatArray = field(default_factory=lambda: _gains(DEFAULT_KV))
    trajectory: PoseTrajectory | SearchTrajectory | None = None
    limit_push_speed: bool = False
    orientation_free: bool = False
    posture_rad: FloatArray | None = None
    spring_masses: FloatArray = field(default_factory=lambda: np.zeros(6))
    cruise_integral: bool = True
    touch_braking: bool = False
    landing: tuple[float, float, float] = (0.0, 0.0, 0.0)
    leg: bool = False

    force_world: FloatArray = field(init=False)
    """The force setpoint in world axes (derived from force_task). # (6,)."""
    uniform_gains: bool = field(init=False)
    """True when every axis has the same gains (the servo then skips frame rotations)."""

    @property
    def insert_approach(self) -> bool:
        """An INSERT's approach (:func:`cosmos.osc.push_speed.approach_speed`).

        A GOAL motion without the cruise integral, with uniform gains (a spring's are its own).
        """
        return self.mode is MotionMode.GOAL and not self.cruise_integral and self.uniform_gains

    def continues(self, previous: ServoSetpoint | None) -> bool:
        """Whether this is the next leg (``leg``) of ``previous``'s goal motion, with its cruise integral."""
        return (
            self.leg
            and previous is not None
            and previous.mode is MotionMode.GOAL
            and self.mode is MotionMode.GOAL
            and previous.motion_axes == self.motion_axes
            and previous.cruise_integral
            and self.cruise_integral
        )

    def __post_init__(self) -> None:
        r = self.rotation_task_to_world
        target = np.concatenate((r.dot(self.force_task[:3]), r.dot(self.force_task[3:])))
        object.__setattr__(self, "force_world", target)
        # The ramp starts from the sensed force, but never from beyond the setpoint nor
        # from the other side of zero: an impact spike at touch is no place to start from.
        start = np.clip(self.force_start_world, np.minimum(target, 0.0), np.maximum(target, 0.0))
        object.__setattr__(self, "force_start_world", start)
        object.__setattr__(self, "uniform_gains", _uniform(self.kp_task) and _uniform(self.kv_task))


def _uniform(gains: FloatArray) -> bool:
    """Whether every entry of ``gains`` equals the first: ``np.all(gains == gains[0])`` in floats.

    Two of NumPy's comparisons and reductions cost a segment's start 5 us; a list of six floats, 1 us.
    """
    values = gains.tolist()
    return all(value == values[0] for value in values)
