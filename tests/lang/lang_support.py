"""Shared helpers of the language tests: hand-written fixture frames, compiling."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos import plan
from cosmos.lang import Compiler, CompileState, compile_program

C20, S20 = math.cos(math.radians(20)), math.sin(math.radians(20))

# Fixture frames written out by hand (the workcell's values when these tests were
# written), so that these tests do not depend on the scene file.
DOWN_FACING = np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]])  # RPY (180 deg, 0, 0)
SLOPE_ROTATION = np.array([[C20, 0, -S20], [0, -1, 0], [-S20, 0, -C20]])
FIXTURE_ROTATION = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])  # Rz(90 deg)


@dataclass(frozen=True)
class Frame:
    name: str
    position: np.ndarray
    rotation: np.ndarray


FIXTURES = {
    "table": Frame("table", np.array([0.6, -0.15, 0.2]), DOWN_FACING),
    "hole": Frame("hole", np.array([0.6, 0.15, 0.26]), DOWN_FACING),
    "slope": Frame("slope", np.array([0.45, -0.4, 0.26]), SLOPE_ROTATION),
    "fixture": Frame("fixture", np.array([0.7, 0.0, 0.3]), FIXTURE_ROTATION),
}


def compile_text(source: str) -> plan.Plan:
    return compile_program(source, "test.cos", FIXTURES)


def steps_after(prelude: str, line: str) -> tuple[tuple[plan.Step, ...], tuple[plan.Diagnostic, ...]]:
    """The steps and warnings of ``line`` alone, compiled after ``prelude``."""
    compiler = Compiler(FIXTURES)
    state: CompileState = compiler.compile_text(prelude, compiler.initial_state(), "prelude.cos").state
    result = compiler.compile_text(line, state, "line.cos")
    return result.steps, result.warnings


def segments_after(prelude: str, line: str) -> list[plan.Segment]:
    steps, _ = steps_after(prelude, line)
    return [step for step in steps if isinstance(step, plan.Segment)]
