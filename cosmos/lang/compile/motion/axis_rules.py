"""The axis rule: an axis takes one job, and the axis setup that follows from it.

:meth:`AxisRules._axes` makes a segment's :class:`~cosmos.lang.compile.motion.axes.Axes`
from the COMPLY in force and the statement's forces; the other methods are the
checks of the axis rule shared by the motion statements.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.compile.motion.axes import ALIGNED_COS, ALL_MOTION, AXIS_NAMES, Axes, vector_text
from cosmos.lang.compile.motion.base import MotionBuilderBase
from cosmos.lang.compile.state import NO_COMPLIANCE, HeldContact, TaskFrame
from cosmos.rotations import readonly


class AxisRules(MotionBuilderBase):
    """The motion builder's axis setups and axis-rule checks."""

    __slots__ = ()

    def _axes(self, forces: dict[int, float], free: set[int]) -> Axes:
        """Axis setup: COMPLY in force, then zero-force axes ``free``, then ``forces``."""
        if not forces and not free and self.state.compliance == NO_COMPLIANCE:
            return ALL_MOTION
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
        return Axes(motion_array, readonly(force), tuple(stiffness), tuple(damping), all(motion))

    def _no_compliance(self, axis: int, what: Callable[[], str], span: Span) -> None:
        compliance = self.state.compliance[axis]
        if compliance is not None:
            raise ProgramError(
                f"{AXIS_NAMES[axis]} is compliant (COMPLY at line {compliance.span.line}) and "
                f"{what()} commands a force along it; an axis takes one job: COMPLY NONE first, "
                "or comply other axes",
                span,
            )

    def _motion_allowed(self, axis: int, what: Callable[[], str], span: Span) -> None:
        compliance = self.state.compliance[axis]
        if compliance is not None and compliance.stiffness == 0:
            raise ProgramError(
                f"{what()} moves along {AXIS_NAMES[axis]}, but {AXIS_NAMES[axis]} is compliant "
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
        projections = (frame.rotation.T @ contact.direction_world).tolist()
        for axis in range(3):
            if abs(projections[axis]) >= ALIGNED_COS:
                return axis, 1 if projections[axis] > 0 else -1
        raise ProgramError(
            f"the contact held along {vector_text(contact.direction_world)} in the world "
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
        return direction.axis.value, direction.sign
