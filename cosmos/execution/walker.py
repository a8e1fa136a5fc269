"""Walks a plan with branches: the steps to run next, chosen at run time.

The executor runs statements (a statement's segments) and scene changes; the
walker hands them to it in order and decides the plan's other nodes when it
reaches them:

- an IF (:class:`~cosmos.plan.Branch`) reads its condition once, on what the
  arm senses then and on how the statement run last ended, and walks one branch;
- a WHILE (:class:`~cosmos.plan.Loop`) reads its condition before every pass,
  and fails when it still holds after its last allowed pass;
- a TRY (:class:`~cosmos.plan.Attempt`) walks its block; a statement that fails
  there (the executor has already held the arm and logged the failure) runs the
  ON FAIL part instead of ending the program; a RETRY (:class:`~cosmos.plan.Retry`)
  there walks the block again, and once its count is used up the failure ends
  the program after all.

Every decision is an event in the log (``decision``, with the values read and
the branch taken), and so is every recovery (``recovery``) and retry (``retry``).

A statement's context (:meth:`PlanWalker.context_of`) is where it came from: the
PROC calls and REPEAT passes it was compiled from, and the WHILE pass or TRY
retry the walk is in, so a failure inside one names which.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NoReturn, Protocol

import numpy as np

from cosmos.errors import TaskFailure
from cosmos.execution.wording import run_context
from cosmos.plan import (
    AddObstacle,
    AllOf,
    AnyOf,
    Attempt,
    Branch,
    Comparison,
    Condition,
    Ending,
    FloatArray,
    HandStep,
    LastOutcome,
    Loop,
    Quantity,
    RemoveObstacle,
    Retry,
    Segment,
    Step,
)


@dataclass(frozen=True, eq=False)
class Senses:
    """What a decision reads, measured when it is reached.

    Attributes:
        force_world: Force the tool applies to the environment [N], world. # (3,)
        torque_world: Moment the tool applies [N m], world. # (3,)
        position_world: The tool point [m], world. # (3,)
        grip_n: The smaller of the gripper's pad forces [N] (FINGER FORCE); 0 without the gripper.
    """

    force_world: FloatArray
    torque_world: FloatArray
    position_world: FloatArray
    grip_n: float = 0.0


class HandSteps(Protocol):
    """What runs GRASP and RELEASE (:class:`cosmos.hand.grasping.Hand`)."""

    def apply(self, step: HandStep, fail: Callable[[str], None]) -> str:
        """Run the step; returns what it did. ``fail(reason)`` logs a failure and raises."""
        ...

    def grip_n(self) -> float:
        """The smaller of the pads' forces as their sensors read them now [N] (FINGER FORCE)."""
        ...


class _NoHand:
    """The hand of a workcell without the gripper: every hand step fails."""

    def apply(self, step: HandStep, fail: Callable[[str], None]) -> str:
        fail("needs the gripper: this run's tool is the peg (TOOL GRIPPER)")
        raise AssertionError  # fail() raises

    def grip_n(self) -> float:
        return 0.0  # no pads (the compiler refuses FINGER FORCE without TOOL GRIPPER)


NO_HAND: HandSteps = _NoHand()


class StepRunner(Protocol):
    """What the walker needs of the executor."""

    hand: HandSteps

    def run_statement(self, segments: list[Segment]) -> bool:
        """Run one statement's segments; True when its UNTIL ended it.

        Raises:
            TaskFailure: It failed (the arm held, the failure logged).
        """
        ...

    def scene_step(self, step: AddObstacle | RemoveObstacle) -> None:
        """Add or remove an obstacle."""
        ...

    def senses(self) -> Senses:
        """What the arm senses now."""
        ...

    def note(self, kind: str, step: Step, reason: str) -> None:
        """Write an event about ``step`` to the log."""
        ...

    def fail(self, step: Step, reason: str) -> NoReturn:
        """Log a failure of ``step``, hold the arm, and raise :class:`TaskFailure`."""
        ...

    def recoverable(self, failure: TaskFailure) -> bool:
        """Whether a TRY may take over ``failure`` (an interruption from outside may not be)."""
        ...


class _RetryRequest(Exception):
    """A RETRY reached in an ON FAIL part: run the TRY block again (caught by its Attempt)."""

    def __init__(self, step: Retry):
        super().__init__(step.statement)
        self.step = step


_UNITS = {
    Quantity.FORCE: (1.0, "N", 2),
    Quantity.FORCE_ALONG: (1.0, "N", 2),
    Quantity.TORQUE: (1.0, "N m", 2),
    Quantity.TORQUE_ABOUT: (1.0, "N m", 2),
    Quantity.POSITION_ALONG: (1e3, "mm", 1),
    Quantity.DISTANCE_FROM: (1e3, "mm", 1),
    Quantity.FINGER_FORCE: (1.0, "N", 2),
}
"""How a value read is written in the log: scale from SI, unit, and decimals (as the
other reasons write forces and distances: ``read -10.09 N``, ``read 24.8 mm``)."""
_ENDED = {None: "was done", Ending.FAILED: "failed", Ending.STOPPED: "ended on its UNTIL"}


class PlanWalker:
    """Walks the steps of one plan, deciding its branches as it reaches them.

    Args:
        runner: The executor.

    Attributes:
        last: How the motion statement run last ended: ``FAILED``, ``STOPPED``
            (its UNTIL held), or None (it was done, or none has run).
    """

    def __init__(self, runner: StepRunner):
        self.runner = runner
        self.last: Ending | None = None
        self.frames: list[tuple[str, str]] = []
        """The WHILE passes and TRY retries being walked, outermost first: (its step's context, its text)."""

    def context_of(self, step: Step) -> str:
        """Where ``step`` came from: ``"REPEAT pass 2 of 2 at line 6; PROC probe called at line 7"``."""
        return run_context(getattr(step, "context", ""), self.frames)  # scene and hand steps have none

    def _walk_in(self, step: Loop | Attempt, text: str, steps: tuple[Step, ...]) -> None:
        """Walk ``steps`` as a pass of ``step`` (``text``: ``"WHILE pass 2 at line 6"``)."""
        self.frames.append((step.context, text))
        try:
            self.walk(steps)
        finally:
            self.frames.pop()

    def walk(self, steps: tuple[Step, ...]) -> None:
        """Run ``steps`` in order, deciding each IF, WHILE and TRY when it is reached.

        Raises:
            TaskFailure: A statement failed outside any TRY (or its TRY's retries ran out).
        """
        for group in statement_groups(steps):
            if isinstance(group, list):
                try:
                    stopped = self.runner.run_statement(group)
                except TaskFailure:
                    self.last = Ending.FAILED
                    raise
                self.last = Ending.STOPPED if stopped else None
            elif isinstance(group, AddObstacle | RemoveObstacle):
                self.runner.scene_step(group)
            elif isinstance(group, HandStep):
                self._hand(group)
            elif isinstance(group, Branch):
                self._branch(group)
            elif isinstance(group, Loop):
                self._loop(group)
            elif isinstance(group, Attempt):
                self._attempt(group)
            else:
                raise _RetryRequest(group)

    def _hand(self, step: HandStep) -> None:
        runner = self.runner
        runner.note("start", step, "")
        done = runner.hand.apply(step, lambda reason: runner.fail(step, reason))
        runner.note("done", step, done)

    def _branch(self, step: Branch) -> None:
        holds, read = self.decide(step.condition)
        if holds:
            first = f"line {step.then_steps[0].line}" if step.then_steps else "empty"
            taken = f"runs the IF branch ({first})"
        elif step.else_line is not None:
            taken = f"runs the ELSE branch (line {step.else_line})"
        else:
            taken = "runs nothing (no ELSE)"
        self.runner.note("decision", step, f"{read}; {'holds' if holds else 'does not hold'}: {taken}")
        self.walk(step.then_steps if holds else step.else_steps)

    def _loop(self, step: Loop) -> None:
        passes = 0
        while True:
            holds, read = self.decide(step.condition)
            if not holds:
                said = f"{passes} pass" + ("" if passes == 1 else "es")
                self.runner.note("decision", step, f"{read}; does not hold: ends after {said}")
                return
            if passes == step.max_passes:
                self.runner.note("decision", step, f"{read}; holds after {passes} passes")
                self.runner.fail(step, f"still holds after {passes} passes (MAX {step.max_passes}): {read}")
            passes += 1
            self.runner.note("decision", step, f"{read}; holds: pass {passes}")
            self._walk_in(step, f"WHILE pass {passes} at line {step.line}", step.body)

    def _attempt(self, step: Attempt) -> None:
        retries, times = 0, 0
        while True:
            try:
                if retries:
                    self._walk_in(step, f"TRY retry {retries} of {times} at line {step.line}", step.body)
                else:
                    self.walk(step.body)
                return
            except TaskFailure as failure:
                if not self.runner.recoverable(failure):
                    raise
                last_failure = failure
                self.last = Ending.FAILED  # a WHILE past its MAX or a used-up RETRY failed too
            self.runner.note(
                "recovery", step, f"ON FAIL (line {step.handler_line}) takes over: {last_failure.message}"
            )
            try:
                self.walk(step.handler)
                return
            except _RetryRequest as request:
                retry = request.step
                if retries >= retry.times:
                    self.runner.fail(
                        retry,
                        f"ran out: the TRY block (line {step.line}) failed again after {retries} "
                        f"retr{'y' if retries == 1 else 'ies'}: {last_failure.message}",
                    )
                retries, times = retries + 1, retry.times
                self.runner.note(
                    "retry",
                    retry,
                    f"runs the TRY block (line {step.line}) again: retry {retries} of {retry.times}",
                )

    # ------------------------------------------------------------- reading

    def decide(self, condition: Condition) -> tuple[bool, str]:
        """Whether ``condition`` holds now, and what was read (``"FORCE Z < -5 N: FORCE Z = -9.8 N"``)."""
        senses = self.runner.senses()
        readings: list[str] = []
        holds = _holds(condition, senses, self.last, readings)
        return holds, "; ".join(readings)


def _holds(condition: Condition, senses: Senses, last: Ending | None, readings: list[str]) -> bool:
    """Evaluate ``condition`` (every term, so each value read is logged), appending what it read."""
    if isinstance(condition, AllOf):
        return all([_holds(term, senses, last, readings) for term in condition.terms])
    if isinstance(condition, AnyOf):
        return any([_holds(term, senses, last, readings) for term in condition.terms])
    if isinstance(condition, LastOutcome):
        readings.append(f"{condition.text}: the last statement {_ENDED[last]}")
        return last is condition.ending
    measured = measure(condition, senses)
    scale, unit, decimals = _UNITS.get(condition.quantity, (1.0, "", 3))
    readings.append(f"{condition.text}: read {measured * scale:.{decimals}f} {unit}".rstrip())
    return condition.op.holds(measured, condition.value)


def measure(comparison: Comparison, senses: Senses) -> float:
    """The value a decision's comparison reads, in SI (N, N m, m)."""
    quantity = comparison.quantity
    if quantity is Quantity.FINGER_FORCE:
        return senses.grip_n
    if quantity is Quantity.FORCE:
        return float(np.linalg.norm(senses.force_world))
    if quantity is Quantity.TORQUE:
        return float(np.linalg.norm(senses.torque_world))
    if quantity is Quantity.FORCE_ALONG:
        return float(np.dot(senses.force_world, comparison.direction_world))  # type: ignore[arg-type]
    if quantity is Quantity.TORQUE_ABOUT:
        return float(np.dot(senses.torque_world, comparison.direction_world))  # type: ignore[arg-type]
    offset = senses.position_world - comparison.origin_world  # type: ignore[operator]
    if quantity is Quantity.POSITION_ALONG:
        return float(np.dot(offset, comparison.direction_world))  # type: ignore[arg-type]
    if quantity is Quantity.DISTANCE_FROM:
        return float(np.linalg.norm(offset))
    raise ValueError(f"a decision cannot read {quantity.value}")  # DISTANCE travelled: UNTIL only


def statement_groups(
    steps: tuple[Step, ...],
) -> list[list[Segment] | AddObstacle | RemoveObstacle | HandStep | Branch | Loop | Attempt | Retry]:
    """Steps grouped into statements: consecutive segments sharing a statement index."""
    groups: list[
        list[Segment] | AddObstacle | RemoveObstacle | HandStep | Branch | Loop | Attempt | Retry
    ] = []
    for step in steps:
        if not isinstance(step, Segment):
            groups.append(step)
        elif (
            groups and isinstance(groups[-1], list) and groups[-1][0].statement_index == step.statement_index
        ):
            groups[-1].append(step)
        else:
            groups.append([step])
    return groups
