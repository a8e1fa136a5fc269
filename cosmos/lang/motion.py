"""Motion statements (MOVE, CONTACT, SLIDE, INSERT, WAIT) to segments.

Each statement picks its task frame (``IN frame``, else the world; WAIT uses the
held contact's frame) and fills in, per task axis, the diagonal of the seed's
selection matrix Omega (motion) and its complement (force), the force setpoint,
stiffness and damping, from three sources:

- COMPLY in force: zero stiffness = force control at 0 N, else a spring;
- the held contact: its axis stays force-controlled at its force;
- the statement: CONTACT's and INSERT's force axis, INSERT's compliant axes.

The axis rule (docs/language.md, "One job per axis"): an axis that carries a
commanded force (the contact's, INSERT's) may not also be under COMPLY, and the
direction a statement moves along (SLIDE, the CONTACT approach) may be neither
force-controlled nor compliant at zero stiffness. Breaking it is an error.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.conditions import comparisons, compile_condition, holds_at_start
from cosmos.lang.frozen_new import quick
from cosmos.lang.rotations import IDENTITY, readonly, readonly_of, signed_column
from cosmos.lang.state import WORLD, AxisCompliance, CompileState, Defaults, HeldContact, TaskFrame
from cosmos.lang.values import BindingKind, Evaluator, FrameValue, Scalar

_ALIGNED = math.cos(math.radians(1.0))
"""A contact direction within 1 degree of a task axis counts as along it."""

_AXIS_NAMES = tuple(axis.name for axis in ast.Axis)


@dataclass(frozen=True)
class _Axes:
    """Per-axis setup of a segment in its task frame."""

    motion: np.ndarray  # (6,) bool
    force: np.ndarray  # (6,) float
    stiffness: tuple[float | None, ...]
    damping: tuple[float | None, ...]
    all_motion: bool  # motion.all()


@dataclass(slots=True)
class _Clauses:
    """A statement's clauses by keyword (the checker has refused duplicates).

    ``exprs`` holds the value of each value clause by its kind (``.get``: None where absent).
    """

    given: tuple[ast.Clause, ...]
    exprs: dict[ast.ClauseKind, ast.Expr]
    via: ast.ViaClause | None
    until: ast.UntilClause | None
    comply: ast.ComplyClause | None

    def span_of(self, kind: ast.ClauseKind) -> Span:
        """The span of the value clause of ``kind`` (keyword and value), which is given."""
        return next(c.span for c in self.given if type(c) is _VALUE_CLAUSE and c.kind is kind)


def _clauses_of(clauses: tuple[ast.Clause, ...]) -> _Clauses:
    """A statement's clauses sorted by keyword (one shared, never changed, value for none)."""
    if not clauses:
        return _NO_CLAUSES
    exprs: dict[ast.ClauseKind, ast.Expr] = {}
    found = _new(_Clauses)  # the fields set here, without the dataclass __init__
    found.given = clauses
    found.exprs = exprs
    found.via = found.until = found.comply = None
    for clause in clauses:
        kind = type(clause)
        if kind is _VALUE_CLAUSE:
            exprs[clause.kind] = clause.value  # type: ignore[union-attr]
        elif kind is _VIA_CLAUSE:
            found.via = clause  # type: ignore[assignment]
        elif kind is _UNTIL_CLAUSE:
            found.until = clause  # type: ignore[assignment]
        else:
            found.comply = clause  # type: ignore[assignment]
    return found


_NO_CLAUSES = _Clauses((), {}, None, None, None)
"""The clauses of a statement without any (its dictionaries stay empty)."""
_VALUE_CLAUSE = ast.ValueClause
_VIA_CLAUSE = ast.ViaClause
_UNTIL_CLAUSE = ast.UntilClause


_NO_COMPLIANCE = (None,) * 6
_IN_WORLD: tuple[TaskFrame, float | None, str | None] = (WORLD, None, None)
"""What ``_frame`` gives a statement without IN: the world frame, no duration, no fixture."""
_NO_FORCES: dict[int, float] = {}  # never changed
_NO_FREE: set[int] = set()  # never changed
_new = object.__new__


def _all_motion() -> _Axes:
    """Every axis under motion control (no COMPLY, no force); its arrays are read-only."""
    motion = np.ones(6, dtype=bool)
    motion.flags.writeable = False
    return _Axes(motion, readonly(np.zeros(6)), (None,) * 6, (None,) * 6, True)


_ALL_MOTION = _all_motion()

_set_attribute = object.__setattr__
_absolute_target = quick(plan.AbsoluteTarget)


def _relative_target(offset_world: plan.FloatArray) -> plan.RelativeTarget:
    """``plan.RelativeTarget(offset_world)`` without the frozen ``__setattr__``."""
    target = _new(plan.RelativeTarget)
    target.__dict__["offset_world"] = offset_world
    return target


_QUICK_SEGMENT = tuple(plan.Segment.__dataclass_fields__) == (
    "index", "kind", "statement_index", "span", "line", "statement", "context", "frame_name",
    "frame_rotation", "motion_axes", "force_setpoint", "stiffness", "damping", "target", "via",
    "via_radius_m", "speed_limit_mps", "duration_s", "completion", "until", "timeout_s", "jam_check",
) and not hasattr(plan.Segment, "__post_init__")  # fmt: skip
"""Whether :meth:`MotionBuilder._add` fills a Segment's fields itself (they are the ones it knows)."""

# Enum members read in every statement, looked up once (a member lookup on an
# Enum class costs about 0.3 us in Python 3.11).
_SPEED = ast.ClauseKind.SPEED
_BY = ast.ClauseKind.BY
_FORCE = ast.ClauseKind.FORCE
_DEPTH = ast.ClauseKind.DEPTH
_IN = ast.ClauseKind.IN
_TIMEOUT = ast.ClauseKind.TIMEOUT
_MOVE_TO = ast.MoveMode.TO
_MOVE = plan.SegmentKind.MOVE
_CONTACT_APPROACH = plan.SegmentKind.CONTACT_APPROACH
_CONTACT_HOLD = plan.SegmentKind.CONTACT_HOLD
_SLIDE = plan.SegmentKind.SLIDE
_INSERT = plan.SegmentKind.INSERT
_WAIT = plan.SegmentKind.WAIT
_FIXTURE = BindingKind.FIXTURE

_AXES_SEEN: dict[tuple[object, ...], _Axes] = {}
"""Axis setups made so far, by (COMPLY settings, forces, free axes)."""


_CONTACT_AXES: dict[tuple[bytes, bytes], tuple[int, int]] = {}
"""(axis, sign) of held contacts, by (task frame rotation, contact direction) bytes."""

_NORMS: dict[bytes, float] = {}
"""Euclidean norms of offsets, by the offset's bytes."""

_contact_touch = quick(plan.ContactTouch)
_force_settled = quick(plan.ForceSettled)
_depth_reached = quick(plan.DepthReached)
_new_held_contact = quick(HeldContact)


_COMPLIANCE_KEYS: dict[int, tuple[tuple[object, ...], tuple[object, ...]]] = {}
"""By id of a state's COMPLY tuple: (that tuple, kept alive; its settings without spans)."""


def _compliance_key(compliance: tuple[AxisCompliance | None, ...]) -> tuple[object, ...]:
    """The COMPLY settings as (stiffness, damping) per axis: what an axis setup depends on.

    Two COMPLY statements with equal numbers give equal keys (their spans differ).
    """
    found = _COMPLIANCE_KEYS.get(id(compliance))
    if found is not None and found[0] is compliance:
        return found[1]
    key = tuple(None if c is None else (c.stiffness, c.damping) for c in compliance)
    if len(_COMPLIANCE_KEYS) >= 1024:
        _COMPLIANCE_KEYS.clear()
    _COMPLIANCE_KEYS[id(compliance)] = (compliance, key)
    return key


def _norm(offset: plan.FloatArray) -> float:
    """``float(np.linalg.norm(offset))``, remembered for equal offsets."""
    key = offset.tobytes()
    norm = _NORMS.get(key)
    if norm is None:
        norm = float(np.linalg.norm(offset))
        if len(_NORMS) < 4096:
            _NORMS[key] = norm
    return norm


def _held_since(contact: HeldContact | None) -> str:
    """``"the contact held since line 3"``, for messages."""
    return f"the contact held since line {contact.span.line}" if contact else ""


def _axis_list(axes: list[int] | set[int]) -> str:
    return " ".join(_AXIS_NAMES[i] for i in sorted(axes))


def _vector_text(vector: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.3g}" if abs(v) > 1e-12 else "0" for v in vector) + ")"


@dataclass(frozen=True, eq=False)
class _Completions:
    """The immutable plan values one ``Defaults`` gives every segment that needs them."""

    goal_reached: plan.GoalReached
    jam_check: plan.JamCheck


_COMPLETIONS: dict[int, tuple[Defaults, _Completions]] = {}
"""By id of a Defaults (kept alive here): its completions, made once."""


def _completions(defaults: Defaults) -> _Completions:
    """The goal tolerances and jam check of ``defaults`` (a Defaults is hashed slowly: by id)."""
    found = _COMPLETIONS.get(id(defaults))
    if found is not None and found[0] is defaults:
        return found[1]
    made = _Completions(
        plan.GoalReached(
            position_tolerance_m=defaults.position_tolerance_m,
            orientation_tolerance_rad=defaults.orientation_tolerance_rad,
            speed_tolerance_mps=defaults.rest_speed_mps,
        ),
        plan.JamCheck(
            stall_speed_mps=defaults.jam_stall_speed_mps,
            stall_time_s=defaults.jam_stall_time_s,
        ),
    )
    if len(_COMPLETIONS) >= 64:
        _COMPLETIONS.clear()
    _COMPLETIONS[id(defaults)] = (defaults, made)
    return made


_ContactChange = tuple[HeldContact | None, Span | None]
"""What MOVE and CONTACT change in the state: the held contact, and what released the last.

A plain tuple: a NamedTuple is made by a Python-level ``__new__``, once per statement.
"""


class MotionBuilder:
    """Builds the segments of motion statements, one statement per :meth:`build`.

    One builder serves a whole compilation pass: ``build`` points it at each
    statement's state in turn.

    Args:
        defaults: Values used where the program gives none.
        evaluator: Evaluates expressions against the names of the statement's state.
        text_of: Source text of a span.
        warn: Records a warning.
    """

    __slots__ = (
        "defaults",
        "state",
        "evaluator",
        "text_of",
        "warn",
        "context",
        "_goal_reached",
        "_jam_check",
        "_segments",
        "_text_span",
        "_text",
    )

    def __init__(
        self,
        defaults: Defaults,
        evaluator: Evaluator,
        text_of: Callable[[Span], str],
        warn: Callable[[str, Span], None],
    ):
        self.defaults = defaults
        self.evaluator = evaluator
        self.text_of = text_of
        self.warn = warn
        self.state: CompileState
        self.context = ""
        completions = _completions(defaults)
        self._goal_reached = completions.goal_reached
        self._jam_check = completions.jam_check
        self._segments: list[plan.Segment] = []
        self._text_span: Span | None = None
        self._text = ""

    def build(
        self,
        statement: ast.Move | ast.Contact | ast.Slide | ast.Insert | ast.Wait,
        state: CompileState,
        context: str,
    ) -> tuple[list[plan.Segment], CompileState]:
        """The statement's segments and the state after it.

        Args:
            statement: The motion statement.
            state: The compile state before it (the evaluator reads its names).
            context: Where an expanded statement came from (see ``Segment.context``).

        Raises:
            ProgramError: A unit, value or axis error, pointing at its cause.
        """
        self.state = state
        self.context = context
        segments: list[plan.Segment] = []
        self._segments = segments
        change: _ContactChange | None = _BUILDERS[type(statement)](self, statement)
        statements = state.statement_count + 1
        if change is None:
            state = state.with_counts(statements, state.segment_count + len(segments))
        else:  # one new state for both changes
            contact, released_by = change
            state = state.with_contact_and_counts(
                contact, released_by, statements, state.segment_count + len(segments)
            )
        return segments, state

    # ------------------------------------------------------------ statements

    def _move(self, statement: ast.Move) -> _ContactChange:
        clauses = _clauses_of(statement.clauses)
        frame, duration, _ = (
            self._frame(clauses, "MOVE", allow_duration=True) if _IN in clauses.exprs else _IN_WORLD
        )
        speed: float | None = None
        if _SPEED in clauses.exprs:
            if duration is not None:
                raise ProgramError(
                    "give MOVE a SPEED or a duration (IN 2 s), not both",
                    clauses.span_of(_SPEED),
                )
            speed = self._speed(clauses, None)
        elif duration is None:
            speed = self.state.default_speed_mps
        target: plan.Target
        distance: float | None = None
        if statement.mode is _MOVE_TO:
            goal = self.evaluator.expect_position(statement.target, "MOVE TO")
            target = _absolute_target(goal.position, goal.rotation)
        else:
            if isinstance(statement.target, ast.Pose):
                raise ProgramError(
                    "MOVE BY takes an offset (x, y, z); to turn the tool, MOVE TO a pose with RPY",
                    statement.target.span,
                )
            offset = self.evaluator.expect_vector3(statement.target, units.LENGTH, "MOVE BY")
            distance = _norm(offset)
            if distance == 0:
                self.warn("MOVE BY (0, 0, 0) goes nowhere", statement.target.span)
            if frame.rotation is IDENTITY:  # the world's axes: the offset as it is (read-only)
                target = _relative_target(offset)
            else:
                target = _relative_target(readonly(frame.rotation @ offset))
        via: tuple[plan.AbsoluteTarget, ...] = ()
        if clauses.via is not None:
            via = tuple(
                _absolute_target(p.position, p.rotation)
                for p in (self.evaluator.expect_position(point, "VIA") for point in clauses.via.points)
            )
        axes = self._axes(_NO_FORCES, _NO_FREE)
        floating = (
            [] if axes is _ALL_MOTION else [i for i, moved in enumerate(axes.motion.tolist()) if not moved]
        )
        if floating:
            comply = self.state.compliance[floating[0]]
            assert comply is not None
            self.warn(
                f"{_axis_list(floating)} compliant (COMPLY at line {comply.span.line}), so this "
                "MOVE does not control them; COMPLY NONE first to move on every axis",
                statement.span,
            )
        timeout = self._timeout(clauses)
        if timeout is not None:
            self._warn_timeout(timeout, distance, speed, duration, clauses)
        self._add(
            _MOVE,
            statement,
            frame,
            axes,
            target=target,
            via=via,
            speed=speed,
            duration=duration,
            completion=self._goal_reached,
            until=None
            if clauses.until is None
            else self._until(
                clauses,
                frame,
                force_expected=self.state.contact is not None,
                heading_world=target.offset_world if isinstance(target, plan.RelativeTarget) else None,
            ),
            timeout=timeout,
        )
        released = statement.span if self.state.contact is not None else self.state.contact_released_by
        return None, released

    def _contact(self, statement: ast.Contact) -> _ContactChange:
        clauses = _clauses_of(statement.clauses)
        frame, _, fixture = (
            self._frame(clauses, "CONTACT", allow_duration=False) if _IN in clauses.exprs else _IN_WORLD
        )
        axis, sign = self._translation(statement.direction, "CONTACT")
        direction_world, direction = signed_column(frame.rotation, axis, sign)
        force = self._force(clauses)
        speed = self._speed(clauses, self.defaults.contact_speed_mps)
        self._no_compliance(axis, lambda: f"CONTACT {statement.direction.text}", statement.direction.span)
        self._warn_away_from_fixture(statement.direction, fixture, "CONTACT")
        timeout = self._timeout(clauses)
        until = (
            None
            if clauses.until is None
            else self._until(clauses, frame, force_expected=self.state.contact is not None)
        )
        travel = self.defaults.contact_max_travel_m
        self._add(
            _CONTACT_APPROACH,
            statement,
            frame,
            self._axes(_NO_FORCES, _NO_FREE),
            target=_relative_target(readonly_of(tuple([d * travel for d in direction]))),
            speed=speed,
            completion=_contact_touch(
                direction_world, min(self.defaults.touch_threshold_n, 0.5 * force), travel
            ),
            until=until,
            timeout=timeout,
        )
        self._add(
            _CONTACT_HOLD,
            statement,
            frame,
            self._axes({axis: sign * force}, _NO_FREE),
            target=None,
            speed=speed,
            completion=_force_settled(
                max(self.defaults.settle_tolerance_n, 0.1 * force),
                self.defaults.settle_time_s,
                self.defaults.settle_max_time_s,
            ),
            until=until,
            timeout=timeout,
        )
        contact = _new_held_contact(direction_world, force, frame, statement.span)
        released = statement.span if self.state.contact is not None else self.state.contact_released_by
        return contact, released

    def _slide(self, statement: ast.Slide) -> None:  # keeps the contact: no change
        clauses = _clauses_of(statement.clauses)
        contact = self._held_contact("SLIDE", statement.span)
        frame, _, _ = (
            self._frame(clauses, "SLIDE", allow_duration=False) if _IN in clauses.exprs else _IN_WORLD
        )
        axis, sign = self._translation(statement.direction, "SLIDE")
        contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
        if axis == contact_axis:
            raise ProgramError(
                f"SLIDE {statement.direction.text} moves along the contact's own axis "
                f"({_AXIS_NAMES[axis]}, CONTACT at line {contact.span.line}); slide across the "
                "surface, or MOVE to leave it",
                statement.direction.span,
            )
        self._motion_allowed(axis, lambda: f"SLIDE {statement.direction.text}", statement.direction.span)
        self._no_compliance(contact_axis, lambda: _held_since(contact), statement.span)
        by = clauses.exprs.get(_BY)
        assert by is not None  # the checker requires BY
        distance = self._positive_scalar(by, units.LENGTH, "BY")
        force = self._force(clauses) if _FORCE in clauses.exprs else contact.force_n
        speed = self._speed(clauses, self.state.default_speed_mps)
        timeout = self._timeout(clauses)
        if timeout is not None:
            self._warn_timeout(timeout, distance, speed, None, clauses)
        offset = tuple([c * distance for c in signed_column(frame.rotation, axis, sign)[1]])
        self._add(
            _SLIDE,
            statement,
            frame,
            self._axes({contact_axis: contact_sign * force}, _NO_FREE),
            target=_relative_target(readonly_of(offset)),
            speed=speed,
            completion=self._goal_reached,
            until=None if clauses.until is None else self._until(clauses, frame, force_expected=True),
            timeout=timeout,
        )

    def _insert(self, statement: ast.Insert) -> None:
        clauses = _clauses_of(statement.clauses)
        frame, _, fixture = (
            self._frame(clauses, "INSERT", allow_duration=False) if _IN in clauses.exprs else _IN_WORLD
        )
        axis, sign = self._translation(statement.direction, "INSERT")
        direction_world = signed_column(frame.rotation, axis, sign)[0]
        depth_expr = clauses.exprs.get(_DEPTH)
        assert depth_expr is not None  # the checker requires DEPTH
        depth = self._positive_scalar(depth_expr, units.LENGTH, "DEPTH")
        force = self._force(clauses)
        contact = self.state.contact
        forces = {axis: sign * force}
        contact_axis = None
        if contact is not None:
            contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
            if contact_axis != axis:
                forces[contact_axis] = contact_sign * contact.force_n

        def what() -> str:  # for messages only: built when one is given
            return f"INSERT {statement.direction.text}"

        if clauses.comply is not None:
            free = {ref.axis._value_ for ref in clauses.comply.axes}
            for ref in clauses.comply.axes:
                if ref.axis._value_ in forces:
                    because = (
                        f"{what()} pushes along it"
                        if ref.axis._value_ == axis
                        else f"it carries {_held_since(contact)}"
                    )
                    raise ProgramError(
                        f"{ref.axis.name} cannot be compliant here: {because}; leave it out of COMPLY",
                        ref.span,
                    )
        else:
            lateral = [i for i in range(3) if i != axis]
            free = {i for i in lateral + [i + 3 for i in lateral] if i != contact_axis}
        self._no_compliance(axis, what, statement.direction.span)
        if contact_axis is not None and contact_axis != axis:
            self._no_compliance(contact_axis, lambda: _held_since(contact), statement.span)
        if contact is None:
            self.warn(
                f"no contact is held, so {what()} pushes {force:g} N into free space (at up to "
                f"{self._speed(clauses, self.defaults.insert_speed_mps) * 1000:g} mm/s) until it "
                "meets something; make a CONTACT first",
                statement.span,
            )
        self._warn_away_from_fixture(statement.direction, fixture, "INSERT")
        self._add(
            _INSERT,
            statement,
            frame,
            self._axes(forces, free),
            target=None,
            speed=self._speed(clauses, self.defaults.insert_speed_mps),
            completion=_depth_reached(direction_world, depth),
            until=None if clauses.until is None else self._until(clauses, frame, force_expected=True),
            timeout=self._timeout(clauses),
            jam_check=self._jam_check,
        )

    def _wait(self, statement: ast.Wait) -> None:
        clauses = _clauses_of(statement.clauses)
        duration = None
        if statement.duration is not None:
            duration = self._positive_scalar(statement.duration, units.TIME, "WAIT")
        contact = self.state.contact
        frame = WORLD if contact is None else contact.frame
        forces: dict[int, float] = {}
        if contact is not None:
            contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
            self._no_compliance(contact_axis, lambda: _held_since(contact), statement.span)
            forces[contact_axis] = contact_sign * contact.force_n
        axes = self._axes(forces, _NO_FREE)
        until = (
            None if clauses.until is None else self._until(clauses, frame, force_expected=contact is not None)
        )
        movable = not axes.all_motion or any(c is not None and c.stiffness > 0 for c in self.state.compliance)
        if until is not None and not movable:
            for comparison in comparisons(until):
                if comparison.quantity is plan.Quantity.DISTANCE:
                    raise ProgramError(
                        "WAIT holds the tool still (no contact held, nothing compliant), so "
                        "DISTANCE stays 0 and cannot be sensed here",
                        comparison.span,
                    )
        timeout = self._timeout(clauses)
        if duration is None and timeout is None:
            self.warn("WAIT UNTIL without TIMEOUT may wait for ever; add TIMEOUT", statement.span)
        self._add(
            _WAIT,
            statement,
            frame,
            axes,
            target=None,
            speed=self.defaults.contact_speed_mps if forces else None,
            completion=plan.UntilOnly() if duration is None else plan.Elapsed(duration),
            until=until,
            timeout=timeout,
        )

    # ------------------------------------------------------------------ axes

    def _axes(self, forces: dict[int, float], free: set[int]) -> _Axes:
        """Axis setup: COMPLY in force, then zero-force axes ``free``, then ``forces``.

        Equal setups share one (read-only) value: a program repeats a few of them.
        """
        compliance = self.state.compliance
        if not forces and not free and compliance == _NO_COMPLIANCE:
            return _ALL_MOTION
        key = (_compliance_key(compliance), tuple(forces.items()), tuple(free))
        axes = _AXES_SEEN.get(key)
        if axes is None:
            axes = self._new_axes(forces, free)
            if len(_AXES_SEEN) < 1024:
                _AXES_SEEN[key] = axes
        return axes

    def _new_axes(self, forces: dict[int, float], free: set[int]) -> _Axes:
        motion = [True] * 6
        force = [0.0] * 6
        stiffness: list[float | None] = [None] * 6
        damping: list[float | None] = [None] * 6
        for i, compliance in enumerate(self.state.compliance):
            if compliance is None:
                continue
            damping[i] = compliance.damping
            stiffness[i] = compliance.stiffness
            if compliance.stiffness == 0:
                motion[i] = False
        for i in free:
            motion[i] = False
            stiffness[i] = 0.0
        for i, value in forces.items():
            motion[i] = False
            force[i] = value
            stiffness[i] = 0.0
        motion_array = np.array(motion, dtype=bool)
        motion_array.flags.writeable = False
        return _Axes(motion_array, readonly(force), tuple(stiffness), tuple(damping), all(motion))

    def _no_compliance(self, axis: int, what: Callable[[], str], span: Span) -> None:
        compliance = self.state.compliance[axis]
        if compliance is not None:
            raise ProgramError(
                f"{_AXIS_NAMES[axis]} is compliant (COMPLY at line {compliance.span.line}) and "
                f"{what()} commands a force along it; an axis takes one job: COMPLY NONE first, "
                "or comply other axes",
                span,
            )

    def _motion_allowed(self, axis: int, what: Callable[[], str], span: Span) -> None:
        compliance = self.state.compliance[axis]
        if compliance is not None and compliance.stiffness == 0:
            raise ProgramError(
                f"{what()} moves along {_AXIS_NAMES[axis]}, but {_AXIS_NAMES[axis]} is compliant "
                f"with zero stiffness (COMPLY at line {compliance.span.line}), so it cannot be "
                "moved; COMPLY NONE first",
                span,
            )

    def _held_contact(self, keyword: str, span: Span) -> HeldContact:
        contact = self.state.contact
        if contact is not None:
            return contact
        released = self.state.contact_released_by
        why = f"; the contact was released at line {released.line}" if released is not None else ""
        raise ProgramError(
            f"{keyword} needs a held contact: make one with CONTACT first "
            f"(e.g. CONTACT DOWN FORCE 10 N){why}",
            span,
        )

    def _contact_axis(self, contact: HeldContact, frame: TaskFrame, span: Span) -> tuple[int, int]:
        """The task axis (0..2) and sign along which the contact pushes."""
        key = (frame.rotation.tobytes(), contact.direction_world.tobytes())
        found = _CONTACT_AXES.get(key)
        if found is not None:
            return found
        projections = (frame.rotation.T @ contact.direction_world).tolist()
        for axis in range(3):
            if abs(projections[axis]) >= _ALIGNED:
                found = axis, 1 if projections[axis] > 0 else -1
                if len(_CONTACT_AXES) < 1024:
                    _CONTACT_AXES[key] = found
                return found
        raise ProgramError(
            f"the contact held along {_vector_text(contact.direction_world)} in the world "
            f"(CONTACT at line {contact.span.line}) is not along an axis of frame "
            f"'{frame.name}'; give this statement IN {contact.frame.name}",
            span,
        )

    def _translation(self, direction: ast.Direction, keyword: str) -> tuple[int, int]:
        if direction.axis.is_rotation:
            raise ProgramError(
                f"{keyword} needs a translation direction (+X -X +Y -Y +Z -Z, UP or DOWN), "
                f"not {direction.axis.name}",
                direction.span,
            )
        return direction.axis._value_, direction.sign

    # ---------------------------------------------------------------- values

    def _frame(
        self, clauses: _Clauses, keyword: str, *, allow_duration: bool
    ) -> tuple[TaskFrame, float | None, str | None]:
        """(task frame, duration of IN t, fixture named by IN)."""
        expr = clauses.exprs.get(_IN)
        if expr is None:
            return _IN_WORLD
        value = self.evaluator.evaluate(expr)
        if isinstance(value, FrameValue):
            rotation = IDENTITY if value.rotation is None else value.rotation
            fixture = None
            if isinstance(expr, ast.Name):
                binding = self.evaluator.names.get(expr.name.casefold())
                if binding is not None and binding.kind is _FIXTURE:
                    fixture = expr.name
            return TaskFrame(self.text_of(expr.span), rotation), None, fixture
        if isinstance(value, Scalar) and allow_duration:
            return WORLD, self._positive_scalar(expr, units.TIME, "IN"), None
        if allow_duration:
            also = " or a duration, like IN 2 s"
        elif isinstance(value, Scalar):
            also = " (only MOVE takes a duration)"
        else:
            also = ""
        raise ProgramError(
            f"IN takes a frame, like IN hole{also}; {self.text_of(expr.span)} is not one", expr.span
        )

    def _positive_scalar(self, expr: ast.Expr, dim: units.Dim, what: str) -> float:
        value = self.evaluator.expect_scalar(expr, dim, what)
        if not 0.0 < value < math.inf:  # NaN and inf fail too
            raise ProgramError(
                f"{what} must be positive, not {self.text_of(expr.span)}"
                + ("; the direction gives the sign" if what in ("FORCE", "BY", "DEPTH") else ""),
                expr.span,
            )
        return value

    def _force(self, clauses: _Clauses) -> float:
        expr = clauses.exprs.get(_FORCE)
        assert expr is not None  # the checker requires FORCE where there is no default
        force = self._positive_scalar(expr, units.FORCE, "FORCE")
        if force > 100:
            self.warn(f"FORCE {force:g} N is a lot for the PUMA 560's wrist", expr.span)
        return force

    def _speed(self, clauses: _Clauses, default: float | None) -> float:
        expr = clauses.exprs.get(_SPEED)
        if expr is None:
            assert default is not None
            return default
        return self._positive_scalar(expr, units.SPEED, "SPEED")

    def _timeout(self, clauses: _Clauses) -> float | None:
        expr = clauses.exprs.get(_TIMEOUT)
        return None if expr is None else self._positive_scalar(expr, units.TIME, "TIMEOUT")

    def _until(
        self,
        clauses: _Clauses,
        frame: TaskFrame,
        *,
        force_expected: bool,
        heading_world: plan.FloatArray | None = None,
    ) -> plan.Condition | None:
        if clauses.until is None:
            return None
        condition = compile_condition(clauses.until.condition, frame, self.evaluator, self.text_of)
        if heading_world is not None:
            self._warn_force_sign(condition, heading_world)
        early = holds_at_start(condition, force_expected)
        if early is not None:
            self.warn(
                f"UNTIL {early.text} already holds when the statement starts, so it stops at once",
                early.span,
            )
        return condition

    # --------------------------------------------------------------- warnings

    def _warn_force_sign(self, condition: plan.Condition, heading_world: plan.FloatArray) -> None:
        """A force component compared the wrong way round for what the move will run into.

        Moving along h, the tool pushes whatever it meets along h: the force it applies
        grows along h. ``FORCE Z > 3 N`` on a move toward -Z can then never hold.
        """
        norm = float(np.linalg.norm(heading_world))
        if norm == 0.0:
            return
        heading = heading_world / norm
        for comparison in comparisons(condition):
            direction = comparison.direction_world
            if comparison.quantity is not plan.Quantity.FORCE_ALONG or direction is None:
                continue
            grows = float(direction @ heading)  # > 0: the compared force grows on contact
            rising = comparison.op in (plan.CompareOp.GT, plan.CompareOp.GE)
            if abs(grows) > 0.7 and (grows < 0) == rising and (comparison.value > 0) == rising:
                self.warn(
                    f"this move pushes along {_vector_text(heading)} when it meets something, so "
                    f"the force along that way grows but {comparison.text} needs the opposite sign; "
                    "see 'Sign of forces' in the language reference",
                    comparison.span,
                )

    def _warn_timeout(
        self,
        timeout: float | None,
        distance: float | None,
        speed: float | None,
        duration: float | None,
        clauses: _Clauses,
    ) -> None:
        if timeout is None:
            return
        needed = duration
        if needed is None and distance is not None and speed:
            needed = distance / speed
        if needed is not None and timeout < needed:
            self.warn(
                f"TIMEOUT {timeout:g} s is shorter than the {needed:.3g} s this motion needs",
                clauses.span_of(_TIMEOUT),
            )

    def _warn_away_from_fixture(self, direction: ast.Direction, fixture: str | None, keyword: str) -> None:
        if fixture is not None and direction.axis is ast.Axis.Z and direction.sign < 0:
            self.warn(
                f"fixture frames point +Z into their surface, so {keyword} -Z IN {fixture} "
                f"moves away from it; did you mean +Z IN {fixture}, or DOWN?",
                direction.span,
            )

    # --------------------------------------------------------------- segments

    def _add(
        self,
        kind: plan.SegmentKind,
        statement: ast.Statement,
        frame: TaskFrame,
        axes: _Axes,
        *,
        target: plan.Target | None,
        speed: float | None,
        completion: plan.Completion,
        until: plan.Condition | None,
        timeout: float | None,
        via: tuple[plan.AbsoluteTarget, ...] = (),
        duration: float | None = None,
        jam_check: plan.JamCheck | None = None,
    ) -> None:
        span = statement.span
        if span is not self._text_span:  # a statement's segments share its text
            self._text_span = span
            self._text = self.text_of(span)
        fields = {
            "index": self.state.segment_count + len(self._segments),
            "kind": kind,
            "statement_index": self.state.statement_count,
            "span": span,
            "line": span.line,
            "statement": self._text,
            "context": self.context,
            "frame_name": frame.name,
            "frame_rotation": frame.rotation,
            "motion_axes": axes.motion,
            "force_setpoint": axes.force,
            "stiffness": axes.stiffness,
            "damping": axes.damping,
            "target": target,
            "via": via,
            "via_radius_m": self.defaults.via_radius_m if via else None,
            "speed_limit_mps": speed,
            "duration_s": duration,
            "completion": completion,
            "until": until,
            "timeout_s": timeout,
            "jam_check": jam_check,
        }
        if _QUICK_SEGMENT:  # what Segment's __init__ makes, without its frozen __setattr__s
            segment = _new(plan.Segment)
            _set_attribute(segment, "__dict__", fields)  # the new dict itself, not a copy
        else:
            segment = plan.Segment(**fields)  # type: ignore[arg-type]
        self._segments.append(segment)


_BUILDERS: dict[type, Callable[[MotionBuilder, Any], _ContactChange | None]] = {
    ast.Move: MotionBuilder._move,
    ast.Contact: MotionBuilder._contact,
    ast.Slide: MotionBuilder._slide,
    ast.Insert: MotionBuilder._insert,
    ast.Wait: MotionBuilder._wait,
}
"""The builder of each motion statement type; those that change the held contact say how."""
