"""Statement-by-statement compiling (the REPL): the state carries across inputs."""

from __future__ import annotations

import numpy as np
import pytest
from lang_support import FIXTURES

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import Compiler


def test_contact_names_compliance_and_procedures_carry_across_inputs() -> None:
    compiler = Compiler(FIXTURES)
    state = compiler.initial_state()
    state = compiler.compile_text("LET d = 20 mm\nCOMPLY RX STIFFNESS 3 Nm/rad", state).state
    first = compiler.compile_text("CONTACT DOWN FORCE 6 N", state)
    assert len(first.steps) == 2
    state = compiler.compile_text("PROC wipe\n  SLIDE +X BY d\nEND", first.state).state
    result = compiler.compile_text("wipe", state, "<repl>")
    [slide] = result.steps
    assert isinstance(slide, plan.Segment) and slide.kind is plan.SegmentKind.SLIDE
    np.testing.assert_allclose(slide.force_setpoint, [0, 0, -6, 0, 0, 0])
    assert slide.stiffness[3] == 3.0
    assert slide.statement == "SLIDE +X BY d"  # from the input that defined the PROC
    assert (slide.index, slide.statement_index) == (2, 1)
    assert result.state.contact is not None


def test_an_error_leaves_the_state_as_it_was() -> None:
    compiler = Compiler(FIXTURES)
    state = compiler.compile_text("CONTACT DOWN FORCE 6 N", compiler.initial_state()).state
    with pytest.raises(ProgramError, match="unknown name"):
        compiler.compile_text("MOVE TO nowhere", state)
    [slide] = compiler.compile_text("SLIDE +Y BY 5 mm", state).steps
    assert isinstance(slide, plan.Segment)


def test_error_in_a_procedure_from_an_earlier_input_shows_its_line() -> None:
    compiler = Compiler(FIXTURES)
    state = compiler.compile_text(
        "PROC wipe\n  SLIDE +X BY 5 mm\nEND", compiler.initial_state(), "<repl>"
    ).state
    with pytest.raises(ProgramError) as caught:
        compiler.compile_text("wipe", state, "<repl>")
    rendered = caught.value.render()
    assert "SLIDE +X BY 5 mm" in rendered.splitlines()[1]
    assert "(in PROC wipe called at line 1)" in rendered
