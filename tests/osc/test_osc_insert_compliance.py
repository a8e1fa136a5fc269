"""An INSERT's compliant axes by depth (cosmos.osc.tilt_window.insert_compliance).

Checked against geometry computed independently of the law (a rotation applied to the peg's
axis with SciPy, Whitney's wedging bound ``c / mu``), without the simulator.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cosmos.osc.tilt_window import insert_compliance, tilt_window
from cosmos.runtime.servo_gains import ServoGains

PARAMS = np.array(ServoGains().insert_compliance)
WINDOW_RAD, RATE, ENTRY_M, ALIGNED_RAD, ALIGNING_RATE, SHARE, SLIDE_MPS = PARAMS
STILL = np.zeros(6)
PUSH_N = 12.0
DOWN = np.array([0.0, 0.0, -1.0])
FORCE_GOAL = np.concatenate((PUSH_N * DOWN, np.zeros(3)))
LATERAL = np.diag([1.0, 1.0, 0.0, 0.0, 0.0, 0.0])
"""Omega_bar of ``INSERT DOWN`` with X Y compliant: the force axes X Y Z (the rotations admit)."""
FORCE_AXES = np.diag([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])


def tilted(rotvec: np.ndarray) -> np.ndarray:
    """The pose error of a tool turned by ``rotvec`` from its start, the tool point still. # (6,)."""
    return np.concatenate((np.zeros(3), rotvec))


def at_depth(depth_m: float) -> np.ndarray:
    """``x - x_d`` of a tool ``depth_m`` along the push from the INSERT's start. # (6,)."""
    return np.concatenate((depth_m * DOWN, np.zeros(3)))


@pytest.mark.parametrize("seed", range(5))
def test_the_push_across_goes_where_the_peg_leans(seed: int) -> None:
    """Short of the mouth, a peg tipped by ``theta`` and pressing at its FORCE is pushed across
    the insertion toward where its upper end went: SciPy turns the peg's axis (tip to flange,
    up) and the flange's displacement gives the direction. Catches the push pointing away from
    the hole (a sign) or along the insertion; its size is ``s |F_d|`` from the window on,
    ``s |F_d| theta/theta_w`` within it."""
    rng = np.random.default_rng(seed)
    heading = rng.uniform(0.0, 2.0 * np.pi)
    for angle in (0.3 * WINDOW_RAD, WINDOW_RAD, 1.2 * WINDOW_RAD):
        rotvec = angle * np.array([np.cos(heading), np.sin(heading), 0.0])
        _, slide = insert_compliance(
            np.zeros(6), tilted(rotvec), at_depth(0.0), STILL, FORCE_GOAL, FORCE_GOAL, FORCE_AXES, PARAMS
        )
        flange = Rotation.from_rotvec(rotvec).apply(-DOWN) - (-DOWN)  # where the peg's top went
        lean = flange[:2] / np.linalg.norm(flange[:2])
        assert slide[2] == pytest.approx(0.0, abs=1e-12) and not slide[3:].any()
        assert slide[:2] / np.linalg.norm(slide[:2]) == pytest.approx(lean, abs=1e-9)
        size = SHARE * PUSH_N * min(1.0, angle / WINDOW_RAD)
        assert np.linalg.norm(slide) == pytest.approx(size, rel=1e-9)


def test_the_push_across_is_on_force_axes_only() -> None:
    """With the translations across held stiff (``COMPLY RX RY``: not force axes) nothing is
    pushed across: the push is Omega_bar's. Catches a lateral force fed to motion axes."""
    rotvec = np.array([0.1, 0.05, 0.0])
    only_z = np.diag([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    _, slide = insert_compliance(
        np.zeros(6), tilted(rotvec), at_depth(0.0), STILL, FORCE_GOAL, FORCE_GOAL, only_z, PARAMS
    )
    assert not slide.any()


def test_in_the_mouth_the_window_closes_under_whitneys_bound() -> None:
    """From ``d_in`` on, the push across ends and the window is ``theta_in``: within half a
    degree (the controller's error in the tool's orientation) of Whitney's wedging bound
    ``c / mu`` for the shipped fit (0.24 mm clearance on 20.065 mm, steel 0.45), and under
    the tilt at which the 45 deg chamfers lock on the sweeps' roughest steel (0.8):
    a peg tipped 10 deg is turned back, whatever the contact's moment asks (its part tipping
    further dropped), one tipped under ``theta_in`` left to the contact. Catches the wide
    window kept in the bore (the peg wedged at 10.85 deg, 2.9 mm in) and a stop the
    admittance outruns (a held peg stayed at 5.9 deg)."""
    clearance_ratio = 0.24 / 20.065
    assert ALIGNED_RAD <= clearance_ratio / 0.45 + np.radians(0.5) + 1e-9
    assert ALIGNED_RAD < np.radians(45.0) - np.arctan(0.8)
    speed = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.0])
    deep = at_depth(ENTRY_M + 1e-4)
    wide = tilted(np.array([0.0, np.radians(10.0), 0.0]))
    got, slide = insert_compliance(speed, wide, deep, STILL, FORCE_GOAL, FORCE_GOAL, LATERAL, PARAMS)
    assert not slide.any()
    assert got == pytest.approx(tilt_window(speed, wide, ALIGNED_RAD, ALIGNING_RATE))
    assert got[4] < -ALIGNING_RATE * (np.radians(10.0) - ALIGNED_RAD) * 0.99  # turned back toward upright
    further = np.array([0.0, 0.0, 0.0, 0.1, 0.3, 0.0])  # the contact's moment tips it further over
    got, _ = insert_compliance(further, wide, deep, STILL, FORCE_GOAL, FORCE_GOAL, LATERAL, PARAMS)
    expected = -ALIGNING_RATE * (np.radians(10.0) - ALIGNED_RAD)
    assert got == pytest.approx([0.0, 0.0, 0.0, 0.1, expected, 0.0])
    small = tilted(np.array([0.5 * ALIGNED_RAD, 0.0, 0.0]))
    got, _ = insert_compliance(speed, small, deep, STILL, FORCE_GOAL, FORCE_GOAL, LATERAL, PARAMS)
    assert got == pytest.approx(speed)


def test_short_of_the_mouth_the_window_is_wide() -> None:
    """Above ``d_in`` the window is ``theta_w`` (the peg may tip its far side into the mouth):
    a 5 deg tilt is left alone. Catches the narrow window applied on the fixture's top."""
    speed = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.0])
    five = tilted(np.array([np.radians(5.0), 0.0, 0.0]))
    got, _ = insert_compliance(
        speed, five, at_depth(0.5 * ENTRY_M), STILL, FORCE_GOAL, FORCE_GOAL, LATERAL, PARAMS
    )
    assert got == pytest.approx(speed)


def test_no_push_no_change() -> None:
    """Without a push (F_d's force zero) there is no direction: the wide window, nothing across."""
    speed = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.0])
    wide = tilted(np.array([0.0, np.radians(12.0), 0.0]))
    got, slide = insert_compliance(
        speed, wide, at_depth(0.0), STILL, np.zeros(6), np.zeros(6), LATERAL, PARAMS
    )
    assert not slide.any()
    assert got == pytest.approx(tilt_window(speed, wide, WINDOW_RAD, RATE))


def test_the_push_across_follows_the_push_felt() -> None:
    """The push across is ``s`` times the push felt along the insertion (clipped to F_d): none
    over the mouth in free air (a SEARCH's tipped peg crossed the mouth at 30 mm/s and hit
    the far wall at 42 N), half at half the push, no more than ``s |F_d|`` pressing harder.
    Catches the push across applied without a contact to hold it, or a pull read as a push."""
    rotvec = np.array([0.0, WINDOW_RAD, 0.0])
    sizes = []
    for felt in (0.0, -0.5, 0.5, 2.0):
        wrench = np.concatenate((felt * PUSH_N * DOWN, np.zeros(3)))
        args = (tilted(rotvec), at_depth(0.0), STILL, FORCE_GOAL, wrench, FORCE_AXES, PARAMS)
        sizes.append(float(np.linalg.norm(insert_compliance(np.zeros(6), *args)[1])))
    assert sizes == pytest.approx([0.0, 0.0, 0.5 * SHARE * PUSH_N, SHARE * PUSH_N])


def test_the_push_across_is_held_to_its_speed() -> None:
    """The push across fades as the tool's speed toward the lean nears ``v_s`` and is off from
    it on (a SEARCH's peg pushed off the mouth's edge crossed the mouth at 25 mm/s and hit
    the far wall at 42 N); moving away from the lean, it stays whole. Catches a push that
    accelerates the tool through free air, or fades on the speed across the lean."""
    rotvec = np.array([0.0, WINDOW_RAD, 0.0])
    _, still = insert_compliance(
        np.zeros(6), tilted(rotvec), at_depth(0.0), STILL, FORCE_GOAL, FORCE_GOAL, FORCE_AXES, PARAMS
    )
    lean = still[:3] / np.linalg.norm(still[:3])
    across = np.cross(lean, DOWN)
    sizes = []
    for velocity in (
        0.5 * SLIDE_MPS * lean,
        SLIDE_MPS * lean,
        2 * SLIDE_MPS * lean,
        -lean * SLIDE_MPS,
        across * SLIDE_MPS,
    ):
        moving = np.concatenate((velocity, np.zeros(3)))
        args = (tilted(rotvec), at_depth(0.0), moving, FORCE_GOAL, FORCE_GOAL, FORCE_AXES, PARAMS)
        sizes.append(float(np.linalg.norm(insert_compliance(np.zeros(6), *args)[1])))
    whole = SHARE * PUSH_N
    assert sizes == pytest.approx([0.5 * whole, 0.0, 0.0, 2.0 * whole, whole])
