"""The physical range of every number a program gives: durations, speeds, distances, forces, counts.

Pure functions of values: each returns the message of a check error, or None.
The checker calls them where a slot's value becomes a number
(:meth:`cosmos.lang.evaluate.evaluator.Evaluator.expect_scalar` and ``expect_vector``), so
nothing a program says runs unbounded (``WAIT 1e308 s``), crawls for ever
(``SPEED 1e-300 m/s``) or overflows (``MOVE BY (1e305 mm, 0, 0)``), and a
request beyond the workcell's declared capabilities
(:data:`cosmos.capabilities.WRIST_SENSOR`, :data:`cosmos.capabilities.ARM_CAPABILITY`)
is refused with the limit in the message. The table is documented in
docs/language.md, "Limits"; a slot without a row of its own takes its
dimension's row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos import plan
from cosmos.capabilities import ARM_CAPABILITY, HOME_TOOL, WRIST_SENSOR, ArmCapability, Pose
from cosmos.errors import Span
from cosmos.hand.tool import GRIPPER
from cosmos.lang import units

MAX_DURATION_S = 3600.0
"""Longest WAIT, TIMEOUT or timed move [s]: one hour."""
MIN_DURATION_S = 0.001
"""Shortest: one servo period [s]."""
MAX_TRAVEL_M = 2.0
"""Longest relative move, slide or insertion [m] (the arm reaches 0.88 m)."""
MAX_COORDINATE_M = 10.0
"""Largest coordinate of a position [m]: the workcell's size, generously."""
MIN_SPEED_MPS = 1e-4
"""Slowest tool speed a program may ask [m/s] (0.1 mm/s)."""
MAX_OBSTACLE_SPEED_MPS = 5.0
"""Fastest MOVING obstacle [m/s]."""
MAX_OBSTACLES = 64
"""Obstacles a program's scene may hold at once: the workcell's obstacle slots
(:data:`cosmos.obstacles.scene.CAPACITY` is this number)."""
MAX_ANGLE_RAD = 4.0 * math.pi
"""Largest angle a program may write [rad] (two turns)."""
MAX_COUNT = 10_000
MAX_SEARCH_RADIUS_M = 0.05
"""Largest SEARCH RADIUS [m]: a search is for a part placed within centimetres."""
MIN_SEARCH_PITCH_M = 5e-4
"""Smallest SEARCH PITCH [m]: finer than the arm's tracking under friction, and slow."""
"""Largest REPEAT count and GAIN."""


@dataclass(frozen=True)
class Range:
    """A slot's allowed magnitudes, in SI, and how to write them in messages.

    Attributes:
        low: Smallest magnitude (0 where any non-negative value will do).
        high: Largest magnitude.
        scale: SI value of one ``unit`` (1e-3 for mm).
        unit: The unit the message writes the range in.
        why: What the upper bound is (``the wrist sensor's rating``).
    """

    low: float
    high: float
    scale: float
    unit: str
    why: str = ""

    def text(self) -> str:
        """``0.1 mm/s to 1000 mm/s``."""
        low, high = self.low / self.scale, self.high / self.scale
        unit = f" {self.unit}" if self.unit else ""
        return f"{low:g}{unit} to {high:g}{unit}"


_DURATION = Range(MIN_DURATION_S, MAX_DURATION_S, 1.0, "s", "one hour")
_TRAVEL = Range(0.0, MAX_TRAVEL_M, 1e-3, "mm", "more than the arm spans")
_FORCE = Range(0.0, WRIST_SENSOR.force_n, 1.0, "N", "the wrist sensor's rating")
_TORQUE = Range(0.0, WRIST_SENSOR.torque_nm, 1.0, "N m", "the wrist sensor's rating")
_ARM_SPEED = Range(MIN_SPEED_MPS, ARM_CAPABILITY.tool_speed_mps, 1e-3, "mm/s", "the arm's tool speed")

SLOT_RANGES: dict[tuple[str, units.Dim], Range] = {
    ("SPEED", units.SPEED): _ARM_SPEED,
    ("WAIT", units.TIME): _DURATION,
    ("TIMEOUT", units.TIME): _DURATION,
    ("IN", units.TIME): _DURATION,
    ("BY", units.LENGTH): _TRAVEL,
    ("DEPTH", units.LENGTH): _TRAVEL,
    ("MOVE BY", units.LENGTH): _TRAVEL,
    ("FORCE", units.FORCE): _FORCE,
    ("SEARCH RADIUS", units.LENGTH): Range(
        0.0, MAX_SEARCH_RADIUS_M, 1e-3, "mm", "a search finds a part placed within centimetres"
    ),
    ("SEARCH PITCH", units.LENGTH): Range(MIN_SEARCH_PITCH_M, MAX_SEARCH_RADIUS_M, 1e-3, "mm"),
    ("LIMIT FORCE", units.FORCE): _FORCE,
    ("GRASP FORCE", units.FORCE): Range(
        GRIPPER.grip_force_min_n, GRIPPER.grip_force_max_n, 1.0, "N", "the gripper's datasheet"
    ),
    ("REPEAT", units.DIMENSIONLESS): Range(0.0, MAX_COUNT, 1.0, "", "passes"),
    ("GAIN", units.DIMENSIONLESS): Range(0.0, MAX_COUNT, 1.0, ""),
    ("MOVING", units.SPEED): Range(0.0, MAX_OBSTACLE_SPEED_MPS, 1.0, "m/s"),
    ("STIFFNESS", units.STIFFNESS): Range(
        0.0, ARM_CAPABILITY.stiffness_n_per_m, 1.0, "N/m", "what the servo renders"
    ),
    ("STIFFNESS", units.ROTATIONAL_STIFFNESS): Range(
        0.0, ARM_CAPABILITY.stiffness_nm_per_rad, 1.0, "Nm/rad", "what the servo renders"
    ),
    ("DAMPING", units.DAMPING): Range(
        0.0, ARM_CAPABILITY.damping_ns_per_m, 1.0, "Ns/m", "what the servo renders"
    ),
    ("DAMPING", units.ROTATIONAL_DAMPING): Range(
        0.0, ARM_CAPABILITY.damping_nms_per_rad, 1.0, "Nms/rad", "what the servo renders"
    ),
}
"""Ranges of named slots (the slot as the checker names it, and its dimension)."""

DIMENSION_RANGES: dict[units.Dim, Range] = {
    units.TIME: Range(0.0, MAX_DURATION_S, 1.0, "s", "one hour"),
    units.LENGTH: Range(0.0, MAX_COORDINATE_M, 1.0, "m", "the workcell's size"),
    units.SPEED: Range(0.0, ARM_CAPABILITY.tool_speed_mps, 1e-3, "mm/s", "the arm's tool speed"),
    units.FORCE: _FORCE,
    units.TORQUE: _TORQUE,
    units.ANGLE: Range(0.0, MAX_ANGLE_RAD, math.pi / 180.0, "deg", "two turns"),
    units.STIFFNESS: SLOT_RANGES[("STIFFNESS", units.STIFFNESS)],
    units.ROTATIONAL_STIFFNESS: SLOT_RANGES[("STIFFNESS", units.ROTATIONAL_STIFFNESS)],
    units.DAMPING: SLOT_RANGES[("DAMPING", units.DAMPING)],
    units.ROTATIONAL_DAMPING: SLOT_RANGES[("DAMPING", units.ROTATIONAL_DAMPING)],
}
"""Ranges by dimension: for every slot without a row of its own (positions, thresholds)."""


def range_of(what: str, dim: units.Dim) -> Range | None:
    """The range of slot ``what`` of dimension ``dim`` (its own row, else its dimension's)."""
    found = SLOT_RANGES.get((what, dim))
    return found if found is not None else DIMENSION_RANGES.get(dim)


def _problem(what: str, written: str, magnitude: float, found: Range) -> str | None:
    if found.low <= magnitude <= found.high:
        return None
    why = f" ({found.why})" if found.why and magnitude > found.high else ""
    bound = "at most" if magnitude > found.high else "at least"
    limit = found.high if magnitude > found.high else found.low
    unit = f" {found.unit}" if found.unit else ""
    return (
        f"{what} {written} is out of its range: {bound} {limit / found.scale:g}{unit}{why}; "
        f"the range is {found.text()}"
    )


def scalar_problem(what: str, dim: units.Dim, value: float, written: str) -> str | None:
    """The check error for a slot's number outside its range, else None.

    Args:
        what: The slot (``"SPEED"``, ``"WAIT"``, a condition's ``"FORCE Z"``).
        dim: Its dimension.
        value: Its SI value (the sign is a direction: the magnitude is judged).
        written: The value as written, for the message.
    """
    found = range_of(what, dim)
    if found is None or not math.isfinite(value):
        return None  # not a bounded slot, or a NaN / inf the slot's own check refuses
    magnitude = abs(value)
    if magnitude == 0.0 and found.low > 0.0:
        return None  # "must be positive" is the slot's own message
    return _problem(what, written, magnitude, found)


def vector_problem(what: str, dim: units.Dim, values: tuple[float, ...], written: str) -> str | None:
    """The check error for a vector with a component outside its slot's range, else None."""
    found = range_of(what, dim)
    if found is None:
        return None
    bounded = Range(0.0, found.high, found.scale, found.unit, found.why)  # a component may be 0
    for value in values:
        if math.isfinite(value):
            problem = _problem(what, written, abs(value), bounded)
            if problem is not None:
                return problem
    return None


def shortest_timed_move_s(distance_m: float, angle_rad: float, arm: ArmCapability = ARM_CAPABILITY) -> float:
    """The shortest duration of a timed move the arm can do [s].

    A timed move follows a minimum-jerk profile (:class:`cosmos.osc.motion.PoseTrajectory`):
    over a distance d in time T its peak speed is 1.875 d / T and its peak acceleration
    5.774 d / T^2; both must stay within the arm's capabilities (the PUMA's by default,
    :attr:`cosmos.robots.Robot.capability`), for the translation and for the rotation.
    """
    return max(
        1.875 * distance_m / arm.tool_speed_mps,
        math.sqrt(5.774 * distance_m / arm.tool_acceleration_mps2),
        1.875 * angle_rad / arm.angular_speed_rad_s,
        math.sqrt(5.774 * angle_rad / arm.angular_acceleration_rad_s2),
        MIN_DURATION_S,
    )


def timed_move_problem(
    distance_m: float, angle_rad: float, duration_s: float, arm: ArmCapability = ARM_CAPABILITY
) -> str | None:
    """The check error for a timed move the arm cannot do in ``duration_s``, else None."""
    shortest = shortest_timed_move_s(distance_m, angle_rad, arm)
    if duration_s >= shortest:
        return None
    return (
        f"cannot move {distance_m * 1e3:.0f} mm"
        + (f" and turn {math.degrees(angle_rad):.0f} deg" if angle_rad > 1e-9 else "")
        + f" in {duration_s:g} s: the shortest feasible duration is {math.ceil(shortest * 100) / 100:g} s "
        f"(the tool at most {arm.tool_speed_mps:g} m/s and "
        f"{arm.tool_acceleration_mps2:g} m/s^2, its rotation at most "
        f"{arm.angular_speed_rad_s:g} rad/s and "
        f"{arm.angular_acceleration_rad_s2:g} rad/s^2)"
    )


def first_infeasible_timed_move(
    steps: tuple[plan.Step, ...], arm: ArmCapability = ARM_CAPABILITY, home: Pose = HOME_TOOL
) -> tuple[str, Span] | None:
    """The first timed ``MOVE TO`` the arm cannot do in its time, where its start is known.

    The tool starts at ``home`` (the arm's with its tool); after a MOVE that ends where it
    was sent (no UNTIL) the tool is known to be at its goal; after anything else (a contact,
    a slide, a stopped motion) it is not known until the next such MOVE. (A timed MOVE BY is
    judged at the statement, its distance being known without this.)

    Returns:
        The check error and the statement's span, or None.
    """
    position: np.ndarray | None = np.array(home.position)
    rotation = np.array(home.rotation)
    for step in steps:
        if not isinstance(step, plan.Segment):
            continue
        target = step.target
        goal_rotation = rotation
        if isinstance(target, plan.AbsoluteTarget) and target.rotation_world is not None:
            goal_rotation = np.asarray(target.rotation_world)
        if step.duration_s is not None and position is not None and isinstance(target, plan.AbsoluteTarget):
            distance = float(np.linalg.norm(np.asarray(target.position_world) - position))
            cosine = (float(np.trace(rotation.T @ goal_rotation)) - 1.0) / 2.0
            angle = math.acos(min(1.0, max(-1.0, cosine)))
            problem = timed_move_problem(distance, angle, step.duration_s, arm)
            if problem is not None:
                return f"from where the program leaves the tool, the arm {problem}", step.span
        end = step.tool_end
        if end is plan.ToolEnd.STAYS:
            continue
        if end is plan.ToolEnd.UNKNOWN:
            position = None
        elif isinstance(target, plan.AbsoluteTarget):
            position, rotation = np.asarray(target.position_world), goal_rotation
        elif isinstance(target, plan.RelativeTarget) and position is not None:
            position = position + target.offset_world
    return None
