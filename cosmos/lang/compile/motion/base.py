"""What a motion builder holds, and how it writes a plan segment.

:class:`MotionBuilderBase` is the root of :class:`cosmos.lang.compile.motion.builder.MotionBuilder`:
its slots (one compilation pass's defaults, evaluator and callbacks; the state of
the statement being built) and :meth:`MotionBuilderBase._add`, which appends one
segment. The other parts of the builder (axes, clause values, the statements)
are subclasses of it.
"""

from __future__ import annotations

from collections.abc import Callable

from cosmos import plan
from cosmos.errors import Span
from cosmos.lang import ast
from cosmos.lang.compile.motion.axes import Axes
from cosmos.lang.compile.motion.clauses import completions_of
from cosmos.lang.compile.state import CompileState, Defaults, HeldContact, TaskFrame
from cosmos.lang.evaluate.evaluator import Evaluator

_ORIENTATION_FREE_KINDS = (plan.SegmentKind.MOVE, plan.SegmentKind.WAIT)
"""ORIENTATION FREE frees these, when every axis is motion-controlled (no contact held)."""

ContactChange = tuple[HeldContact | None, Span | None]
"""What MOVE and CONTACT change in the state: the held contact, and what released the last."""


class MotionBuilderBase:
    """The attributes every part of the motion builder reads, and the segment writer.

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
        completions = completions_of(defaults)
        self._goal_reached = completions.goal_reached
        self._jam_check = completions.jam_check
        self._segments: list[plan.Segment] = []
        self._text_span: Span | None = None
        self._text = ""

    # --------------------------------------------------------------- segments

    def _add(
        self,
        kind: plan.SegmentKind,
        statement: ast.Statement,
        frame: TaskFrame,
        axes: Axes,
        *,
        target: plan.Target | None,
        speed: float | None,
        completion: plan.Completion,
        until: plan.Condition | None,
        timeout: float | None,
        via: tuple[plan.AbsoluteTarget, ...] = (),
        duration: float | None = None,
        jam_check: plan.JamCheck | None = None,
        search: plan.Search | None = None,
    ) -> None:
        span = statement.span
        if span is not self._text_span:  # a statement's segments share its text
            self._text_span = span
            self._text = self.text_of(span)
        segment = plan.Segment(
            index=self.state.segment_count + len(self._segments),
            kind=kind,
            statement_index=self.state.statement_count,
            span=span,
            line=span.line,
            statement=self._text,
            context=self.context,
            frame_name=frame.name,
            frame_rotation=frame.rotation,
            motion_axes=axes.motion,
            force_setpoint=axes.force,
            stiffness=axes.stiffness,
            damping=axes.damping,
            target=target,
            via=via,
            via_radius_m=self.defaults.via_radius_m if via else None,
            speed_limit_mps=speed,
            duration_s=duration,
            completion=completion,
            until=until,
            timeout_s=timeout,
            jam_check=jam_check,
            force_limit_n=self.state.force_limit_n,
            search=search,
            orientation_free=self.state.orientation_free
            and kind in _ORIENTATION_FREE_KINDS
            and all(axes.motion),
            posture=self.state.posture,
        )
        self._segments.append(segment)
