"""The plan as JSON: what `cosmos check --json` prints and the log's /cosmos/segment carries."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from cosmos.plan.conditions import AllOf, AnyOf, Condition, LastOutcome
from cosmos.plan.segments import Segment
from cosmos.plan.steps import Attempt, Branch, Decided, HandStep, Loop, Plan, RemoveObstacle, Retry, Step
from cosmos.plan.targets import Completion, RelativeTarget, Target
from cosmos.rotations import matrix_to_quaternion

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
