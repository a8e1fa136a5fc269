"""The compiled plan: the contract between the language and the executor.

A :class:`Plan` is the program after parsing, checking and compiling: a list of
steps in execution order. A step is a :class:`Segment` (the arm does something
under one fixed control law until a completion or stop condition), a scene
change (:class:`AddObstacle`, :class:`RemoveObstacle`), or a node the executor
decides at run time: a :class:`Branch` (IF), a :class:`Loop` (WHILE), an
:class:`Attempt` (TRY) and its :class:`Retry`, each holding its compiled steps.
Procedures and REPEAT loops are already expanded; each step keeps the span of
the statement it came from.

Conventions, for every field below:

- Units are SI: m, s, N, N m, rad, m/s, N/m, N m/rad, N s/m, N m s/rad.
- Vectors and matrices are read-only ``float64`` numpy arrays. A 6-vector is
  ordered (x, y, z, rx, ry, rz): three translations then three rotations.
- ``*_world`` quantities are in the world frame. 6-vectors of a segment
  (``motion_axes``, ``force_setpoint``, ``stiffness``, ``damping``) are in the
  segment's *task frame*, whose orientation is ``frame_rotation``: a 3x3 matrix
  whose columns are the task frame's x, y, z axes in world coordinates (so a
  task-frame vector v is ``frame_rotation @ v`` in the world). The task frame's
  origin is the tool point; only its orientation matters.
- Forces and moments are those the tool applies to the environment
  (docs/language.md, "Sign of forces"): ``CONTACT DOWN FORCE 10 N`` holds a
  setpoint of -10 N on the world z axis.

Statement-level semantics the executor must honour:

- Segments of one statement share ``statement_index`` (CONTACT gives two).
  ``timeout_s`` and the ``DISTANCE`` of ``until`` count from the start of the
  statement's first segment. When ``until`` holds, the statement ends with
  success: skip its remaining segments.
- A relative target or a ``None`` target is resolved against the tool pose
  measured when the segment starts.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from cosmos.errors import CosmosError, Span
from cosmos.hand.work_object import WorkObject
from cosmos.rotations import matrix_to_quaternion

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


class SegmentKind(enum.Enum):
    """What a segment does; the statement it came from is in ``Segment.statement``."""

    MOVE = "move"
    """Goal-position motion (seed eq. 20-21) or a timed trajectory (eq. 19)."""
    CONTACT_APPROACH = "contact_approach"
    """Guarded move along a direction at low speed until the tool touches."""
    CONTACT_HOLD = "contact_hold"
    """Hold the contact force on the contact axis, position on the others."""
    SLIDE = "slide"
    """Motion along a direction while the held contact axis stays force-controlled."""
    INSERT = "insert"
    """Force control along the insertion axis, zero-force compliance laterally."""
    WAIT = "wait"
    """Hold (position, and any held contact force) for a time or until a condition."""


# ----------------------------------------------------------------- targets


@dataclass(frozen=True, eq=False)
class AbsoluteTarget:
    """A goal pose in the world.

    Attributes:
        position_world: Tool point position [m], shape (3,).
        rotation_world: Tool orientation (tool frame to world), shape (3, 3), or
            ``None`` to keep the orientation the tool has when the segment starts.
    """

    position_world: FloatArray
    rotation_world: FloatArray | None


@dataclass(frozen=True, eq=False)
class RelativeTarget:
    """A goal offset from the tool position measured when the segment starts.

    Attributes:
        offset_world: Displacement of the tool point [m], world axes, shape (3,).
            The orientation is kept as it is at the segment start.
    """

    offset_world: FloatArray


Target = AbsoluteTarget | RelativeTarget


# ------------------------------------------------------------- completions


class CompletionKind(enum.Enum):
    """How a segment finishes successfully when no stop condition fires first."""

    GOAL_REACHED = "goal_reached"
    CONTACT_TOUCH = "contact_touch"
    FORCE_SETTLED = "force_settled"
    DEPTH_REACHED = "depth_reached"
    DURATION = "duration"
    CONDITION = "condition"


@dataclass(frozen=True, eq=False)
class GoalReached:
    """Done when the motion axes are at the target and the tool is nearly at rest.

    Only motion-controlled axes are compared; force-controlled axes are ignored.

    Attributes:
        position_tolerance_m: Largest position error on the motion axes [m].
        orientation_tolerance_rad: Largest orientation error on the motion axes [rad].
        speed_tolerance_mps: Largest tool-point speed [m/s].
    """

    position_tolerance_m: float
    orientation_tolerance_rad: float
    speed_tolerance_mps: float
    kind: ClassVar[CompletionKind] = CompletionKind.GOAL_REACHED


@dataclass(frozen=True, eq=False)
class ContactTouch:
    """Done when the tool touches.

    Touching: the force the tool applies along ``direction_world``
    (``wrench_force_world @ direction_world``) exceeds ``threshold_n``.

    Attributes:
        direction_world: Unit approach direction, world, shape (3,).
        threshold_n: Touch threshold [N].
        max_travel_m: The segment *fails* ("nothing touched") when the tool has
            moved this far along the direction without touching [m]. The
            segment's target sits at this distance.
    """

    direction_world: FloatArray
    threshold_n: float
    max_travel_m: float
    kind: ClassVar[CompletionKind] = CompletionKind.CONTACT_TOUCH


@dataclass(frozen=True, eq=False)
class ForceSettled:
    """Done when the force has settled on its setpoint.

    Settled: every force-controlled axis has been within ``tolerance_n`` of its
    setpoint (moments: ``tolerance_n`` read as N m) for ``settle_time_s``.

    Attributes:
        tolerance_n: Allowed force error [N].
        settle_time_s: How long the force must stay within tolerance [s].
        max_time_s: The segment fails ("force did not settle") after this long [s].
    """

    tolerance_n: float
    settle_time_s: float
    max_time_s: float
    kind: ClassVar[CompletionKind] = CompletionKind.FORCE_SETTLED


@dataclass(frozen=True, eq=False)
class DepthReached:
    """Done when the tool point has gone ``depth_m`` deep along ``direction_world``.

    Depth is measured since the statement started (its first segment):
    ``(x - x_start) @ direction_world >= depth_m``.

    Attributes:
        direction_world: Unit insertion direction, world, shape (3,).
        depth_m: Depth to reach [m].
        touch_n: None for the insertion itself. Set on an INSERT's approach (every axis
            held while it moves along the direction): done also when the force the tool
            applies exceeds this [N], in any direction (a peg that enters its hole without
            meeting the chamfer touches the bore's wall first); the insertion follows.
    """

    direction_world: FloatArray
    depth_m: float
    touch_n: float | None = None
    kind: ClassVar[CompletionKind] = CompletionKind.DEPTH_REACHED


@dataclass(frozen=True, eq=False)
class Elapsed:
    """Done after ``duration_s`` seconds in the segment (WAIT t)."""

    duration_s: float
    kind: ClassVar[CompletionKind] = CompletionKind.DURATION


@dataclass(frozen=True, eq=False)
class UntilOnly:
    """Never done by itself: only ``until`` ends it (``WAIT UNTIL ...``), or the timeout."""

    kind: ClassVar[CompletionKind] = CompletionKind.CONDITION


Completion = GoalReached | ContactTouch | ForceSettled | DepthReached | Elapsed | UntilOnly


# --------------------------------------------------------- stop conditions


class Quantity(enum.Enum):
    """A sensed quantity an UNTIL condition compares."""

    FORCE = "force"
    """Magnitude of the force the tool applies [N]."""
    FORCE_ALONG = "force_along"
    """Force the tool applies, projected on ``direction_world`` [N]."""
    TORQUE = "torque"
    """Magnitude of the moment the tool applies [N m]."""
    TORQUE_ABOUT = "torque_about"
    """Moment the tool applies, projected on ``direction_world`` [N m]."""
    DISTANCE = "distance"
    """Distance of the tool point from where the statement started [m]."""
    POSITION_ALONG = "position_along"
    """Decisions only: the tool point's coordinate along ``direction_world`` from ``origin_world`` [m]."""
    DISTANCE_FROM = "distance_from"
    """Decisions only: distance of the tool point from ``origin_world`` [m]."""
    FINGER_FORCE = "finger_force"
    """The grip: the smaller of the gripper's two pad forces, as their sensors read them [N]."""


class CompareOp(enum.Enum):
    """Comparison operators."""

    GT = ">"
    GE = ">="
    LT = "<"
    LE = "<="

    def holds(self, measured: float, value: float) -> bool:
        """``measured <op> value``."""
        if self is CompareOp.GT:
            return measured > value
        if self is CompareOp.GE:
            return measured >= value
        if self is CompareOp.LT:
            return measured < value
        return measured <= value


@dataclass(frozen=True, eq=False)
class Comparison:
    """``quantity <op> value``.

    Attributes:
        quantity: What is measured.
        direction_world: Unit vector, world, for FORCE_ALONG and TORQUE_ABOUT; else None.
        op: The comparison.
        value: Threshold in SI (N, N m or m).
        text: The condition as written.
        span: Where it is written.
        origin_world: For POSITION_ALONG and DISTANCE_FROM: the frame's origin [m],
            world, (3,); else None.
    """

    quantity: Quantity
    direction_world: FloatArray | None
    op: CompareOp
    value: float
    text: str
    span: Span
    origin_world: FloatArray | None = None


@dataclass(frozen=True, eq=False)
class AllOf:
    """True when every term is true (AND)."""

    terms: tuple[Condition, ...]


@dataclass(frozen=True, eq=False)
class AnyOf:
    """True when any term is true (OR)."""

    terms: tuple[Condition, ...]


class Ending(enum.Enum):
    """How a statement ended, as a decision asks about it (``LAST FAILED``, ``LAST STOPPED``)."""

    FAILED = "failed"
    """It failed (only inside a TRY: elsewhere a failure ends the program)."""
    STOPPED = "stopped"
    """Its UNTIL held: it ended early, with success."""


@dataclass(frozen=True, eq=False)
class LastOutcome:
    """Decisions only: true when the motion statement run last ended so.

    Attributes:
        ending: The ending asked about.
        text: The condition as written.
        span: Where it is written.
    """

    ending: Ending
    text: str
    span: Span


Condition = Comparison | AllOf | AnyOf | LastOutcome


def condition_holds(
    condition: Condition,
    force_world: FloatArray,
    torque_world: FloatArray,
    distance_m: float,
    grip_n: float = 0.0,
) -> bool:
    """Evaluate a stop condition on measured values.

    Args:
        condition: The condition tree.
        force_world: Force the tool applies to the environment [N], world, (3,).
        torque_world: Moment the tool applies to the environment [N m], world, (3,).
        distance_m: Distance of the tool point from the statement's start [m].
        grip_n: The smaller of the gripper's pad forces [N] (FINGER FORCE; 0 without the gripper).
    """
    if isinstance(condition, AllOf):
        return all(condition_holds(t, force_world, torque_world, distance_m, grip_n) for t in condition.terms)
    if isinstance(condition, AnyOf):
        return any(condition_holds(t, force_world, torque_world, distance_m, grip_n) for t in condition.terms)
    if isinstance(condition, LastOutcome):  # the compiler keeps LAST out of UNTIL
        raise ValueError(f"{condition.text} is read by IF and WHILE, not by a stop condition")
    quantity = condition.quantity
    # Scalar arithmetic on the three components: this runs every servo tick.
    if quantity is Quantity.FORCE:
        measured = math.hypot(*force_world.tolist())
    elif quantity is Quantity.TORQUE:
        measured = math.hypot(*torque_world.tolist())
    elif quantity is Quantity.FORCE_ALONG:
        measured = float(force_world.dot(condition.direction_world))  # type: ignore[arg-type]
    elif quantity is Quantity.TORQUE_ABOUT:
        measured = float(torque_world.dot(condition.direction_world))  # type: ignore[arg-type]
    elif quantity is Quantity.FINGER_FORCE:
        measured = grip_n
    else:
        measured = distance_m
    return condition.op.holds(measured, condition.value)


# ---------------------------------------------------------------- segments


@dataclass(frozen=True, eq=False)
class JamCheck:
    """When an INSERT counts as jammed.

    Jammed: the tool moves slower than ``stall_speed_mps`` along the insertion
    direction for ``stall_time_s`` before the depth is reached.
    """

    stall_speed_mps: float
    stall_time_s: float


class SearchPattern(enum.Enum):
    """The lateral pattern of an INSERT's search (:mod:`cosmos.osc.search`)."""

    SPIRAL = "spiral"
    """Archimedean spiral ``r = pitch theta / 2 pi`` out to the radius."""
    LISSAJOUS = "lissajous"
    """``(r sin(a phi), r sin((a + 1) phi))``, ``a = ceil(pi r / pitch)``, one period."""


@dataclass(frozen=True, eq=False)
class Search:
    """INSERT ... SEARCH: find the hole before inserting.

    From the segment's start the two ``lateral_axes`` are motion-controlled and
    track the pattern (eq. 19) at ``speed_mps`` along its arc, while the insertion
    axis keeps its force. When the tool has gone ``found_depth_m`` along the
    insertion direction beyond where it started, the hole is found: the lateral
    axes return to the segment's compliance and the INSERT goes on. A pattern
    run to its end without that fails the statement.

    Attributes:
        pattern: Spiral or Lissajous.
        radius_m: How far out the pattern goes [m].
        pitch_m: Spiral: the distance between its turns; Lissajous: the largest
            distance between its strands [m].
        lateral_axes: The task-frame translation axes (0..2) of the pattern's x and y.
        speed_mps: Tangential speed along the pattern [m/s].
        found_depth_m: Depth beyond the start that counts as the hole found [m].
    """

    pattern: SearchPattern
    radius_m: float
    pitch_m: float
    lateral_axes: tuple[int, int]
    speed_mps: float
    found_depth_m: float


NAMED_POSTURES = ("home",)
"""Joint configurations a POSTURE may name; the executor takes them from the arm (``home``: its keyframe)."""


@dataclass(frozen=True, eq=False)
class Posture:
    """The joint configuration the null space returns the arm to (POSTURE; seed section 4).

    Attributes:
        joints_rad: The joint angles written [rad], or None for a named pose.
        name: The named pose (one of :data:`NAMED_POSTURES`), or None.
        span: The POSTURE statement (the executor names it when the arm cannot take the pose).
    """

    joints_rad: tuple[float, ...] | None
    name: str | None
    span: Span


@dataclass(frozen=True, eq=False)
class Segment:
    """One control law held until completion, a stop condition, a timeout or a failure.

    Attributes:
        index: Position among the plan's segments, from 0.
        kind: What the segment does.
        statement_index: Counts executed statements from 0; a statement's segments
            share it (procedures and loops expanded, so every call counts anew).
        span: The statement in the source.
        line: ``span.line``.
        statement: The statement's source text.
        context: Where an expanded statement came from ("" at top level), e.g.
            ``"PROC pick called at line 12, REPEAT pass 2 of 3 at line 10"``.
        frame_name: The task frame as written (``"world"`` unless ``IN frame``).
        frame_rotation: Task frame to world rotation, (3, 3).
        motion_axes: Diagonal of the seed's selection matrix Omega, (6,) bool, task
            frame: True = motion-controlled, False = force-controlled (the
            complement selects the force servo).
        force_setpoint: Force then moment the tool applies [N, N m], task frame,
            (6,); zero on motion axes.
        stiffness: Per task axis [N/m x3, N m/rad x3]. ``None`` = the controller's
            default servo stiffness; 0.0 on every force-controlled axis; a COMPLY
            STIFFNESS value on a motion axis makes that axis a spring.
        damping: Per task axis [N s/m x3, N m s/rad x3]; ``None`` = controller default.
        target: Goal of the motion axes: absolute, relative to the pose at segment
            start, or ``None`` = hold the pose measured at segment start.
        via: Intermediate goals passed in order before ``target`` (MOVE TO ... VIA).
        via_radius_m: Switch to the next goal when this close to a via point [m].
        speed_limit_mps: Tool-point speed limit [m/s] (V_max of seed eq. 21); the
            executor also keeps force-controlled axes below it. ``None`` when the
            motion is timed or the segment does not move.
        duration_s: For a timed MOVE (``IN t``): the trajectory's duration [s] (eq. 19).
        completion: How the segment succeeds.
        until: Stop condition (UNTIL): the statement ends with success when it holds.
        timeout_s: The statement fails if not finished this long after it started [s]
            (a CONTACT_HOLD carries its CONTACT's TIMEOUT, which bounds only the
            search for the surface: the hold is bounded by ``ForceSettled.max_time_s``).
        jam_check: INSERT only: when to fail as jammed.
        force_limit_n: The protective stop's force limit in free motion set by the last
            ``LIMIT FORCE`` [N]; None for the executor's default.
        search: INSERT only: the search for the hole before inserting, or None.
        orientation_free: MOVE and WAIT under ORIENTATION FREE: the task controls the
            tool point only, the orientation is left to the null space (seed section 4).
        posture: The POSTURE in force (the null space returns the arm to it), or None.
    """

    index: int
    kind: SegmentKind
    statement_index: int
    span: Span
    line: int
    statement: str
    context: str
    frame_name: str
    frame_rotation: FloatArray
    motion_axes: BoolArray
    force_setpoint: FloatArray
    stiffness: tuple[float | None, ...]
    damping: tuple[float | None, ...]
    target: Target | None
    via: tuple[AbsoluteTarget, ...]
    via_radius_m: float | None
    speed_limit_mps: float | None
    duration_s: float | None
    completion: Completion
    until: Condition | None
    timeout_s: float | None
    jam_check: JamCheck | None
    force_limit_n: float | None = None
    search: Search | None = None
    orientation_free: bool = False
    posture: Posture | None = None

    @property
    def force_axes(self) -> BoolArray:
        """Complement of ``motion_axes``: the diagonal of the force selection matrix."""
        return ~self.motion_axes


# ------------------------------------------------------------------- scene


class ObstacleShape(enum.Enum):
    """Obstacle primitives."""

    SPHERE = "sphere"
    CYLINDER = "cylinder"
    BOX = "box"
    PLANE = "plane"


@dataclass(frozen=True, eq=False)
class AddObstacle:
    """Add an obstacle to the scene (a body in the simulation and a FIRAS field).

    Attributes:
        name: The obstacle's name as written.
        shape: Its primitive.
        position_world: Centre of the shape when added [m], (3,) (for a cylinder the
            middle of its axis; for a plane a point on it).
        rotation_world: Shape frame to world, (3, 3): a cylinder's axis and a plane's
            normal are the shape frame's z axis; a box's edges its x, y, z axes.
        radius_m: Sphere and cylinder radius [m], else None.
        height_m: Cylinder length along its axis [m], else None.
        size_m: Box edge lengths along its x, y, z axes [m], (3,), else None.
        velocity_world_mps: Constant velocity [m/s], (3,); zeros when not MOVING.
        influence_m: Distance of influence of the repulsive field (rho_0) [m], or
            None for the controller's default.
        gain_scale: Factor on the controller's default repulsion gain (1.0 = default).
        span, line, statement: Where it was written.
    """

    name: str
    shape: ObstacleShape
    position_world: FloatArray
    rotation_world: FloatArray
    radius_m: float | None
    height_m: float | None
    size_m: FloatArray | None
    velocity_world_mps: FloatArray
    influence_m: float | None
    gain_scale: float
    span: Span
    line: int
    statement: str


@dataclass(frozen=True, eq=False)
class RemoveObstacle:
    """Remove the obstacle named ``name`` from the scene."""

    name: str
    span: Span
    line: int
    statement: str


class HandAction(enum.Enum):
    """What a hand step does."""

    GRASP = "grasp"
    RELEASE = "release"


@dataclass(frozen=True, eq=False)
class HandStep:
    """GRASP or RELEASE: the gripper closes on an object and holds it, or opens and lets go.

    Attributes:
        action: Grasp or release.
        object_name: The object a GRASP names (as declared), or None for whatever is between
            the fingers; None for a RELEASE.
        force_n: The grip force [N] (a RELEASE opens with the drive's smallest force).
        width_m: The opening a GRASP expects to close to (``WIDTH``) [m], or None.
        span, line, statement: Where it was written.
    """

    action: HandAction
    object_name: str | None
    force_n: float
    width_m: float | None
    span: Span
    line: int
    statement: str


# -------------------------------------------------------- decided at run time


@dataclass(frozen=True, eq=False)
class Branch:
    """IF: the executor reads the condition when it reaches the IF and runs one branch.

    Attributes:
        condition: Read once, on what the arm senses then (and the last statement's ending).
        then_steps: Run when it holds.
        else_steps: Run when it does not (empty without ELSE).
        else_line: The ELSE's line, None without one.
        span, line, statement, context: Where it was written (as for a segment).
    """

    condition: Condition
    then_steps: tuple[Step, ...]
    else_steps: tuple[Step, ...]
    else_line: int | None
    span: Span
    line: int
    statement: str
    context: str


@dataclass(frozen=True, eq=False)
class Loop:
    """WHILE: the condition is read before each pass; the body runs while it holds.

    Attributes:
        condition: Read before every pass.
        body: The steps of one pass.
        max_passes: The loop fails when the condition still holds after this many passes.
        span, line, statement, context: Where it was written.
    """

    condition: Condition
    body: tuple[Step, ...]
    max_passes: int
    span: Span
    line: int
    statement: str
    context: str


@dataclass(frozen=True, eq=False)
class Attempt:
    """TRY: a step of ``body`` that fails runs ``handler`` instead of ending the program.

    The failure leaves the arm holding its pose (no force commanded) before the
    handler starts; a :class:`Retry` in the handler runs ``body`` again.

    Attributes:
        body: The steps tried.
        handler: The ON FAIL steps.
        handler_line: The ON FAIL's line.
        span, line, statement, context: Where the TRY was written.
    """

    body: tuple[Step, ...]
    handler: tuple[Step, ...]
    handler_line: int
    span: Span
    line: int
    statement: str
    context: str


@dataclass(frozen=True, eq=False)
class Retry:
    """RETRY n (in an Attempt's handler): run the Attempt's body again, at most ``times`` times in all.

    When the body has already been run again ``times`` times, the failure that
    led here ends the program.
    """

    times: int
    span: Span
    line: int
    statement: str
    context: str


Step = Segment | AddObstacle | RemoveObstacle | HandStep | Branch | Loop | Attempt | Retry
Decided = Branch | Loop | Attempt | Retry
"""The steps decided at run time."""


def inner_steps(step: Step) -> tuple[Step, ...]:
    """The steps a step holds, in the order they are written (none for a segment or scene change)."""
    if isinstance(step, Branch):
        return step.then_steps + step.else_steps
    if isinstance(step, Loop):
        return step.body
    if isinstance(step, Attempt):
        return step.body + step.handler
    return ()


def all_steps(steps: tuple[Step, ...]) -> list[Step]:
    """Every step, depth first: each node before the steps it holds."""
    found: list[Step] = []
    for step in steps:
        found.append(step)
        if isinstance(step, Branch | Loop | Attempt):
            found += all_steps(inner_steps(step))
    return found


# -------------------------------------------------------------------- plan


@dataclass(frozen=True)
class Diagnostic:
    """A warning: legal but likely not what was meant."""

    message: str
    span: Span

    def render(self, source: str | None = None) -> str:
        """``file:line:col: warning: message``, the line, and a caret."""
        return CosmosError(f"warning: {self.message}", self.span, source).render()


@dataclass(frozen=True, eq=False)
class Plan:
    """A compiled program.

    Attributes:
        file: The program's path as given.
        source: The program text.
        steps: Segments and scene changes in execution order.
        warnings: Diagnostics that do not stop the program.
        robot: The arm it runs on (:data:`cosmos.robots.ROBOTS`: its ROBOT statement, else the
            run's ``--robot``, else the PUMA 560).
        tool: The hand on the flange (``peg`` or ``gripper``: its TOOL statement, else the peg).
        objects: The workcell's free objects (its OBJECT statements), there from the start.
    """

    file: str
    source: str
    steps: tuple[Step, ...]
    warnings: tuple[Diagnostic, ...]
    robot: str = "puma560"
    tool: str = "peg"
    objects: tuple[WorkObject, ...] = ()

    @property
    def segments(self) -> tuple[Segment, ...]:
        """Every segment, in order, those of every branch included (``Segment.index`` order)."""
        if not any(isinstance(step, Branch | Loop | Attempt) for step in self.steps):
            return tuple(step for step in self.steps if isinstance(step, Segment))
        return tuple(step for step in all_steps(self.steps) if isinstance(step, Segment))

    @property
    def decided(self) -> bool:
        """Whether the plan has steps decided at run time (IF, WHILE, TRY)."""
        return any(isinstance(step, Branch | Loop | Attempt) for step in self.steps)


# -------------------------------------------------------------------- JSON


def _floats(values: Any) -> list[float]:
    return [float(v) for v in np.asarray(values, dtype=np.float64).ravel()]


def _target_json(target: Target | None) -> dict[str, Any] | None:
    if target is None:
        return None
    if isinstance(target, RelativeTarget):
        return {"type": "relative", "offset": _floats(target.offset_world)}
    orientation = None if target.rotation_world is None else list(matrix_to_quaternion(target.rotation_world))
    return {"type": "absolute", "position": _floats(target.position_world), "orientation": orientation}


def _completion_json(completion: Completion) -> dict[str, Any]:
    fields: dict[str, Any] = {"type": completion.kind.value}
    for name, value in vars(completion).items():
        fields[name] = _floats(value) if isinstance(value, np.ndarray) else value
    return fields


def condition_to_json(condition: Condition) -> dict[str, Any]:
    """A condition as nested dicts."""
    if isinstance(condition, AllOf | AnyOf):
        key = "all" if isinstance(condition, AllOf) else "any"
        return {key: [condition_to_json(t) for t in condition.terms]}
    if isinstance(condition, LastOutcome):
        return {"last": condition.ending.value, "text": condition.text}
    direction = None if condition.direction_world is None else _floats(condition.direction_world)
    fields = {
        "quantity": condition.quantity.value,
        "direction": direction,
        "op": condition.op.value,
        "value": condition.value,
        "text": condition.text,
    }
    if condition.origin_world is not None:
        fields["origin"] = _floats(condition.origin_world)
    return fields


def segment_to_json(segment: Segment) -> dict[str, Any]:
    """A segment as a JSON-ready dict (the fields of the ``/cosmos/segment`` topic).

    ``frame`` is the task frame orientation as a quaternion (w, x, y, z);
    ``motion_axes`` is 6 of 0/1; ``stiffness`` and ``damping`` hold ``null`` where
    the controller's default applies.
    """
    return {
        "segment": segment.index,
        "kind": segment.kind.value,
        "line": segment.line,
        "column": segment.span.column,
        "statement": segment.statement,
        "statement_index": segment.statement_index,
        "context": segment.context,
        "frame_name": segment.frame_name,
        "frame": list(matrix_to_quaternion(segment.frame_rotation)),
        "motion_axes": [int(bool(a)) for a in segment.motion_axes],
        "force_setpoint": _floats(segment.force_setpoint),
        "stiffness": list(segment.stiffness),
        "damping": list(segment.damping),
        "goal": _target_json(segment.target),
        "via": [_target_json(v) for v in segment.via],
        "via_radius": segment.via_radius_m,
        "speed_limit": segment.speed_limit_mps,
        "duration": segment.duration_s,
        "timeout": segment.timeout_s,
        "completion": _completion_json(segment.completion),
        "until": None if segment.until is None else condition_to_json(segment.until),
        "force_limit": segment.force_limit_n,
        "jam_check": None
        if segment.jam_check is None
        else {
            "stall_speed": segment.jam_check.stall_speed_mps,
            "stall_time": segment.jam_check.stall_time_s,
        },
        "search": None
        if segment.search is None
        else {
            "pattern": segment.search.pattern.value,
            "radius": segment.search.radius_m,
            "pitch": segment.search.pitch_m,
            "lateral_axes": list(segment.search.lateral_axes),
            "speed": segment.search.speed_mps,
            "found_depth": segment.search.found_depth_m,
        },
        "orientation_free": segment.orientation_free,
        "posture": None
        if segment.posture is None
        else {
            "name": segment.posture.name,
            "joints": None if segment.posture.joints_rad is None else list(segment.posture.joints_rad),
        },
    }


def _decided_to_json(step: Decided) -> dict[str, Any]:
    """An IF, WHILE, TRY or RETRY as a dict holding its steps."""
    where = {"line": step.line, "statement": step.statement, "context": step.context}
    if isinstance(step, Branch):
        return {
            "step": "if",
            **where,
            "condition": condition_to_json(step.condition),
            "then": [step_to_json(s) for s in step.then_steps],
            "else": [step_to_json(s) for s in step.else_steps],
            "else_line": step.else_line,
        }
    if isinstance(step, Loop):
        return {
            "step": "while",
            **where,
            "condition": condition_to_json(step.condition),
            "max_passes": step.max_passes,
            "body": [step_to_json(s) for s in step.body],
        }
    if isinstance(step, Attempt):
        return {
            "step": "try",
            **where,
            "body": [step_to_json(s) for s in step.body],
            "on_fail": [step_to_json(s) for s in step.handler],
            "on_fail_line": step.handler_line,
        }
    return {"step": "retry", **where, "times": step.times}


def step_to_json(step: Step) -> dict[str, Any]:
    """A step as a JSON-ready dict with a ``step`` field naming its type."""
    if isinstance(step, Segment):
        return {"step": "segment", **segment_to_json(step)}
    if isinstance(step, Branch | Loop | Attempt | Retry):
        return _decided_to_json(step)
    if isinstance(step, RemoveObstacle):
        return {"step": "remove_obstacle", "name": step.name, "line": step.line, "statement": step.statement}
    if isinstance(step, HandStep):
        return {
            "step": step.action.value,
            "object": step.object_name,
            "force": step.force_n,
            "width": step.width_m,
            "line": step.line,
            "statement": step.statement,
        }
    return {
        "step": "add_obstacle",
        "name": step.name,
        "shape": step.shape.value,
        "position": _floats(step.position_world),
        "orientation": list(matrix_to_quaternion(step.rotation_world)),
        "radius": step.radius_m,
        "height": step.height_m,
        "size": None if step.size_m is None else _floats(step.size_m),
        "velocity": _floats(step.velocity_world_mps),
        "influence": step.influence_m,
        "gain_scale": step.gain_scale,
        "line": step.line,
        "statement": step.statement,
    }


def plan_to_json(plan: Plan) -> Mapping[str, Any]:
    """The plan as JSON-ready dicts: ``file``, ``robot``, ``steps``, ``warnings``."""
    return {
        "file": plan.file,
        "robot": plan.robot,
        "tool": plan.tool,
        "objects": [
            {
                "name": item.name,
                "shape": item.shape.value,
                "size_m": [2 * h for h in item.half_extents_m],
                "mass_kg": item.mass_kg,
                "position_m": list(item.position_m),
                "friction": item.friction,
            }
            for item in plan.objects
        ],
        "steps": [step_to_json(step) for step in plan.steps],
        "warnings": [
            {"line": w.span.line, "column": w.span.column, "message": w.message} for w in plan.warnings
        ],
    }
