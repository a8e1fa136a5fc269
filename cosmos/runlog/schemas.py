"""Topics and JSON schemas of the cosmos channels of a run log.

Each cosmos channel is JSON-encoded and carries a named JSON Schema (draft
2020-12). The schemas are written so that two kinds of reader agree on them:

- a JSON Schema validator checks every message exactly, nulls included;
- Foxglove, which builds its message types from ``properties`` and only
  understands a single ``type`` per property, can parse them too. Fields that
  may be ``null`` (a union type Foxglove does not parse) are therefore
  declared under ``patternProperties`` (anchored on the exact name), which
  validators apply and Foxglove skips; they are listed in ``required`` all
  the same.

See docs/log-format.md for the meaning, units and frames of every field.
"""

from __future__ import annotations

import json
from enum import StrEnum
from typing import Any, Final

JSON_SCHEMA_DIALECT: Final = "https://json-schema.org/draft/2020-12/schema"

STATE_TOPIC: Final = "/cosmos/state"
SEGMENT_TOPIC: Final = "/cosmos/segment"
EVENT_TOPIC: Final = "/cosmos/event"

STATE_SCHEMA_NAME: Final = "cosmos.State"
SEGMENT_SCHEMA_NAME: Final = "cosmos.Segment"
EVENT_SCHEMA_NAME: Final = "cosmos.Event"

METADATA_NAME: Final = "cosmos"
"""Name of the metadata record that identifies a cosmos run log."""

DEFAULT_JOINTS: Final = 6
"""The arm's number of joints in a log that does not say (the PUMA 560's: logs before the Panda)."""


FINGER_VECTORS: Final = (("fingers", 2), ("finger_force", 2))
"""The gripper's fields of a state message (metadata ``fingers``: TOOL GRIPPER), after the arm's."""


def state_vectors(joints: int = DEFAULT_JOINTS, fingers: bool = False) -> tuple[tuple[str, int], ...]:
    """The vector fields of a state message, in message order, with their lengths.

    ``q``, ``qd`` and ``tau`` have one entry per joint of the arm (metadata ``joints``);
    with ``fingers`` (a gripper's log), :data:`FINGER_VECTORS` follow the wrench.
    """
    arm = (
        ("q", joints),
        ("qd", joints),
        ("tau", joints),
        ("x", 3),
        ("quat", 4),
        ("v", 6),
        ("wrench", 6),
    )
    return arm + FINGER_VECTORS if fingers else arm


def state_width(joints: int = DEFAULT_JOINTS, fingers: bool = False) -> int:
    """Numbers in a state message besides t: 3 joints + 19 (37 for six joints), + 4 with the fingers."""
    return sum(n for _, n in state_vectors(joints, fingers))


STATE_VECTORS: Final = state_vectors()
"""The vector fields of a six-joint arm's state message (:func:`state_vectors`)."""

STATE_WIDTH: Final = state_width()  # 37 numbers besides t

STATE_DECIMALS: Final = 6
"""Vector fields of a state message are rounded to 1e-6 of their SI unit."""


class EventKind(StrEnum):
    """What an event on ``/cosmos/event`` reports."""

    START = "start"
    DONE = "done"
    STOPPED = "stopped"
    FAILED = "failed"
    CONTACT = "contact"
    COLLISION = "collision"
    WARNING = "warning"
    PROTECTIVE_STOP = "protective_stop"
    INTERRUPTED = "interrupted"
    DECISION = "decision"
    """An IF or WHILE read its condition: the values read and the branch taken."""
    RECOVERY = "recovery"
    """A TRY's ON FAIL part took over the failure logged just before."""
    RETRY = "retry"
    """A RETRY runs its TRY block again."""
    FOUND = "found"
    """An INSERT's SEARCH found the hole: where, when, and the INSERT goes on."""
    FIELD_ON_TOOL = "field_on_tool"
    """A link's obstacle field reaches the tool although the task leaves a null space (and ends)."""


OUTCOME_KINDS: Final = frozenset(("done", "stopped", "failed", "interrupted"))
"""Event kinds that end a statement."""


def _number(description: str) -> dict[str, Any]:
    return {"type": "number", "description": description}


def _integer(description: str) -> dict[str, Any]:
    return {"type": "integer", "minimum": 0, "description": description}


def _string(description: str) -> dict[str, Any]:
    return {"type": "string", "description": description}


def _vector(n: int, description: str, item: str = "number") -> dict[str, Any]:
    return {
        "type": "array",
        "items": {"type": item},
        "minItems": n,
        "maxItems": n,
        "description": description,
    }


def _nullable(schema: dict[str, Any]) -> dict[str, Any]:
    nullable = dict(schema)
    nullable["type"] = [schema["type"], "null"]
    return nullable


def _object(
    title: str,
    description: str,
    properties: dict[str, dict[str, Any]],
    nullable: dict[str, dict[str, Any]] | None = None,
) -> dict[str, Any]:
    nullable = nullable or {}
    schema: dict[str, Any] = {
        "$schema": JSON_SCHEMA_DIALECT,
        "title": title,
        "description": description,
        "type": "object",
        "properties": properties,
        "required": [*properties, *nullable],
    }
    if nullable:
        schema["$comment"] = (
            "Fields that may be null are under patternProperties so that Foxglove, "
            "which reads only single-typed properties, can parse this schema."
        )
        schema["patternProperties"] = {f"^{name}$": _nullable(s) for name, s in nullable.items()}
    return schema


_STATE_DESCRIPTIONS: Final = {
    "q": "joint positions 1..n [rad] (n: metadata joints)",
    "qd": "joint velocities 1..n [rad/s]",
    "tau": "joint torques 1..n commanded to the plant [N m]",
    "x": "tool point position in the world frame [m]",
    "quat": "tool orientation in the world frame, quaternion w x y z",
    "v": "tool twist in world axes at the tool point: vx vy vz [m/s] then wx wy wz [rad/s]",
    "wrench": (
        "force fx fy fz [N] then moment mx my mz [N m] that the tool applies to the "
        "environment, world axes, moment about the tool point"
    ),
    "fingers": (
        "the gripper's fingers, left then right: each pad's distance from the gripper's "
        "centre plane [m] (the opening between the pads is their sum); only with TOOL GRIPPER"
    ),
    "finger_force": (
        "normal force on the left then the right pad, as their sensors read them [N]; only with TOOL GRIPPER"
    ),
}


def state_schema(joints: int = DEFAULT_JOINTS, fingers: bool = False) -> dict[str, Any]:
    """The state message's schema for an arm of ``joints`` joints (and the gripper's, if ``fingers``)."""
    return _object(
        STATE_SCHEMA_NAME,
        "Arm and tool state sampled at the state rate (metadata state_hz). A value that is "
        "not finite (the controller diverged) is written as null.",
        {
            "t": _number("simulated time since the start of the run [s]"),
            **{name: _vector(n, _STATE_DESCRIPTIONS[name]) for name, n in state_vectors(joints, fingers)},
            "segment": _integer("index of the segment being executed (see /cosmos/segment)"),
            "line": _integer("source line of the statement being executed (0: none)"),
        },
    )


STATE_SCHEMA: Final = state_schema()

SEGMENT_SCHEMA: Final = _object(
    SEGMENT_SCHEMA_NAME,
    "A segment of the compiled plan, published when it starts. Axes are those of the "
    "task frame: x y z then rx ry rz.",
    {
        "t": _number("simulated time at which the segment starts [s]"),
        "segment": _integer("index of the segment, counting from 0 in order of execution"),
        "line": _integer("source line of the statement the segment comes from"),
        "statement": _string("source text of that statement"),
        "kind": _string("what the segment does, e.g. move, contact, slide, insert, wait"),
        "frame": _vector(4, "task frame orientation in the world frame, quaternion w x y z"),
        "motion_axes": _vector(
            6,
            "diagonal of the selection matrix Omega: 1 motion-controlled, 0 force-controlled",
            item="integer",
        ),
        "force_setpoint": _vector(
            6, "force [N] and moment [N m] the tool applies to the environment, task axes"
        ),
        "stiffness": _vector(6, "stiffness per task axis [N/m, N m/rad]"),
        "damping": _vector(6, "damping per task axis [N s/m, N m s/rad]"),
    },
    nullable={
        "goal": {
            "type": "array",
            "items": {"type": "number"},
            "minItems": 3,
            "maxItems": 7,
            "description": "goal in the world frame: position x y z [m], optionally followed "
            "by the orientation quaternion w x y z; null if the segment has no goal",
        },
        "speed_limit": _number("speed limit of the tool point [m/s]; null if none"),
        "timeout": _number("time allowed for the segment [s]; null if none"),
    },
)

EVENT_SCHEMA: Final = _object(
    EVENT_SCHEMA_NAME,
    "A change of outcome: a statement starts, ends (done, stopped by its UNTIL, failed), "
    "touches, collides, or a warning.",
    {
        "t": _number("simulated time of the event [s]"),
        "kind": _string("one of " + ", ".join(k.value for k in EventKind))
        | {"enum": [k.value for k in EventKind]},
        "line": _integer("source line of the statement concerned (0: none)"),
        "statement": _string("source text of the statement concerned"),
        "reason": _string("why, in words (empty if there is nothing to add)"),
        "context": _string(
            "where a statement expanded from a PROC, REPEAT, WHILE or TRY came from, outermost "
            "first ('REPEAT pass 2 of 2 at line 6; PROC probe called at line 7'); empty at top "
            "level and in logs written before it was recorded"
        ),
    },
)


def schema_bytes(schema: dict[str, Any]) -> bytes:
    """The schema as the UTF-8 JSON text stored in an MCAP Schema record."""
    return json.dumps(schema, indent=1).encode()
