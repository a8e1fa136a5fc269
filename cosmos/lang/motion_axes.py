"""Per-axis setup of a motion segment, and the axis rule.

The diagonal of the seed's selection matrix Omega (motion) and its complement
(force), the force setpoint, stiffness and damping of each task axis
(:class:`_Axes`), made by :meth:`AxisRules._axes`; and the checks of the axis
rule (an axis takes one job) shared by the motion statements.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.motion_builder_base import MotionBuilderBase
from cosmos.lang.rotations import readonly
from cosmos.lang.state import NO_COMPLIANCE, HeldContact, TaskFrame

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


_NO_FORCES: dict[int, float] = {}  # never changed
_NO_FREE: set[int] = set()  # never changed


def _all_motion() -> _Axes:
    """Every axis under motion control (no COMPLY, no force); its arrays are read-only."""
    motion = np.ones(6, dtype=bool)
    motion.flags.writeable = False
    return _Axes(motion, readonly(np.zeros(6)), (None,) * 6, (None,) * 6, True)


_ALL_MOTION = _all_motion()


def _held_since(contact: HeldContact | None) -> str:
    """``"the contact held since line 3"``, for messages."""
    return f"the contact held since line {contact.span.line}" if contact else ""


def _axis_list(axes: list[int] | set[int]) -> str:
    return " ".join(_AXIS_NAMES[i] for i in sorted(axes))


def _vector_text(vector: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.3g}" if abs(v) > 1e-12 else "0" for v in vector) + ")"


class AxisRules(MotionBuilderBase):
    """The motion builder's axis setups and axis-rule checks."""

    __slots__ = ()

    def _axes(self, forces: dict[int, float], free: set[int]) -> _Axes:
        """Axis setup: COMPLY in force, then zero-force axes ``free``, then ``forces``."""
        if not forces and not free and self.state.compliance == NO_COMPLIANCE:
            return _ALL_MOTION
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
        projections = (frame.rotation.T @ contact.direction_world).tolist()
        for axis in range(3):
            if abs(projections[axis]) >= _ALIGNED:
                return axis, 1 if projections[axis] > 0 else -1
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
