"""``cosmos check PROGRAM [--json] [--full]``: parse, check and compile; print the plan.

Exit status 0 when the program compiles (warnings are printed on stderr and do
not change it; they include what :func:`cosmos.runtime.foresight.with_foreseen_limits`
foresees, as ``cosmos run`` prints them: a joint limit in the way, a goal inside a
fixture); a syntax or check error raises a :class:`ProgramError`, which
the command line renders on stderr with exit status 1.

Printing costs what the plan is worth: a plan of up to :data:`SCREEN_STEPS`
steps prints as a table; a longer one as a summary and its first steps, one
plain line each (``--full``: every step). ``--json`` writes the plan step by
step as it goes (an error, too, as JSON:
:func:`error_json`; exit status 1 for a program error, 2 for a file that cannot
be read). The branches of IF, WHILE and TRY are printed in place, each
step indented under the decision that holds it.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from collections import Counter
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np

from cosmos import plan
from cosmos.errors import CosmosError, UsageError
from cosmos.lang import compile_program, read_program
from cosmos.lang.compile.state import FrameLike
from cosmos.robots import ROBOTS
from cosmos.runtime.foresight import with_foreseen_limits

if TYPE_CHECKING:
    from rich.table import Table

_AXES = ("X", "Y", "Z", "RX", "RY", "RZ")

SCREEN_STEPS = 40
"""Plans of at most this many steps print as a table; longer ones as plain lines."""
SUMMARY_STEPS = 20
"""Steps a summary of a long plan lists (``--full`` lists them all)."""
SUMMARY_WARNINGS = 20
"""Warnings printed (``--full`` prints them all)."""


def load_fixtures() -> Mapping[str, FrameLike]:
    """The workcell's fixture frames (kept in the user cache: no simulator is loaded to check)."""
    from cosmos.commands.fixture_cache import fixture_frames

    return fixture_frames()


def error_json(error: CosmosError) -> dict[str, Any]:
    """``{"ok": false, "error": {...}}``: the error's kind, message, location and rendering."""
    span = error.span
    where = (
        {}
        if span is None
        else {
            "file": span.file,
            "line": span.line,
            "column": span.column,
            "end_line": span.end_line,
            "end_column": span.end_column,
        }
    )
    kind = "usage" if isinstance(error, UsageError) else "program"
    return {"ok": False, "error": {"kind": kind, "message": error.message, **where, "text": error.render()}}


def check_program(
    program: Path,
    as_json: bool = False,
    fixtures: Mapping[str, FrameLike] | None = None,
    out: TextIO | None = None,
    err: TextIO | None = None,
    full: bool = False,
    robot: str | None = None,
) -> int:
    """Compile ``program`` and print its plan; return the exit status (0; with ``as_json``, 1 or 2 on error).

    Args:
        program: Path of the program.
        as_json: Print the plan as one JSON object instead of a table.
        fixtures: Fixture frames; by default the workcell's.
        out: Where the plan goes (stdout).
        err: Where warnings go (stderr).
        full: Print every step of a long plan and every warning, not a summary.
        robot: The arm to check for (a program's ROBOT must agree); None: the program's ROBOT.

    Raises:
        ProgramError: Syntax or check errors (unless ``as_json``: printed as JSON).
        UsageError: The file cannot be read (unless ``as_json``).
    """
    out = out or sys.stdout
    err = err or sys.stderr
    try:
        source = read_program(program)
        compiled = compile_program(
            source, str(program), load_fixtures() if fixtures is None else fixtures, robot=robot
        )
        compiled = with_foreseen_limits(compiled)
    except CosmosError as error:
        if not as_json:
            raise
        out.write(json.dumps(error_json(error), indent=2) + "\n")
        return 2 if isinstance(error, UsageError) else 1
    warnings = compiled.warnings if full else compiled.warnings[:SUMMARY_WARNINGS]
    for warning in warnings:
        print(warning.render(source), file=err)
    if len(warnings) < len(compiled.warnings):
        more = len(compiled.warnings) - len(warnings)
        print(f"... {more} more warnings; cosmos check --full prints every one", file=err)
    if as_json:
        write_plan_json(compiled, out)
    elif len(plan.all_steps(compiled.steps)) <= SCREEN_STEPS:
        from rich.console import Console  # only plans that fit a screen are drawn

        Console(file=out, width=max(Console(file=out).width, 140)).print(plan_table(compiled))
    else:
        write_plan_lines(compiled, out, full)
    return 0


def write_plan_json(compiled: plan.Plan, out: TextIO) -> None:
    """The plan as :func:`cosmos.plan.plan_to_json` gives it, written one step at a time."""
    head = plan.plan_to_json(dataclasses.replace(compiled, steps=()))
    out.write("{")
    for index, (key, value) in enumerate(head.items()):
        out.write(f"{',' if index else ''}\n  {json.dumps(key)}: ")
        if key != "steps":
            out.write(json.dumps(value))
            continue
        out.write("[")
        for number, step in enumerate(compiled.steps):
            out.write(f"{',' if number else ''}\n    {json.dumps(plan.step_to_json(step))}")
        out.write("\n  ]")
    out.write("\n}\n")


def write_plan_lines(compiled: plan.Plan, out: TextIO, full: bool) -> None:
    """A long plan as plain text: counts by kind, then one line per step.

    Only the first :data:`SUMMARY_STEPS` steps are listed, unless ``full``.
    """
    rows = list(_rows(compiled.steps))
    kinds = Counter(_kind(step) for step in plan.all_steps(compiled.steps))
    out.write(
        f"{compiled.file}: {len(compiled.segments)} segments, {len(rows)} steps ("
        + ", ".join(f"{kind} {count}" for kind, count in kinds.items())
        + ")\n"
    )
    shown = rows if full else rows[:SUMMARY_STEPS]
    out.write("".join(step_line(step, depth) + "\n" for depth, step in shown))
    if len(shown) < len(rows):
        out.write(f"... {len(rows) - len(shown)} more steps; cosmos check --full prints every one\n")


_Row = plan.Step | tuple[str, int]
"""A step, or a divider inside a decided step: (``"else"`` or ``"on fail"``, its line)."""


def _rows(steps: tuple[plan.Step, ...], depth: int = 0) -> Iterator[tuple[int, _Row]]:
    """Every step with its depth, the branches of a decided step under it, dividers between them."""
    for step in steps:
        yield depth, step
        if isinstance(step, plan.Branch):
            yield from _rows(step.then_steps, depth + 1)
            if step.else_line is not None:
                yield depth, ("else", step.else_line)
                yield from _rows(step.else_steps, depth + 1)
        elif isinstance(step, plan.Loop):
            yield from _rows(step.body, depth + 1)
        elif isinstance(step, plan.Attempt):
            yield from _rows(step.body, depth + 1)
            yield depth, ("on fail", step.handler_line)
            yield from _rows(step.handler, depth + 1)


def _kind(step: plan.Step) -> str:
    if isinstance(step, plan.Segment):
        return step.kind.value
    if isinstance(step, plan.AddObstacle):
        return f"add {step.shape.value}"
    if isinstance(step, plan.RemoveObstacle):
        return "remove obstacle"
    if isinstance(step, plan.HandStep):
        return step.action.value
    return _DECIDED[type(step)]


_DECIDED = {plan.Branch: "if", plan.Loop: "while", plan.Attempt: "try", plan.Retry: "retry"}


def _decides(step: plan.Step) -> str:
    """What a decided step does, for the "ends" column."""
    if isinstance(step, plan.Branch):
        return f"reads {_condition(step.condition)}: the IF branch when it holds, else the ELSE branch"
    if isinstance(step, plan.Loop):
        return f"reads {_condition(step.condition)} before each pass; fails after {step.max_passes} passes"
    if isinstance(step, plan.Attempt):
        return "a failure in the block runs ON FAIL"
    if isinstance(step, plan.Retry):
        return f"the TRY block again, {step.times} times at most"
    return ""


def step_line(step: _Row, depth: int = 0) -> str:
    """One step as one plain line: index, line, kind, statement, then what it does."""
    indent = "  " * depth
    if isinstance(step, tuple):
        return f"{'':>6} {step[1]:>6}  {step[0]:<16}  {indent}{step[0].upper()}"
    if not isinstance(step, plan.Segment):
        decides = _decides(step)
        return f"{'':>6} {step.line:>6}  {_kind(step):<16}  {indent}{step.statement}" + (
            f"  | {decides}" if decides else ""
        )
    index, line, _, kind, frame, motion, force, setpoints, goal, ends = _segment_row(step)
    context = f"  [{step.context}]" if step.context else ""
    return (
        f"{index:>6} {line:>6}  {kind:<16}  {indent}{step.statement}{context}  | frame {frame}; "
        f"motion {motion}; force {force}; {setpoints}; {goal}; ends {ends}"
    )


def plan_table(compiled: plan.Plan) -> Table:
    """The plan as a table: one row per step."""
    from rich.table import Table

    arm = ROBOTS[compiled.robot]
    title = (
        f"{compiled.file}: {len(compiled.segments)} segments on the {arm.title} "
        f"({arm.dof} joints, reach {arm.capability.reach_m * 1e3:.0f} mm)"
    )
    if compiled.tool != "peg":
        objects = ", ".join(f"{o.name} ({o.shape.value}, {o.mass_kg:.3g} kg)" for o in compiled.objects)
        title += f" with the {compiled.tool}" + (f"; objects: {objects}" if objects else "")
    table = Table(title=title, title_justify="left")
    for header in ("#", "line", "statement", "kind", "frame", "motion", "force", "setpoints", "goal", "ends"):
        table.add_column(header, overflow="fold")
    for depth, step in _rows(compiled.steps):
        indent = "  " * depth
        if isinstance(step, tuple):
            table.add_row("", str(step[1]), indent + step[0].upper(), step[0], "", "", "", "", "", "")
        elif isinstance(step, plan.Segment):
            row = _segment_row(step)
            table.add_row(row[0], row[1], indent + row[2], *row[3:])
        else:
            table.add_row(
                "", str(step.line), indent + step.statement, _kind(step), "", "", "", "", "", _decides(step)
            )
    return table


def _segment_row(segment: plan.Segment) -> tuple[str, ...]:
    motion = " ".join(a for a, m in zip(_AXES, segment.motion_axes, strict=True) if m) or "-"
    if segment.orientation_free:  # the rotations are the null space's (ORIENTATION FREE)
        motion = motion.replace("RX RY RZ", "(RX RY RZ free)")
    force = " ".join(a for a, m in zip(_AXES, segment.motion_axes, strict=True) if not m) or "-"
    setpoints = []
    for axis, value, moving, stiffness in zip(
        _AXES, segment.force_setpoint, segment.motion_axes, segment.stiffness, strict=True
    ):
        unit = "N" if axis in ("X", "Y", "Z") else "Nm"
        if not moving:
            setpoints.append(f"F{axis.lower()} {value:+g} {unit}")
        elif stiffness is not None:
            setpoints.append(f"K{axis.lower()} {stiffness:g} {unit}/{'m' if unit == 'N' else 'rad'}")
    statement = segment.statement + (f"\n[dim]{segment.context}[/dim]" if segment.context else "")
    return (
        str(segment.index),
        str(segment.line),
        statement,
        segment.kind.value,
        segment.frame_name,
        motion,
        force,
        ", ".join(setpoints) or "-",
        _goal(segment),
        _ends(segment),
    )


def _vector(values: np.ndarray, scale: float = 1000.0) -> str:
    return "(" + ", ".join(f"{v * scale:.4g}" for v in values) + ")"


def _goal(segment: plan.Segment) -> str:
    target = segment.target
    if target is None:
        text = "hold"
    elif isinstance(target, plan.RelativeTarget):
        text = f"by {_vector(target.offset_world)} mm"
    else:
        text = f"to {_vector(target.position_world)} mm"
        if target.rotation_world is not None:
            text += " oriented"
    if segment.via:
        text += f" via {len(segment.via)}"
    if segment.speed_limit_mps is not None:
        text += f" @ {segment.speed_limit_mps * 1000:g} mm/s"
    if segment.duration_s is not None:
        text += f" in {segment.duration_s:g} s"
    return text


def _ends(segment: plan.Segment) -> str:
    completion = segment.completion
    if isinstance(completion, plan.ContactTouch):
        text = f"touch > {completion.threshold_n:g} N"
    elif isinstance(completion, plan.ForceSettled):
        text = f"force settled ±{completion.tolerance_n:g} N"
    elif isinstance(completion, plan.DepthReached):
        text = f"depth {completion.depth_m * 1000:g} mm"
        if completion.touch_n is not None:
            text = f"touch > {completion.touch_n:g} N or {text}"
    elif isinstance(completion, plan.Elapsed):
        text = f"after {completion.duration_s:g} s"
    elif isinstance(completion, plan.UntilOnly):
        text = "condition"
    else:
        text = "goal reached"
    if segment.until is not None:
        text += f"; until {_condition(segment.until)}"
    if segment.timeout_s is not None:
        text += f"; timeout {segment.timeout_s:g} s"
    if segment.jam_check is not None:
        text += "; jam check"
    if segment.search is not None:
        search = segment.search
        text += (
            f"; search {search.pattern.value} {search.radius_m * 1e3:g} mm pitch {search.pitch_m * 1e3:g} mm"
        )
    return text


def _condition(condition: plan.Condition) -> str:
    if isinstance(condition, plan.Comparison | plan.LastOutcome):
        return condition.text
    joiner = " AND " if isinstance(condition, plan.AllOf) else " OR "
    return "(" + joiner.join(_condition(term) for term in condition.terms) + ")"
