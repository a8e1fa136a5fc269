"""Joint limits a program runs into, foreseen from its text: home pose and static goals.

A program starts at home; a ``MOVE TO`` with a fixed goal, or a ``MOVE BY`` from a known
pose, that ends where it was sent leaves the arm where the runtime's own plan
(:func:`cosmos.runtime.rotation_plan.plan_rotation`, inverse kinematics along the
tool's path) puts it. Where that plan is stopped by a joint's limit both ways round,
the run will fail there; the checker says so as a warning at the statement
(``MOVE TO: joint 6 would reach its limit of 266 deg ...``), with the wrist
configuration in which the goal is within range if there is one. After anything whose
end is not known (a contact, a slide, an UNTIL, a POSTURE, a block) nothing more is foreseen.

:func:`with_foreseen_limits` adds these warnings to the compiled plan's, and those of goals
inside a fixture (:mod:`cosmos.runtime.goals_in_fixtures`): the language below does not know
the arm's kinematics nor the workcell's solids. ``cosmos check``, ``cosmos run`` and
:func:`cosmos.check` all add them. The kinematics (Pinocchio, the arm's model) and the solids
come from the user cache (:mod:`cosmos.runtime.foresight_cache`), so a check does not load
MuJoCo (``tests/test_fixture_cache.py``); Pinocchio is imported only for a chain of static
goals not foreseen before (:func:`foreseeable_joint_limits`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cosmos import plan
from cosmos.robots import ROBOTS
from cosmos.runtime import foresight_cache
from cosmos.runtime.approach_time import approach_timeout
from cosmos.runtime.arm_at_home import obstacles_through_arm
from cosmos.runtime.goals_in_fixtures import Approach, Pose, ToolShape, goals_inside_fixtures
from cosmos.runtime.reach import beyond_reach


def with_foreseen_limits(compiled: plan.Plan) -> plan.Plan:
    """``compiled`` with a warning for each goal motion a joint's limit will stop or a fixture holds.

    The goals inside a fixture are :func:`cosmos.runtime.goals_in_fixtures.goals_inside_fixtures`'s,
    the CONTACTs whose TIMEOUT ends their approach short of the fixture :func:`approach_timeout`'s.
    The warnings are sorted in by place.
    """
    found = foreseeable_joint_limits(compiled.steps, compiled.robot, compiled.tool)
    cell = foresight_cache.workcell(compiled.robot, compiled.tool)
    home = Pose(cell.home_tool_position, cell.home_tool_rotation)
    tool = ToolShape(cell.tool_length_m, cell.tool_sections, cell.tool_ahead_m)
    approaches: list[Approach] = []
    found += goals_inside_fixtures(compiled.steps, cell.solids, home, tool, approaches)
    found += [late for a in approaches if (late := approach_timeout(a, tool.sections)) is not None]
    found += obstacles_through_arm(compiled.steps, cell.arm_at_home)
    if not found:
        return compiled
    warnings = sorted((*compiled.warnings, *found), key=lambda w: (w.span.line, w.span.column))
    return dataclasses.replace(compiled, warnings=tuple(warnings))


def foreseeable_joint_limits(
    steps: tuple[plan.Step, ...], robot_name: str, tool: str = "peg"
) -> list[plan.Diagnostic]:
    """Warnings for the goal motions a joint's limit will stop, where the program says where the arm is.

    What a chain of goals foresees is kept in the user cache
    (:func:`cosmos.runtime.foresight_cache.foreseen`): checking a program again does not import
    Pinocchio (60 ms of a 0.4 s check).

    Args:
        steps: The compiled plan's steps.
        robot_name: The program's arm (``ROBOTS`` key).
        tool: The program's tool (``Tool`` value): its tool point is the one that moves.

    Returns:
        One diagnostic per foreseen stop, at its statement.
    """
    if not any(_is_static_move(step) for step in steps):
        return []
    key = _chain_key(steps)
    kept = foresight_cache.foreseen(robot_name, tool, key)
    if kept is None or not all(0 <= index < len(steps) for index, _ in kept):
        kept = _follow_from_home(steps, robot_name, tool)
        foresight_cache.keep_foreseen(robot_name, tool, key, kept)
    return [plan.Diagnostic(message, steps[index].span) for index, message in kept]


def _chain_key(steps: tuple[plan.Step, ...]) -> bytes:
    """What :func:`_follow_from_home` reads of ``steps``, as bytes (the cache's key)."""
    parts = []
    for step in steps:
        if not isinstance(step, plan.Segment):
            parts.append(b"B" if isinstance(step, plan.Branch | plan.Loop | plan.Attempt) else b"-")
            continue
        parts.append(f"S{step.tool_end.value}:".encode())
        target = step.target
        if isinstance(target, plan.AbsoluteTarget):
            parts.append(b"T" + np.asarray(target.position_world, dtype=float).tobytes())
            if target.rotation_world is not None:
                parts.append(b"R" + np.asarray(target.rotation_world, dtype=float).tobytes())
        elif isinstance(target, plan.RelativeTarget):
            parts.append(b"O" + np.asarray(target.offset_world, dtype=float).tobytes())
    return b"|".join(parts)


def _follow_from_home(steps: tuple[plan.Step, ...], robot_name: str, tool: str) -> list[tuple[int, str]]:
    """The stops the runtime's rotation plan foresees: (index in ``steps``, message) each."""
    import pinocchio as pin

    from cosmos.runtime.rotation_plan import plan_rotation

    model = foresight_cache.kinematics(robot_name, tool)
    flange_in_tool = foresight_cache.workcell(robot_name, tool).flange_in_tool
    data = model.model.createData()
    known: np.ndarray | None = np.array(model.home_q)
    since = "the home pose"  # where ``known`` comes from
    found: list[tuple[int, str]] = []
    for index, step in enumerate(steps):
        if isinstance(step, plan.Branch | plan.Loop | plan.Attempt):
            known = None  # a block may move the arm, or not
        if not isinstance(step, plan.Segment):
            continue
        if step.tool_end is plan.ToolEnd.STAYS:
            continue
        if known is None or step.tool_end is not plan.ToolEnd.AT_TARGET:
            known = None
            continue
        pin.framesForwardKinematics(model.model, data, known)
        pose = data.oMf[model.tool_frame]
        position, rotation = pose.translation.copy(), pose.rotation.copy()
        target = step.target
        if isinstance(target, plan.AbsoluteTarget):
            goal_position = np.asarray(target.position_world, dtype=float)
            goal_rotation = rotation if target.rotation_world is None else np.asarray(target.rotation_world)
        elif isinstance(target, plan.RelativeTarget):
            goal_position, goal_rotation = position + np.asarray(target.offset_world), rotation
        else:
            known = None
            continue
        if (
            far := beyond_reach(goal_position + goal_rotation @ flange_in_tool, ROBOTS[robot_name])
        ) is not None:
            found.append((index, f"{_keyword(step)}: {far}"))
            known = None
            continue
        route = plan_rotation(model, known, position, rotation, goal_position, goal_rotation, compiled=False)
        if route.blocked_by is not None:
            found.append((index, f"{_keyword(step)}: {_foreseen(route.blocked_by.message, since)}"))
            known = None
            continue
        known, since = route.goal_q, f"the goal of line {step.span.line}"
    return found


def _is_static_move(step: plan.Step) -> bool:
    return isinstance(step, plan.Segment) and step.kind is plan.SegmentKind.MOVE


def _keyword(step: plan.Segment) -> str:
    return "MOVE TO" if isinstance(step.target, plan.AbsoluteTarget) else "MOVE BY"


def _foreseen(message: str, since: str) -> str:
    """``joint 6 at its limit of 266 deg`` as foreseen from ``since`` (``the goal of line 2``)."""
    return message.replace(" at its limit of ", " would reach its limit of ", 1) + f" (from {since})"
