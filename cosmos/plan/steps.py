"""The other steps (scene changes, hand actions, decisions made at run time) and the plan."""

from __future__ import annotations

import enum
from dataclasses import dataclass

from cosmos.errors import CosmosError, Span
from cosmos.hand.work_object import WorkObject
from cosmos.plan.conditions import Condition
from cosmos.plan.segments import Segment
from cosmos.plan.targets import FloatArray

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
