"""The session's names in words: frames, LET values, procedures and obstacles.

Used to echo a definition when it is typed, for ``:frames``, and by the
completer and highlighter (which names exist).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from cosmos.lang import CompileState, units
from cosmos.lang.evaluate.values import Binding, BindingKind, FrameValue, Scalar, Vec
from cosmos.repl.status import format_pose, format_vector

_SI_SYMBOLS = {
    units.LENGTH: "m",
    units.TIME: "s",
    units.ANGLE: "rad",
    units.FORCE: "N",
    units.TORQUE: "N m",
    units.SPEED: "m/s",
    units.ANGULAR_SPEED: "rad/s",
    units.STIFFNESS: "N/m",
    units.ROTATIONAL_STIFFNESS: "N m/rad",
    units.DAMPING: "N s/m",
    units.ROTATIONAL_DAMPING: "N m s/rad",
}


def _unit(dim: units.Dim | None) -> str:
    if dim is None or dim == units.DIMENSIONLESS:
        return ""
    symbol = _SI_SYMBOLS.get(dim)
    return f" {symbol}" if symbol else f" ({units.describe(dim)}, SI)"


def describe_value(binding: Binding) -> str:
    """A name's value as the language would write it (frames in mm and deg, else SI)."""
    value = binding.value
    if value is None:
        return "(its definition had an error)"
    if isinstance(value, FrameValue):
        return format_pose(value.position, value.rotation)
    if isinstance(value, Scalar):
        return f"{value.value:g}{_unit(value.dim)}"
    if isinstance(value, Vec):
        return f"{format_vector(np.array(value.values), digits=4)}{_unit(value.dim)}"
    return str(value)


def frame_names(state: CompileState) -> list[str]:
    """Case-folded names of the fixtures and FRAMEs (``world`` first), in definition order."""
    return [key for key, b in state.names.items() if b.kind in (BindingKind.FIXTURE, BindingKind.FRAME)]


def all_names(state: CompileState) -> dict[str, str]:
    """Every name the session knows, case-folded, with what it is (for completion)."""
    found: dict[str, str] = {}
    for key, binding in state.names.items():
        found[key] = {BindingKind.FIXTURE: "fixture", BindingKind.FRAME: "frame"}.get(binding.kind, "value")
    for key in state.procedures:
        found[key] = "procedure"
    for key in state.obstacles:
        found[key] = "obstacle"
    return found


def changed_names(before: Mapping[str, Binding], after: Mapping[str, Binding]) -> list[str]:
    """Keys of LET and FRAME names new or rebound between two states, in definition order."""
    return [
        key
        for key, binding in after.items()
        if binding.kind is not BindingKind.FIXTURE and before.get(key) is not binding
    ]


def frame_table(state: CompileState) -> list[str]:
    """The ``:frames`` report: one line per fixture or FRAME, with where it is."""
    rows = []
    for key in frame_names(state):
        binding = state.names[key]
        origin = "fixture" if binding.kind is BindingKind.FIXTURE else f"FRAME at {_where(binding)}"
        rows.append((key, describe_value(binding), origin))
    width = max((len(name) for name, _, _ in rows), default=0)
    return [f"{name:<{width}}  {value}  [{origin}]" for name, value, origin in rows]


def _where(binding: Binding) -> str:
    return "?" if binding.span is None else f"{binding.span.file}:{binding.span.line}"
