"""Syntax tree to plan: the statement-by-statement compiler.

:class:`Compiler` turns statements into plan steps while threading a
:class:`~cosmos.lang.state.CompileState` through them: the default speed, the
COMPLY settings, the held contact, names, procedures and obstacles. Motion
statements are built in :mod:`cosmos.lang.motion`; this module handles names,
blocks, the scene, error collection and the public entry points.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.checker import check_statement
from cosmos.lang.frozen_new import quick
from cosmos.lang.gc_pause import gc_paused
from cosmos.lang.motion import MotionBuilder
from cosmos.lang.parser import parse_program
from cosmos.lang.rotations import IDENTITY, readonly
from cosmos.lang.state import (
    AxisCompliance,
    CompileState,
    Defaults,
    FrameLike,
    ProcEntry,
    frozen_map,
)
from cosmos.lang.syntax import STATEMENT_KEYWORDS
from cosmos.lang.values import Binding, BindingKind, Evaluator, FrameValue, SuppressedError, suggest

MAX_STEPS = 100_000
"""Most steps a program may expand to (procedures and loops included)."""
MAX_CALL_DEPTH = 32
"""Deepest chain of procedure calls."""
MAX_ERRORS = 20
"""Errors reported before the compiler stops looking for more."""

_DEFINITIONS = (ast.Let, ast.FrameDef)


class ProgramErrors(ProgramError):
    """Several program errors; renders each, and reads as the first one.

    Attributes:
        errors: The errors in source order.
    """

    def __init__(self, errors: list[ProgramError]):
        first = errors[0]
        super().__init__(first.message, first.span, first.source)
        self.errors = errors

    def render(self) -> str:
        """Every error, rendered, separated by blank lines."""
        return "\n".join(error.render() for error in self.errors)


@dataclass(frozen=True)
class StatementResult:
    """What compiling one statement (or one REPL input) gives.

    Attributes:
        steps: The steps to execute, in order.
        state: The state after the statement.
        warnings: Diagnostics for the statement.
    """

    steps: tuple[plan.Step, ...]
    state: CompileState
    warnings: tuple[plan.Diagnostic, ...]


_statement_result = quick(StatementResult)
_binding = quick(Binding)
_axis_compliance = quick(AxisCompliance)
_LET = BindingKind.LET
_FRAME = BindingKind.FRAME
_STIFFNESS = ast.ClauseKind.STIFFNESS
_DAMPING = ast.ClauseKind.DAMPING
_NO_COMPLIANCE = (None,) * 6


def statement_text(span: Span, source: str | list[str]) -> str:
    """The source text a span covers, lines joined with a space.

    Args:
        span: The span.
        source: The text, or its lines (``str.splitlines``) when called often.
    """
    lines = source.splitlines() if isinstance(source, str) else source
    if not 1 <= span.line <= len(lines):
        return ""
    if span.end_line == span.line:
        return lines[span.line - 1][span.column - 1 : span.end_column - 1].strip()
    parts = [lines[span.line - 1][span.column - 1 :]]
    parts += lines[span.line : span.end_line - 1]
    if span.end_line <= len(lines):
        parts.append(lines[span.end_line - 1][: span.end_column - 1])
    return " ".join(part.strip().rstrip("\\").strip() for part in parts if part.strip())


class _Run:
    """One compilation pass over the top-level statements of one text.

    Holds the source of the statement being compiled (a procedure's own text
    while it is expanded), the call and loop context, and the steps and warnings
    emitted. Its evaluator and motion builder serve every statement of the pass
    (they are pointed at each statement's state in turn, not made anew).
    """

    __slots__ = (
        "compiler",
        "source",
        "lines",
        "context",
        "call_stack",
        "steps",
        "warnings",
        "first_step",
        "evaluator",
        "builder",
    )

    def __init__(self, compiler: Compiler, source: str):
        self.compiler = compiler
        self.source = source
        self.lines = compiler.lines_of(source)
        """``source.splitlines()``: ``source`` changes (to a procedure's text), so do they."""
        self.context: list[str] = []
        self.call_stack: list[str] = []
        self.steps: list[plan.Step] = []
        self.warnings: list[plan.Diagnostic] = []
        self.first_step = 0
        """Index in ``steps`` of the first step of the top-level statement being compiled."""
        self.evaluator = Evaluator(compiler._fixture_names, self.text_of)
        self.builder = MotionBuilder(compiler.defaults, self.evaluator, self.text_of, self.warn)

    def text_of(self, span: Span) -> str:
        lines = self.lines
        line = span.line
        if line == span.end_line and 0 < line <= len(lines):  # most statements: statement_text's first case
            return lines[line - 1][span.column - 1 : span.end_column - 1].strip()
        return statement_text(span, lines)

    def warn(self, message: str, span: Span) -> None:
        if self.context:
            message += f" (in {'; '.join(self.context)})"
        self.warnings.append(plan.Diagnostic(message, span))

    def emit(self, steps: Sequence[plan.Step]) -> None:
        if len(self.steps) - self.first_step + len(steps) > MAX_STEPS:
            raise ProgramError(
                f"the program expands to more than {MAX_STEPS} steps; use fewer REPEATs",
                steps[0].span,
            )
        self.steps.extend(steps)

    def top_level(self, statement: ast.Statement, state: CompileState) -> CompileState:
        """Check and compile one top-level statement; on an error, drop what it emitted.

        Raises:
            ProgramError: The statement is wrong (its source attached).
        """
        steps, warnings = len(self.steps), len(self.warnings)
        self.first_step = steps
        try:
            check_statement(statement)
            try:  # what ``statement`` does; at the top level there is no context to name
                return _DISPATCH.get(type(statement), _Run._call)(self, statement, state)
            except RecursionError:
                raise ProgramError(
                    "this statement nests too deeply to compile; split its expressions",
                    statement.span,
                ) from None
        except ProgramError as error:
            del self.steps[steps:], self.warnings[warnings:]
            raise error.with_source(self.source) from None

    # ------------------------------------------------------------ dispatch

    def statement(self, statement: ast.Statement, state: CompileState) -> CompileState:
        """Compile one statement (expanding blocks) and return the state after it.

        An error leaving here carries the text it points into and, for a statement
        expanded from a procedure or loop, where it was expanded from.
        """
        try:
            try:
                return _DISPATCH.get(type(statement), _Run._call)(self, statement, state)
            except RecursionError:
                raise ProgramError(
                    "this statement nests too deeply to compile; split its expressions",
                    statement.span,
                ) from None
        except ProgramError as error:
            if error.source is None:  # not yet seen by an inner statement
                if self.context and not isinstance(error, SuppressedError):
                    error.message += f" (in {'; '.join(self.context)})"
                error.with_source(self.source)
            raise

    def _evaluator(self, state: CompileState) -> Evaluator:
        """The pass's evaluator, reading the names of ``state``."""
        evaluator = self.evaluator
        evaluator.names = state.names
        return evaluator

    def _motion(self, statement: ast.Statement, state: CompileState) -> CompileState:
        self.evaluator.names = state.names
        context = "; ".join(self.context) if self.context else ""
        segments, state = self.builder.build(statement, state, context)  # type: ignore[arg-type]
        steps = self.steps
        if len(steps) - self.first_step + len(segments) > MAX_STEPS:
            self.emit(segments)  # raises
        steps.extend(segments)
        return state

    def _speed(self, statement: ast.SetSpeed, state: CompileState) -> CompileState:
        speed = self._evaluator(state).expect_scalar(statement.value, units.SPEED, "SPEED")
        _positive(speed, statement.value.span, "SPEED")
        if speed > 1.5:
            self.warn(f"SPEED {speed:g} m/s is faster than the PUMA 560 moves its tool", statement.value.span)
        return state.with_speed(speed)

    # ---------------------------------------------------------------- names

    def _define(self, statement: ast.Let | ast.FrameDef, state: CompileState) -> CompileState:
        evaluator = self._evaluator(state)
        key = statement.name.key
        previous = state.names.get(key)
        if previous is not None and previous.kind is BindingKind.FIXTURE:
            self.warn(
                f"'{statement.name.name}' hides the workcell fixture of that name from here on",
                statement.name.span,
            )
        if isinstance(statement, ast.Let):
            value = evaluator.evaluate(statement.value)
            kind = _LET
        else:
            value = evaluator.expect_position(statement.value, "FRAME")
            kind = _FRAME
        return state.bind(key, _binding(value, kind, statement.name.span))

    # ----------------------------------------------------------- compliance

    def _comply(self, statement: ast.Comply, state: CompileState) -> CompileState:
        if not statement.axes:
            return state.with_compliance(_NO_COMPLIANCE)
        evaluator = self._evaluator(state)
        clauses = {c.kind: c for c in statement.clauses if type(c) is ast.ValueClause}
        rotations = {ref.axis.is_rotation for ref in statement.axes}
        if len(rotations) > 1 and clauses:
            raise ProgramError(
                "one STIFFNESS or DAMPING cannot serve both translation and rotation axes "
                "(N/m against Nm/rad); write one COMPLY for X Y Z and another for RX RY RZ",
                statement.span,
            )
        rotation = rotations.pop()
        stiffness = 0.0
        damping: float | None = None
        if _STIFFNESS in clauses:
            expr = clauses[_STIFFNESS].value
            dim = units.ROTATIONAL_STIFFNESS if rotation else units.STIFFNESS
            stiffness = evaluator.expect_scalar(expr, dim, "STIFFNESS")
            _not_negative(stiffness, expr.span, "STIFFNESS")
        if _DAMPING in clauses:
            expr = clauses[_DAMPING].value
            dim = units.ROTATIONAL_DAMPING if rotation else units.DAMPING
            damping = evaluator.expect_scalar(expr, dim, "DAMPING")
            _not_negative(damping, expr.span, "DAMPING")
        compliance = list(state.compliance)
        setting = _axis_compliance(stiffness, damping, statement.span)  # immutable: shared by the axes
        for ref in statement.axes:
            compliance[ref.axis._value_] = setting
        return state.with_compliance(tuple(compliance))

    # --------------------------------------------------------------- scene

    def _obstacle(self, statement: ast.Obstacle, state: CompileState) -> CompileState:
        evaluator = self._evaluator(state)
        key = statement.name.key
        if key in state.obstacles:
            first = state.obstacles[key]
            raise ProgramError(
                f"an obstacle named '{statement.name.name}' is already in the scene "
                f"(line {first.line}); OBSTACLE REMOVE {statement.name.name} first",
                statement.name.span,
            )
        clauses = {c.kind: c.value for c in statement.clauses if isinstance(c, ast.ValueClause)}
        at = evaluator.expect_position(clauses[ast.ClauseKind.AT], "AT")
        rotation = IDENTITY if at.rotation is None else at.rotation
        position = at.position
        radius = height = None
        size = None
        shape = plan.ObstacleShape(statement.shape.value.lower())

        def length(kind: ast.ClauseKind) -> float:
            value = evaluator.expect_scalar(clauses[kind], units.LENGTH, kind.value)
            _positive(value, clauses[kind].span, kind.value)
            return value

        if ast.ClauseKind.RADIUS in clauses:
            radius = length(ast.ClauseKind.RADIUS)
        if ast.ClauseKind.HEIGHT in clauses:
            height = length(ast.ClauseKind.HEIGHT)
            # AT is the centre of the cylinder's base; the plan holds its centre.
            position = readonly(position + rotation[:, 2] * height / 2)
        if ast.ClauseKind.SIZE in clauses:
            expr = clauses[ast.ClauseKind.SIZE]
            size = evaluator.expect_vector3(expr, units.LENGTH, "SIZE")
            if np.any(size <= 0):
                raise ProgramError("SIZE needs three positive lengths", expr.span)
        if ast.ClauseKind.NORMAL in clauses:
            expr = clauses[ast.ClauseKind.NORMAL]
            if at.rotation is not None:
                raise ProgramError("give the plane a NORMAL or an RPY, not both", expr.span)
            rotation = _rotation_with_z(
                evaluator.expect_vector3(expr, units.DIMENSIONLESS, "NORMAL"), expr.span
            )
        velocity = readonly(np.zeros(3))
        if ast.ClauseKind.MOVING in clauses:
            velocity = evaluator.expect_vector3(clauses[ast.ClauseKind.MOVING], units.SPEED, "MOVING")
        influence = None
        if ast.ClauseKind.INFLUENCE in clauses:
            influence = length(ast.ClauseKind.INFLUENCE)
        gain = 1.0
        if ast.ClauseKind.GAIN in clauses:
            gain = evaluator.expect_scalar(clauses[ast.ClauseKind.GAIN], units.DIMENSIONLESS, "GAIN")
            _positive(gain, clauses[ast.ClauseKind.GAIN].span, "GAIN")
        self.emit(
            [
                plan.AddObstacle(
                    name=statement.name.name,
                    shape=shape,
                    position_world=readonly(position),
                    rotation_world=readonly(rotation),
                    radius_m=radius,
                    height_m=height,
                    size_m=size,
                    velocity_world_mps=velocity,
                    influence_m=influence,
                    gain_scale=gain,
                    span=statement.span,
                    line=statement.span.line,
                    statement=self.text_of(statement.span),
                )
            ]
        )
        return replace(state, obstacles=frozen_map({**state.obstacles, key: statement.span}))

    def _remove(self, statement: ast.RemoveObstacle, state: CompileState) -> CompileState:
        key = statement.name.key
        if key not in state.obstacles:
            raise ProgramError(
                f"no obstacle named '{statement.name.name}' is in the scene"
                f"{suggest(statement.name.name, state.obstacles)}",
                statement.name.span,
            )
        self.emit(
            [
                plan.RemoveObstacle(
                    name=statement.name.name,
                    span=statement.span,
                    line=statement.span.line,
                    statement=self.text_of(statement.span),
                )
            ]
        )
        return replace(state, obstacles=frozen_map({k: v for k, v in state.obstacles.items() if k != key}))

    # -------------------------------------------------------------- blocks

    def _proc(self, statement: ast.ProcDef, state: CompileState) -> CompileState:
        key = statement.name.key
        if key in state.procedures and state.procedures[key].definition.span.file == statement.span.file:
            first = state.procedures[key].definition.span
            raise ProgramError(
                f"PROC {statement.name.name} is already defined at line {first.line}",
                statement.name.span,
            )
        entry = ProcEntry(statement, self.source)
        return replace(state, procedures=frozen_map({**state.procedures, key: entry}))

    def _call(self, statement: ast.Call, state: CompileState) -> CompileState:
        key = statement.name.key
        entry = state.procedures.get(key)
        if entry is None:
            if key == "end":
                raise ProgramError("END without a PROC or REPEAT to close", statement.span)
            if statement.name.name.upper() in STATEMENT_KEYWORDS:
                raise ProgramError(f"{statement.name.name.upper()} needs more after it", statement.span)
            raise ProgramError(
                f"unknown procedure '{statement.name.name}'{suggest(statement.name.name, state.procedures)}",
                statement.name.span,
            )
        if key in self.call_stack or len(self.call_stack) >= MAX_CALL_DEPTH:
            chain = " -> ".join([*self.call_stack, key])
            raise ProgramError(f"procedures call each other without end: {chain}", statement.span)
        state = replace(state, called=state.called | {key})
        outer_source, outer_lines = self.source, self.lines
        self.source = entry.source
        self.lines = self.compiler.lines_of(entry.source)
        self.call_stack.append(key)
        self.context.append(f"PROC {entry.definition.name.name} called at line {statement.span.line}")
        try:
            for inner in entry.definition.body:
                state = self.statement(inner, state)
        finally:
            self.context.pop()
            self.call_stack.pop()
            self.source, self.lines = outer_source, outer_lines
        return state

    def _repeat(self, statement: ast.Repeat, state: CompileState) -> CompileState:
        count_value = self._evaluator(state).expect_scalar(statement.count, units.DIMENSIONLESS, "REPEAT")
        if not math.isfinite(count_value) or count_value != int(count_value) or count_value < 0:
            raise ProgramError(
                f"REPEAT needs a whole number of times, not {self.text_of(statement.count.span)}",
                statement.count.span,
            )
        count = int(count_value)
        if count == 0:
            self.warn("REPEAT 0 runs its block no times", statement.count.span)
        if count > MAX_STEPS:
            raise ProgramError(f"REPEAT {count} is more than {MAX_STEPS} passes", statement.count.span)
        for index in range(count):
            self.context.append(f"REPEAT pass {index + 1} of {count} at line {statement.span.line}")
            try:
                for inner in statement.body:
                    state = self.statement(inner, state)
            finally:
                self.context.pop()
        return state


_DISPATCH: dict[type, Callable[[_Run, Any, CompileState], CompileState]] = {
    ast.Move: _Run._motion,
    ast.Contact: _Run._motion,
    ast.Slide: _Run._motion,
    ast.Insert: _Run._motion,
    ast.Wait: _Run._motion,
    ast.SetSpeed: _Run._speed,
    ast.Comply: _Run._comply,
    ast.Let: _Run._define,
    ast.FrameDef: _Run._define,
    ast.Obstacle: _Run._obstacle,
    ast.RemoveObstacle: _Run._remove,
    ast.ProcDef: _Run._proc,
    ast.Repeat: _Run._repeat,
}
"""How a statement of each type is compiled (a CALL, the only other type, by ``_Run._call``)."""


def _positive(value: float, span: Span, what: str) -> None:
    if not value > 0 or not math.isfinite(value):
        raise ProgramError(f"{what} must be a positive number, not {value:g}", span)


def _not_negative(value: float, span: Span, what: str) -> None:
    if not value >= 0 or not math.isfinite(value):
        raise ProgramError(f"{what} cannot be negative ({value:g})", span)


def _rotation_with_z(normal: np.ndarray, span: Span) -> np.ndarray:
    """A rotation whose z axis is ``normal`` (normalised)."""
    length = float(np.linalg.norm(normal))
    if not length > 0 or not math.isfinite(length):
        raise ProgramError("NORMAL needs a non-zero direction, like (0, 0, 1)", span)
    z = normal / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return readonly(np.column_stack([x, y, z]))


class Compiler:
    """Compiles statements to plan steps against a workcell's fixture frames.

    Args:
        fixtures: Predefined frames by name (``cosmos.workcell.fixture_frames()``):
            each has ``position`` (3,) [m, world] and ``rotation`` (3, 3). ``world``
            (the world frame) is always defined.
        defaults: Values used where a program does not give one.
    """

    def __init__(self, fixtures: Mapping[str, FrameLike] | None = None, defaults: Defaults | None = None):
        self.defaults = defaults or Defaults()
        names = {"world": Binding(FrameValue(readonly(np.zeros(3)), IDENTITY), BindingKind.FIXTURE, None)}
        for name, frame in (fixtures or {}).items():
            value = FrameValue(readonly(frame.position), readonly(frame.rotation))
            names[name.casefold()] = Binding(value, BindingKind.FIXTURE, None)
        self._fixture_names = frozen_map(names)
        self._split: tuple[str | None, list[str]] = (None, [])

    def lines_of(self, source: str) -> list[str]:
        """``source.splitlines()``, remembered for the last text.

        The statements of one program share their text, so a long program is
        split once rather than once per statement.
        """
        if self._split[0] is not source:
            self._split = (source, source.splitlines())
        return self._split[1]

    def initial_state(self) -> CompileState:
        """The state at the start of a program: home pose, no names but the fixtures."""
        return CompileState(default_speed_mps=self.defaults.speed_mps, names=self._fixture_names)

    def compile_statement(
        self, statement: ast.Statement, state: CompileState, source: str
    ) -> StatementResult:
        """Compile one top-level statement.

        Args:
            statement: The statement (a PROC is registered, a CALL or REPEAT expanded).
            state: The state before it.
            source: The text the statement was parsed from.

        Raises:
            ProgramError: The statement is wrong; ``state`` still holds.
        """
        run = _Run(self, source)
        new_state = run.top_level(statement, state)
        return _statement_result(tuple(run.steps), new_state, tuple(run.warnings))

    def compile_text(self, text: str, state: CompileState, file: str = "<repl>") -> StatementResult:
        """Parse and compile a piece of program (a REPL input), continuing from ``state``.

        Raises:
            ProgramError: A syntax or check error (all errors, as :class:`ProgramErrors`).
        """
        with gc_paused():
            return self._compile_text(text, state, file)

    def _compile_text(self, text: str, state: CompileState, file: str) -> StatementResult:
        program = parse_program(text, file)
        run = _Run(self, text)  # one pass: a failed statement's steps and warnings are dropped
        top_level = run.top_level
        errors: list[ProgramError] = []
        for statement in program.statements:
            try:
                state = top_level(statement, state)
            except SuppressedError:
                state = _poison(statement, state)
            except ProgramError as error:
                errors.append(error)
                state = _poison(statement, state)
                if len(errors) >= MAX_ERRORS:
                    break
        if errors:
            raise ProgramErrors(errors)
        return _statement_result(tuple(run.steps), state, tuple(run.warnings))

    def compile_program(self, source: str, file: str = "<input>") -> plan.Plan:
        """Parse, check and compile a whole program.

        Raises:
            ProgramError: Syntax or check errors (several as :class:`ProgramErrors`).
        """
        with gc_paused():
            return self._compile_program(source, file)

    def _compile_program(self, source: str, file: str) -> plan.Plan:
        result = self.compile_text(source, self.initial_state(), file)
        warnings = list(result.warnings)
        for key, entry in result.state.procedures.items():
            if key not in result.state.called:
                warnings.append(
                    plan.Diagnostic(
                        f"PROC {entry.definition.name.name} is never called, so its statements "
                        "were not checked",
                        entry.definition.name.span,
                    )
                )
        if not source.strip():
            warnings.append(plan.Diagnostic("the program is empty", Span(file, 1, 1, 1, 1)))
        warnings.sort(key=lambda w: (w.span.line, w.span.column))
        return plan.Plan(file=file, source=source, steps=result.steps, warnings=tuple(warnings))


def _poison(statement: ast.Statement, state: CompileState) -> CompileState:
    """After a failed definition, mark the name so later uses are not reported again."""
    if isinstance(statement, _DEFINITIONS):
        kind = BindingKind.LET if isinstance(statement, ast.Let) else BindingKind.FRAME
        return state.bind(statement.name.key, Binding(None, kind, statement.name.span))
    return state


def compile_program(
    source: str,
    file: str = "<input>",
    fixtures: Mapping[str, FrameLike] | None = None,
    defaults: Defaults | None = None,
) -> plan.Plan:
    """Parse, check and compile a program to a plan.

    Args:
        source: The program text.
        file: The name errors and spans carry.
        fixtures: Predefined frames by name (see :class:`Compiler`).
        defaults: Values used where the program does not give one.

    Raises:
        ProgramError: Syntax or check errors, with spans and the source attached.
    """
    return Compiler(fixtures, defaults).compile_program(source, file)
