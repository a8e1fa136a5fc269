"""CONTACT and SLIDE on the table, judged from the run's own log (issue 5, "Must show").

CONTACT: the held force within 3 % of the setpoint, overshoot under 30 %, the
contact never lost once made. SLIDE 100 mm: the normal force within 15 % of the
setpoint throughout the slide, and off-path drift under 1 mm.

The force along the contact axis is the logged wrench (the force the tool
applies to the environment, world axes) projected on the approach direction:
for ``CONTACT DOWN`` that is ``-fz``, positive while the tool presses.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from run_support import ProgramRun, run_in_process, samples_of, write_program

CONTACT_FORCE_N = 10.0
"""The contact test's setpoint: the language page's own example force."""
SLIDE_FORCE_N = 20.0
"""The slide test's setpoint (see test_slide_holds_the_normal_force for why not 10 N)."""
SLIDE_SPEED_MPS = 0.02
SLIDE_DISTANCE_M = 0.100
FORCE_RAMP_S = 0.25
"""A new force setpoint ramps in from the sensed force over this time (the executor's ramp)."""

CONTACT_PROGRAM = f"""\
# touch the table, hold, then slide 100 mm along +x pressing harder
SPEED 0.25 m/s
MOVE TO table + (0, 0, 10 mm)
CONTACT DOWN FORCE {CONTACT_FORCE_N:g} N TIMEOUT 5 s
WAIT 1 s
SLIDE +X BY {SLIDE_DISTANCE_M * 1e3:g} mm FORCE {SLIDE_FORCE_N:g} N SPEED {SLIDE_SPEED_MPS * 1e3:g} mm/s
WAIT 0.3 s
MOVE BY (0, 0, 40 mm)
"""


@pytest.fixture(scope="module")
def contact_run(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """One run: CONTACT DOWN 10 N, WAIT 1 s, SLIDE +X 100 mm at 20 N, lift."""
    directory = tmp_path_factory.mktemp("contact")
    program = write_program(directory, "contact", CONTACT_PROGRAM)
    run = run_in_process(program, directory / "contact.mcap")
    assert run.returncode == 0, run.describe()
    return run


def push_along_down(run: ProgramRun) -> np.ndarray:
    """Force the tool applies along world -z [N], one per state sample."""
    return -run.log.state.wrench[:, 2]


def contact_samples(run: ProgramRun) -> tuple[np.ndarray, np.ndarray]:
    """Times and downward push from the CONTACT's touch to the end of the WAIT after it."""
    contact_line = run.line_of("CONTACT DOWN")
    wait_line = run.line_of("WAIT 1 s")
    touch = run.events("contact", contact_line)
    assert len(touch) == 1, run.describe()
    held = [s.segment for s in run.segments(line=contact_line) if s.kind != "contact_approach"]
    held += [s.segment for s in run.segments(line=wait_line)]
    state = run.log.state
    mask = samples_of(run, held) & (state.t >= touch[0].t)
    return state.t[mask], push_along_down(run)[mask]


def test_contact_holds_its_force_within_3_percent(contact_run: ProgramRun) -> None:
    """Mean of the last 0.5 s of the WAIT after CONTACT DOWN FORCE 10 N: within 3 %.

    The last half of the 1 s WAIT: the touch is then at least 1.3 s old (hold
    segment plus half the WAIT), many time constants of the force loop.
    """
    t, push = contact_samples(contact_run)
    last = t >= t[-1] - 0.5
    mean_n = float(push[last].mean())
    error = abs(mean_n - CONTACT_FORCE_N) / CONTACT_FORCE_N
    assert error <= 0.03, f"held {mean_n:.3f} N for a {CONTACT_FORCE_N:g} N setpoint ({error:.1%})"


def test_contact_overshoot_under_30_percent(contact_run: ProgramRun) -> None:
    """Peak push along the contact axis after the touch, over the hold and the WAIT: < 1.3 x setpoint."""
    t, push = contact_samples(contact_run)
    peak = float(push.max())
    overshoot = (peak - CONTACT_FORCE_N) / CONTACT_FORCE_N
    assert overshoot < 0.30, f"peak {peak:.2f} N at t = {t[push.argmax()]:.3f} s ({overshoot:.0%} over)"


def test_contact_never_lost_once_made(contact_run: ProgramRun) -> None:
    """From the first sample at which the push reaches the setpoint, it never falls to 0."""
    t, push = contact_samples(contact_run)
    reached = np.flatnonzero(push >= CONTACT_FORCE_N)
    assert reached.size, f"the push never reached {CONTACT_FORCE_N:g} N (max {push.max():.2f} N)"
    after = push[reached[0] :]
    lowest = int(after.argmin())
    assert after[lowest] > 0.0, f"contact lost at t = {t[reached[0] + lowest]:.3f} s"


def slide_samples(run: ProgramRun) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Times, positions and push during the SLIDE segment, and its force setpoint [N]."""
    slides = run.segments("slide")
    assert len(slides) == 1, run.describe()
    mask = samples_of(run, [slides[0].segment])
    state = run.log.state
    setpoint_n = -slides[0].force_setpoint[2]  # task frame = world for this slide
    return state.t[mask], state.x[mask], push_along_down(run)[mask], setpoint_n


def test_slide_holds_the_normal_force(contact_run: ProgramRun) -> None:
    """SLIDE +X BY 100 mm FORCE 20 N at 20 mm/s: issue 14's bar for a push while sliding.

    Once in contact the push never falls below half its setpoint, and stays within 15 % of
    it for 95 % of the samples. The first 0.25 s are left out: the SLIDE raises the
    setpoint from the contact's 10 N to its own 20 N over the executor's 0.25 s ramp.
    Catches a slide that loses the contact (the push dropping to 0-1 N) or presses unevenly.
    """
    t, x, push, setpoint_n = slide_samples(contact_run)
    assert setpoint_n == pytest.approx(SLIDE_FORCE_N)
    travelled_m = float(x[-1, 0] - x[0, 0])
    assert travelled_m == pytest.approx(SLIDE_DISTANCE_M, abs=1.5e-3)
    judged = t >= t[0] + FORCE_RAMP_S
    _assert_push_held(t[judged], push[judged], setpoint_n)


def test_slide_stays_on_its_path(contact_run: ProgramRun) -> None:
    """Off-path drift (world y, across the +x slide, in the table plane) under 1 mm."""
    _, x, _, _ = slide_samples(contact_run)
    drift_m = float(np.abs(x[:, 1] - x[0, 1]).max())
    assert drift_m < 1e-3, f"drift {drift_m * 1e3:.3f} mm"


def test_shipped_contact_slide_holds_10_n(shipped_run: Callable[[str], ProgramRun]) -> None:
    """programs/contact_slide.cos (10 N, 10 mm/s): the push held to issue 14's bar."""
    _assert_push_in_band(shipped_run("contact_slide.cos"))


FAST_LIGHT_SLIDE = """\
SPEED 0.2 m/s
MOVE TO table + (-50 mm, 0, 60 mm)
CONTACT DOWN FORCE 10 N SPEED 20 mm/s TIMEOUT 5 s
SLIDE +X BY 100 mm SPEED 20 mm/s
"""


def test_light_fast_slide_holds_10_n(tmp_path: Path) -> None:
    """SLIDE at 10 N and 20 mm/s: the push held to issue 14's bar (item 5).

    Catches the tool contact creeping out of the table while it slides (the pyramidal
    friction cone's damping lifted the tip: push 0.2 N for milliseconds every 0.1-0.2 s).
    """
    program = write_program(tmp_path, "fast_light_slide", FAST_LIGHT_SLIDE)
    run = run_in_process(program, tmp_path / "fast_light_slide.mcap")
    assert run.returncode == 0, run.describe()
    _assert_push_in_band(run)


def _assert_push_in_band(run: ProgramRun) -> None:
    t, _, push, setpoint_n = slide_samples(run)
    judged = t >= t[0] + FORCE_RAMP_S  # the SLIDE's own force ramp first
    _assert_push_held(t[judged], push[judged], setpoint_n)


def _assert_push_held(t: np.ndarray, push: np.ndarray, setpoint_n: float) -> None:
    """Issue 14, item 5: never below 50 % of the setpoint, within 15 % of it for 95 % of samples."""
    lowest = int(push.argmin())
    assert push[lowest] >= 0.5 * setpoint_n, (
        f"push fell to {push[lowest]:.2f} N at t = {t[lowest]:.3f} s (setpoint {setpoint_n:g} N)"
    )
    error = np.abs(push - setpoint_n) / setpoint_n
    assert np.mean(error <= 0.15) >= 0.95, (
        f"{np.mean(error <= 0.15):.1%} of the slide within 15 % of {setpoint_n:g} N "
        f"(worst {push[int(error.argmax())]:.2f} N at t = {t[int(error.argmax())]:.3f} s)"
    )


def test_contact_program_file_is_kept(contact_run: ProgramRun) -> None:
    """The log carries the program's source as its attachment (what was run is on record)."""
    assert contact_run.log.source == Path(contact_run.program).read_text(encoding="utf-8")


def test_a_first_statement_s_contact_feels_nothing_in_the_air(tmp_path: Path) -> None:
    """Catches the first tick reading the tool weightless (the plant reset with its drives off):
    a program (or a REPL session) whose first statement was CONTACT DOWN "touched: 2.17 N along
    the approach" at t = 0.001 s, 260 mm above the table, then pushed down in the air under force
    control until its 3 s ran out. It must find nothing within its TIMEOUT."""
    program = write_program(tmp_path, "first", "CONTACT DOWN FORCE 5 N TIMEOUT 0.3 s\n")
    run = run_in_process(program, tmp_path / "first.mcap")
    assert run.returncode == 1
    assert not run.events("contact"), run.describe()
    (failed,) = run.events("failed")
    assert failed.reason == "found no contact within 0.3 s", run.describe()
