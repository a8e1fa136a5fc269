"""What carries from one statement to the next while compiling.

The compile state is an immutable value: compiling a statement takes a state
and returns a new one, so a REPL can compile its inputs one by one and keep
names, frames, procedures, compliance and the held contact between them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Protocol, TypeVar

from cosmos import plan
from cosmos.errors import Span
from cosmos.hand.work_object import WorkObject
from cosmos.lang import ast
from cosmos.lang.evaluate.values import Binding
from cosmos.robots import DEFAULT_ROBOT
from cosmos.rotations import IDENTITY, FloatArray


class FrameLike(Protocol):
    """A fixture frame as the workcell gives it (``cosmos.workcell.FixtureFrame``)."""

    @property
    def position(self) -> FloatArray:
        """Origin [m], world, (3,)."""
        ...

    @property
    def rotation(self) -> FloatArray:
        """Frame to world, (3, 3)."""
        ...


@dataclass(frozen=True)
class Defaults:
    """Numbers the language fills in when a program does not say (docs/language.md).

    Attributes:
        speed_mps: Speed limit of MOVE and SLIDE until a SPEED statement [m/s].
        contact_speed_mps: Approach speed of CONTACT without SPEED [m/s].
        insert_speed_mps: Speed limit of INSERT without SPEED [m/s].
        contact_max_travel_m: CONTACT fails when it has gone this far untouched [m].
        touch_threshold_n: Force that counts as touching [N] (at most half the FORCE).
        settle_tolerance_n: Force error that counts as settled [N] (or 10 % of FORCE).
        settle_time_s: How long the force must stay settled [s].
        settle_max_time_s: A CONTACT hold fails when not settled after this long [s].
        position_tolerance_m: MOVE/SLIDE goal tolerance on position [m].
        orientation_tolerance_rad: Goal tolerance on orientation [rad].
        rest_speed_mps: The tool counts as at rest below this speed [m/s].
        via_radius_m: A via point counts as passed within this distance [m].
        jam_stall_speed_mps: INSERT is jammed below this speed along its axis [m/s] ...
        jam_stall_time_s: ... held for this long [s].
        search_speed_mps: Tangential speed of INSERT's SEARCH pattern [m/s].
        search_found_depth_m: A SEARCH has found the hole when the tool has gone this
            much deeper than where the INSERT started [m].
    """

    speed_mps: float = 0.1
    contact_speed_mps: float = 0.02
    insert_speed_mps: float = 0.02
    contact_max_travel_m: float = 0.3
    touch_threshold_n: float = plan.TOUCH_THRESHOLD_N
    settle_tolerance_n: float = 0.5
    settle_time_s: float = 0.2
    settle_max_time_s: float = 3.0
    position_tolerance_m: float = 1e-3
    orientation_tolerance_rad: float = 0.0175
    rest_speed_mps: float = 5e-3
    via_radius_m: float = 0.01
    jam_stall_speed_mps: float = 5e-4
    jam_stall_time_s: float = 1.0
    search_speed_mps: float = 0.01
    search_found_depth_m: float = 1e-3


@dataclass(frozen=True, eq=False)
class TaskFrame:
    """A task frame: its name as written and its orientation (frame to world, (3, 3))."""

    name: str
    rotation: FloatArray


WORLD = TaskFrame("world", IDENTITY)


@dataclass(frozen=True)
class AxisCompliance:
    """What COMPLY set on one axis label (X ... RZ of each statement's task frame).

    Attributes:
        stiffness: N/m or N m/rad; 0.0 means force control at zero force.
        damping: N s/m or N m s/rad, or None for the controller's default.
        span: The COMPLY statement that set it.
    """

    stiffness: float
    damping: float | None
    span: Span


NO_COMPLIANCE: tuple[AxisCompliance | None, ...] = (None,) * 6
"""No axis under COMPLY (the start, and after COMPLY NONE)."""


@dataclass(frozen=True, eq=False)
class HeldContact:
    """A contact made by CONTACT and held until a MOVE or another CONTACT.

    Attributes:
        direction_world: Unit vector along which the tool pushes, world, (3,).
        force_n: Magnitude of the force held [N].
        frame: The CONTACT's task frame (WAIT holds the contact in it).
        span: The CONTACT statement.
    """

    direction_world: FloatArray
    force_n: float
    frame: TaskFrame
    span: Span


@dataclass(frozen=True)
class ProcEntry:
    """A defined procedure and the text it was written in (for statement sources)."""

    definition: ast.ProcDef
    source: str


K = TypeVar("K")
V = TypeVar("V")


def frozen_map(items: Mapping[K, V] | None = None) -> Mapping[K, V]:
    """A read-only copy of ``items``."""
    return MappingProxyType(dict(items or {}))


@dataclass(frozen=True)
class CompileState:
    """Everything statements leave behind for the statements after them.

    Attributes:
        default_speed_mps: Speed limit set by the last SPEED statement [m/s].
        compliance: Per axis label X..RZ: the COMPLY in force, or None (full stiffness).
        contact: The contact held, if any.
        contact_released_by: The MOVE or CONTACT that released the last contact.
        names: LET, FRAME and fixture names, keyed by case-folded name.
        procedures: Defined procedures, keyed by case-folded name.
        obstacles: Obstacles in the scene: case-folded name to the OBSTACLE statement.
        called: Case-folded names of procedures called so far.
        statement_count: Motion statements compiled so far (next statement_index).
        segment_count: Segments emitted so far (next segment index).
        force_limit_n: Free-motion force limit set by the last LIMIT FORCE [N], or None.
        orientation_free: ORIENTATION FREE in force: MOVE and WAIT leave the tool's
            orientation to the null space.
        posture: The POSTURE in force, or None.
        robot: The arm the program runs on (:data:`cosmos.robots.ROBOTS`; ROBOT chooses it).
        robot_fixed: The run's arm was chosen outside the program (``--robot``, the REPL's
            session): a ROBOT statement must name it.
        statements: Top-level statements compiled so far (ROBOT must come first).
        tool: The hand on the flange (:class:`cosmos.hand.tool.Tool`'s value; TOOL chooses it).
        objects: The objects declared so far (OBJECT), in order.
        last_frame: The task frame of the last motion statement: a WAIT without a held
            contact holds the springs of COMPLY ... STIFFNESS in it.
    """

    default_speed_mps: float
    compliance: tuple[AxisCompliance | None, ...] = NO_COMPLIANCE
    contact: HeldContact | None = None
    contact_released_by: Span | None = None
    names: Mapping[str, Binding] = field(default_factory=frozen_map)
    procedures: Mapping[str, ProcEntry] = field(default_factory=frozen_map)
    obstacles: Mapping[str, Span] = field(default_factory=frozen_map)
    called: frozenset[str] = frozenset()
    statement_count: int = 0
    segment_count: int = 0
    force_limit_n: float | None = None
    orientation_free: bool = False
    posture: plan.Posture | None = None
    robot: str = DEFAULT_ROBOT.name
    robot_fixed: bool = False
    statements: int = 0
    tool: str = "peg"
    objects: tuple[WorkObject, ...] = ()
    last_frame: TaskFrame = WORLD

    def bind(self, key: str, binding: Binding) -> CompileState:
        """A state with ``key`` bound."""
        return replace(self, names=frozen_map({**self.names, key: binding}))
