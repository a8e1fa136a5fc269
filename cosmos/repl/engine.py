"""The REPL's core: compile what is typed against the session's state and run it on the arm.

No terminal here: :class:`ReplEngine` takes a text (one input: a statement, a
few separated by ``;`` or new lines, or a whole PROC ... END) and reports
through a :class:`~cosmos.repl.output.Printer`.

An input is parsed and checked whole before anything moves; then its top-level
statements run one after the other, and the compile state (names, frames,
procedures, COMPLY, SPEED, the held contact, obstacles) advances with each one
that finishes. When a statement fails or is interrupted the executor leaves the
arm holding its pose under position control, so the state is corrected to
match: no contact held, and only the obstacles that were really added.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from cosmos.errors import CosmosError, ProgramError, Span, UsageError
from cosmos.execution.executor import Executor, Interrupted
from cosmos.execution.session import Session
from cosmos.execution.wording import statement_head
from cosmos.hand.tool import Tool
from cosmos.hand.work_object import SHIPPED_OBJECTS
from cosmos.lang import Compiler, StatementResult, ast, parse_program, read_program
from cosmos.lang.compile.state import CompileState, frozen_map
from cosmos.lang.parse.source_file import check_typed_text
from cosmos.plan import Diagnostic, Plan, RemoveObstacle, Segment, Step
from cosmos.repl.names import changed_names, describe_value
from cosmos.repl.output import Printer, Tone
from cosmos.repl.progress import StatementProgress
from cosmos.repl.statements import (
    REPL_FILE,
    LoadedFile,
    normalise_newlines,
    state_after_failure,
    statement_groups,
)
from cosmos.repl.status import ArmStatus
from cosmos.repl.transcript import Transcript
from cosmos.workcell import fixture_frames

RESET_HOLD_S = 0.05
"""After ``:reset`` the arm holds at home this long, logged as a segment [s]."""


class ReplEngine:
    """Compiles and runs inputs on one live session, keeping the state between them.

    Args:
        session: The arm, its executor and its log.
        printer: Where results and errors go.
        show_progress: Show a status line (statement, simulated time) while the arm moves.
    """

    def __init__(self, session: Session, printer: Printer, show_progress: bool = False):
        self.session = session
        self.printer = printer
        self.show_progress = show_progress
        # The session's arm is chosen: a ROBOT input must name it.
        self.compiler = Compiler(fixture_frames(session.robot), robot=session.robot.name)
        self.state = self.compiler.initial_state()
        if session.tool is Tool.GRIPPER:  # its workcell as TOOL GRIPPER makes it in a program
            self.state = dataclasses.replace(self.state, tool=session.tool.value, objects=SHIPPED_OBJECTS)
        self.transcript = Transcript()

    @property
    def executor(self) -> Executor:
        """The session's executor."""
        return self.session.executor

    def status(self) -> ArmStatus:
        """The arm as sensed now."""
        return ArmStatus.of(self.session.runtime)

    def interrupt(self) -> None:
        """Ask the running statement to stop and hold (safe from a signal handler or thread)."""
        self.executor.stop_requested = True

    # ------------------------------------------------------------- inputs

    def submit(self, text: str) -> bool:
        """Compile and run one input typed at the prompt; False if it failed."""
        text = normalise_newlines(text)
        if not text.strip():
            return True
        self.executor.stop_requested = False
        source = self.transcript.placed(text)
        try:
            check_typed_text(text, REPL_FILE, self.transcript.line_count + 1)
            results = self._compile(source, REPL_FILE)
        except ProgramError as error:
            self.transcript.add_rejected(text)
            self.printer.write(error.render(), Tone.ERROR)
            return False
        self.transcript.add_statements(text)
        return self._execute(results, source)

    def load(self, path: Path) -> bool:
        """``:load FILE``: check the whole file, then run it into the session; False if it failed.

        The file's text joins the transcript (after a ``# :load FILE`` line), so
        the log's line numbers stay those of the transcript; messages point into
        the file.
        """
        self.transcript.add_command(f":load {path}")
        self.executor.stop_requested = False
        try:
            text = read_program_file(path)
            self._compile(text, str(path))  # errors and warnings point into the file
            loaded = LoadedFile(path, text, self.transcript.line_count + 1)
            source = self.transcript.placed(text)
            results = self._compile(source, REPL_FILE, warn=False)
        except CosmosError as error:
            self.printer.write(error.render(), Tone.ERROR)
            return False
        self.transcript.add_statements(text)
        return self._execute(results, source, loaded)

    def _compile(self, source: str, file: str, warn: bool = True) -> list[StatementResult]:
        """Parse and check a whole input, statement by statement; print its warnings.

        A PROC typed again replaces the earlier one (the compiler refuses a second
        definition within one program; a session is not one program).

        Raises:
            ProgramError: Every syntax and check error of the input.
        """
        program = parse_program(source, file)
        start = self.state
        redefined = {s.name.key for s in program.statements if isinstance(s, ast.ProcDef)}
        if redefined & set(start.procedures):
            kept = {k: v for k, v in start.procedures.items() if k not in redefined}
            start = dataclasses.replace(start, procedures=frozen_map(kept))
        results: list[StatementResult] = []
        state = start
        try:
            for statement in program.statements:
                result = self.compiler.compile_statement(statement, state, source)
                self._fixed_workcell(state, result.state, statement.span)
                results.append(result)
                state = result.state
        except ProgramError:
            self.compiler.compile_text(source, start, file)  # raises every error of the input
            raise
        for result in results if warn else ():
            self._warn(result.warnings, source)
        return results

    def _fixed_workcell(self, before: CompileState, after: CompileState, span: Span) -> None:
        """The session's plant was built when it started: TOOL and OBJECT cannot change it.

        Raises:
            ProgramError: At a TOOL that names another hand, or an OBJECT.
        """
        if after.tool != before.tool:
            raise ProgramError(
                f"TOOL must be chosen when the session starts: cosmos repl --tool {after.tool} "
                f"(this session's hand is the {before.tool})",
                span,
            )
        if after.objects != before.objects:
            raise ProgramError(
                "OBJECT declares the workcell a run starts with, and this session's was built when it "
                "started; declare it in a program and cosmos run it",
                span,
            )

    def _warn(self, warnings: tuple[Diagnostic, ...], source: str) -> None:
        for warning in warnings:
            self.printer.write(warning.render(source), Tone.WARNING)

    # ---------------------------------------------------------- execution

    def _execute(self, results: list[StatementResult], source: str, loaded: LoadedFile | None = None) -> bool:
        """Run each statement's steps in turn, advancing the state as each one finishes."""
        for result in results:
            before = self.state
            executed: list[Step] = []
            try:
                for group in statement_groups(result.steps):
                    self._run_group(group, source)
                    executed.extend(group)
            except CosmosError as error:
                self.state = state_after_failure(before, result.state, executed, error.span)
                self.printer.write(error.render() if loaded is None else loaded.render(error), Tone.ERROR)
                self.printer.write("the arm holds its pose", Tone.NOTE)
                return False
            self.state = result.state
            for key in changed_names(before.names, self.state.names):
                self.printer.write(f"{key} = {describe_value(self.state.names[key])}", Tone.NOTE)
            for key, entry in self.state.procedures.items():
                if before.procedures.get(key) is not entry:
                    definition = entry.definition
                    self.printer.write(
                        f"PROC {definition.name.name} defined ({_count(len(definition.body), 'statement')})",
                        Tone.NOTE,
                    )
        return True

    def _run_group(self, group: tuple[Step, ...], source: str) -> None:
        """Run one statement's steps; say how it went."""
        first = group[0]
        if self.executor.stop_requested:
            self.executor.stop_requested = False
            self.executor.hold()
            raise Interrupted(f"interrupted before {statement_head(first.statement)}", first.span, source)
        start_s = self.session.runtime.time_s
        plan = Plan(file=REPL_FILE, source=source, steps=group, warnings=())
        # A block decided on the arm (IF, WHILE, TRY) says what it read and did as it goes.
        self.executor.on_event = None if isinstance(first, Segment) else self._echo
        try:
            if self.show_progress:
                progress = StatementProgress(start_s)
                self.executor.progress = progress
                try:
                    with progress:
                        self.executor.run(plan)
                finally:
                    self.executor.progress = None
            else:
                self.executor.run(plan)
        finally:
            self.executor.on_event = None
        if isinstance(first, Segment):
            status = self.status()
            where = f" ({first.context})" if first.context else ""
            self.printer.write(
                f"ok  {first.statement}{where}  [{self.session.runtime.time_s - start_s:.2f} s, "
                f"|F| {status.force_n:.1f} N]",
                Tone.OK,
            )

    def _echo(self, kind: str, step: Step, reason: str, context: str) -> None:
        """One line for each decision, each statement ended and each recovery inside a block.

        A failure is not echoed: ON FAIL's ``recovery`` names it, or it ends the input.
        """
        where = f" ({context})" if context else ""
        if kind == "decision":
            # A decision's head is its keyword (IF, WHILE); its reason reads on with the condition.
            self.printer.write(f"{statement_head(step.statement).upper()}{where} {reason}", Tone.NOTE)
        elif kind in ("done", "stopped"):
            said = f"  {reason}" if reason else ""
            self.printer.write(f"ok  {step.statement}{where}{said}", Tone.OK)
        elif kind in ("recovery", "retry"):
            self.printer.write(reason, Tone.NOTE)

    # -------------------------------------------------------------- reset

    def reset(self) -> None:
        """``:reset``: obstacles removed, the arm put back home at rest, the compile state reset.

        The simulated clock goes on, so the log stays in time order; the reset is
        logged as a short hold segment whose statement is ``:reset``.
        """
        self.transcript.add_command(":reset")
        line = self.transcript.line_count
        source = self.transcript.text()
        span = Span(REPL_FILE, line, 1, line, len(":reset") + 1)
        removals = tuple(
            RemoveObstacle(name=key, span=span, line=line, statement=f"OBSTACLE REMOVE {key}")
            for key in self.state.obstacles
        )
        if removals:
            try:
                self.executor.run(Plan(REPL_FILE, source, removals, ()))
            except CosmosError as error:
                self.printer.write(error.render(), Tone.WARNING)
        plant = self.session.plant
        now_s = plant.time_s
        plant.reset()  # the home keyframe, HOME_Q
        plant.data.time = now_s
        self.session.runtime.reset_clocks()
        self.executor.hold()
        self.state = self.compiler.initial_state()
        hold = self.compiler.compile_text(f"WAIT {RESET_HOLD_S} s", self.state, REPL_FILE).steps[0]
        assert isinstance(hold, Segment)  # a WAIT compiles to one segment
        hold = dataclasses.replace(hold, statement=":reset", span=span, line=line)
        self.executor.run(Plan(REPL_FILE, source, (hold,), ()))
        self.printer.write("the arm is home; names, frames, procedures and settings are reset", Tone.OK)


def read_program_file(path: Path) -> str:
    """The text of a file given to ``:load``, read as ``cosmos check`` reads it.

    A file that is not a program shows none of its content (``:load /etc/passwd``
    must not print a line of it): bytes that are not UTF-8 text, or a file whose
    name does not end in ``.cos`` and that does not parse, are refused in one line.

    Raises:
        UsageError: The file is not a program, or cannot be read.
        ProgramError: A ``.cos`` file with a syntax error.
    """
    try:
        text = read_program(path)
    except ProgramError:
        raise UsageError(f"{path}: not UTF-8 text, so not a program file") from None
    if path.suffix.lower() != ".cos":
        try:
            parse_program(text, str(path))
        except ProgramError:
            raise UsageError(
                f"{path}: not a COSMOS program (it does not parse); a program file's name ends in .cos"
            ) from None
    return text


def _count(n: int, noun: str) -> str:
    """``1 statement``, ``2 statements``."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"
