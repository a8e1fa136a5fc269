"""Syntax tree to plan: the statement-by-statement compiler.

:class:`Compiler` turns statements into plan steps while threading a
:class:`~cosmos.lang.compile.state.CompileState` through them: the default
speed, the COMPLY settings, the held contact, names, procedures and obstacles.
One pass over a text is :mod:`cosmos.lang.compile.statement_pass`, which hands
each statement to its handler. This module collects errors and holds the
public entry points.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from cosmos import plan
from cosmos.capabilities import HOME_TOOLS
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.check import limits
from cosmos.lang.compile.context import statement_text as statement_text  # public here, as before
from cosmos.lang.compile.state import CompileState, Defaults, FrameLike, frozen_map
from cosmos.lang.compile.statement_pass import StatementPass
from cosmos.lang.evaluate.values import Binding, BindingKind, FrameValue, SuppressedError
from cosmos.lang.parse.parser import parse_program
from cosmos.robots import ROBOTS, robot_named
from cosmos.rotations import IDENTITY, readonly

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


class Compiler:
    """Compiles statements to plan steps against a workcell's fixture frames.

    Args:
        fixtures: Predefined frames by name (``cosmos.workcell.fixture_frames()``):
            each has ``position`` (3,) [m, world] and ``rotation`` (3, 3). ``world``
            (the world frame) is always defined.
        defaults: Values used where a program does not give one.
        robot: The arm of the run when chosen outside the program (``cosmos run --robot``,
            the REPL's session): a ROBOT statement must name it. None: the program's ROBOT
            chooses, the PUMA 560 without one.
    """

    def __init__(
        self,
        fixtures: Mapping[str, FrameLike] | None = None,
        defaults: Defaults | None = None,
        robot: str | None = None,
    ):
        self.defaults = defaults or Defaults()
        self.robot = robot
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

    def _pass(self, source: str) -> StatementPass:
        return StatementPass(self.defaults, self._fixture_names, self.lines_of, source)

    def initial_state(self) -> CompileState:
        """The state at the start of a program: home pose, no names but the fixtures."""
        state = CompileState(default_speed_mps=self.defaults.speed_mps, names=self._fixture_names)
        if self.robot is not None:
            state = replace(state, robot=robot_named(self.robot).name, robot_fixed=True)
        return state

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
        run = self._pass(source)
        new_state = run.top_level(statement, state)
        return StatementResult(tuple(run.steps), new_state, tuple(run.warnings))

    def compile_text(self, text: str, state: CompileState, file: str = "<repl>") -> StatementResult:
        """Parse and compile a piece of program (a REPL input), continuing from ``state``.

        Raises:
            ProgramError: A syntax or check error (all errors, as :class:`ProgramErrors`).
        """
        program = parse_program(text, file)
        run = self._pass(text)  # one pass: a failed statement's steps and warnings are dropped
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
        return StatementResult(tuple(run.steps), state, tuple(run.warnings))

    def compile_program(self, source: str, file: str = "<input>") -> plan.Plan:
        """Parse, check and compile a whole program.

        Raises:
            ProgramError: Syntax or check errors (several as :class:`ProgramErrors`).
        """
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
        robot = result.state.robot
        infeasible = limits.first_infeasible_timed_move(
            result.steps, ROBOTS[robot].capability, HOME_TOOLS[(robot, result.state.tool)]
        )
        if infeasible is not None:
            raise ProgramError(*infeasible).with_source(source)
        return plan.Plan(
            file=file,
            source=source,
            steps=result.steps,
            warnings=tuple(warnings),
            robot=robot,
            tool=result.state.tool,
            objects=result.state.objects,
        )


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
    robot: str | None = None,
) -> plan.Plan:
    """Parse, check and compile a program to a plan.

    Args:
        source: The program text.
        file: The name errors and spans carry.
        fixtures: Predefined frames by name (see :class:`Compiler`).
        defaults: Values used where the program does not give one.
        robot: The run's arm if chosen outside the program (see :class:`Compiler`).

    Raises:
        ProgramError: Syntax or check errors, with spans and the source attached.
    """
    return Compiler(fixtures, defaults, robot).compile_program(source, file)
