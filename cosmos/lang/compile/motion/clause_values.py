"""The values of a motion statement's clauses, and the warnings about them.

The task frame of ``IN``, positive FORCE, SPEED, TIMEOUT and duration values, the
UNTIL condition, and the warnings a statement's values call for (a timeout too
short for the motion, a force compared with the wrong sign, a move away from a
fixture's surface).
"""

from __future__ import annotations

import math

import numpy as np

from cosmos import plan
from cosmos.capabilities import WRIST_SENSOR
from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.compile.motion.axes import vector_text
from cosmos.lang.compile.motion.base import MotionBuilderBase
from cosmos.lang.compile.motion.clauses import Clauses
from cosmos.lang.compile.motion.conditions import (
    comparisons,
    compile_condition,
    holds_at_start,
    require_gripper,
)
from cosmos.lang.compile.state import WORLD, TaskFrame
from cosmos.lang.evaluate.values import BindingKind, FrameValue, Scalar
from cosmos.osc.landing import IMPACT_MASS_KG, IMPACT_STIFFNESS_N_PER_M, impact_peak_n
from cosmos.rotations import IDENTITY

IN_WORLD: tuple[TaskFrame, float | None, str | None] = (WORLD, None, None)
"""What ``_frame`` gives a statement without IN: the world frame, no duration, no fixture."""

_FIXTURE = BindingKind.FIXTURE


class ClauseValues(MotionBuilderBase):
    """The motion builder's clause values and warnings."""

    __slots__ = ()

    # ---------------------------------------------------------------- values

    def _frame(
        self, clauses: Clauses, keyword: str, *, allow_duration: bool
    ) -> tuple[TaskFrame, float | None, str | None]:
        """(task frame, duration of IN t, fixture named by IN)."""
        expr = clauses.exprs.get(ast.ClauseKind.IN)
        if expr is None:
            return IN_WORLD
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

    def _force(self, clauses: Clauses) -> float:
        expr = clauses.exprs.get(ast.ClauseKind.FORCE)
        assert expr is not None  # the checker requires FORCE where there is no default
        force = self._positive_scalar(expr, units.FORCE, "FORCE")
        if force > 100:
            self.warn(f"FORCE {force:g} N is a lot for the PUMA 560's wrist", expr.span)
        return force

    def _speed(self, clauses: Clauses, default: float | None) -> float:
        expr = clauses.exprs.get(ast.ClauseKind.SPEED)
        if expr is None:
            assert default is not None
            return default
        return self._positive_scalar(expr, units.SPEED, "SPEED")

    def _timeout(self, clauses: Clauses) -> float | None:
        expr = clauses.exprs.get(ast.ClauseKind.TIMEOUT)
        return None if expr is None else self._positive_scalar(expr, units.TIME, "TIMEOUT")

    def _until(
        self,
        clauses: Clauses,
        frame: TaskFrame,
        *,
        force_expected: bool,
        heading_world: plan.FloatArray | None = None,
    ) -> plan.Condition | None:
        if clauses.until is None:
            return None
        condition = compile_condition(clauses.until.condition, frame, self.evaluator, self.text_of)
        require_gripper(condition, self.state.tool)
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
                    f"this move pushes along {vector_text(heading)} when it meets something, so "
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
        clauses: Clauses,
    ) -> None:
        if timeout is None:
            return
        needed = duration
        if needed is None and distance is not None and speed:
            needed = distance / speed
        if needed is not None and timeout < needed:
            self.warn(
                f"TIMEOUT {timeout:g} s is shorter than the {needed:.3g} s this motion needs",
                clauses.span_of(ast.ClauseKind.TIMEOUT),
            )

    def _warn_impact(self, speed: float, clauses: Clauses, keyword: str) -> None:
        """Warn where a CONTACT's or INSERT's SPEED would meet unforeseen steel over the sensor's rating.

        The landing slows the approach before a surface the workcell model knows (cosmos.osc.landing);
        one it does not (a moved fixture, an object) is met at the SPEED, and the steel's impact peaks
        at ``v sqrt(k_i Lambda_n)`` whatever the force loop does after it.
        """
        mass = IMPACT_MASS_KG.get(self.state.robot, max(IMPACT_MASS_KG.values()))
        peak, rating = impact_peak_n(speed, mass), WRIST_SENSOR.force_n
        if peak > rating:
            safe = rating / impact_peak_n(1.0, mass)
            self.warn(
                f"{keyword} SPEED {speed * 1e3:g} mm/s would meet steel the workcell model does not foresee "
                f"(a moved fixture, an object) at about {peak:.0f} N "
                f"(v sqrt(k m): {IMPACT_STIFFNESS_N_PER_M / 1e3:g} kN/m, {mass:g} kg along the approach), "
                f"over the wrist sensor's rating of {rating:g} N; "
                f"at most {safe * 1e3:.0f} mm/s stays under it",
                clauses.span_of(ast.ClauseKind.SPEED),
            )

    def _warn_away_from_fixture(self, direction: ast.Direction, fixture: str | None, keyword: str) -> None:
        if fixture is not None and direction.axis is ast.Axis.Z and direction.sign < 0:
            self.warn(
                f"fixture frames point +Z into their surface, so {keyword} -Z IN {fixture} "
                f"moves away from it; did you mean +Z IN {fixture}, or DOWN?",
                direction.span,
            )
