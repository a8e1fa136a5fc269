"""The integral actions on the translation error (cosmos/osc/integral_action.py), against worked steps."""

from __future__ import annotations

import numpy as np

from cosmos.osc.integral_action import integrate_goal_error, integrate_motion_error

DT_S = 1e-3
FREE = np.zeros((6, 6))  # no force-controlled axis
PRESSED_Z = np.diag((0.0, 0.0, 1.0, 0.0, 0.0, 0.0))  # a slide pressing along z


def test_slide_integral_drops_its_part_pushing_the_tool_past_its_goal() -> None:
    """Short of the goal along +x (e_x < 0) the integral grows negative (F* gains +x); once the tool
    has passed the goal (e_x > 0) the integral's part along the error is dropped before this step
    adds ``e dt``, its part across kept. Catches the windup that carried a slide 1.2 mm past its goal,
    where friction held it (an integral that only unwinds at ``e dt`` a tick)."""
    short = integrate_motion_error(np.zeros(3), np.array((-2e-3, 0, 5e-3, 0, 0, 0)), PRESSED_Z, DT_S, 1.0)
    np.testing.assert_allclose(short, (-2e-6, 0.0, 0.0))  # the pressed axis z left out
    wound = np.array((-1e-3, 2e-4, 0.0))
    past = integrate_motion_error(wound, np.array((1e-3, 0, 0, 0, 0, 0)), PRESSED_Z, DT_S, 1.0)
    np.testing.assert_allclose(past, (1e-6, 2e-4, 0.0))
    still_short = integrate_motion_error(wound, np.array((-1e-3, 0, 0, 0, 0, 0)), PRESSED_Z, DT_S, 1.0)
    np.testing.assert_allclose(still_short, (-1e-3 - 1e-6, 2e-4, 0.0))
    clamped = integrate_motion_error(wound, np.array((-1e-3, 0, 0, 0, 0, 0)), PRESSED_Z, DT_S, 1e-3)
    np.testing.assert_allclose(clamped, (-1e-3, 2e-4, 0.0))


def test_goal_integral_grows_only_near_slow_and_free() -> None:
    """``e dt`` within the band, below the speed and the push; held (not reset) outside any of them.
    Catches an integral that winds up on a motion's own approach (fast, or far) or against something
    in the way, and one that forgets what it built when the tool starts to move."""
    gate = (1e-3, 3e-3, 5e-3, 2.0)  # limit [m s], band [m], slow [m/s], quiet [N]
    held = np.array((1e-4, -2e-4, 0.0))
    error = np.array((1e-3, 0.0, -5e-4, 0.0, 0.0, 0.0))
    rest, push = np.zeros(6), np.zeros(6)
    np.testing.assert_allclose(
        integrate_goal_error(held, error, rest, push, DT_S, gate), held + error[:3] * DT_S
    )
    moving = np.array((0.0, 6e-3, 0.0, 0.0, 0.0, 0.0))
    far = np.array((4e-3, 0.0, 0.0, 0.0, 0.0, 0.0))
    pushing = np.array((0.0, 0.0, 2.5, 0.0, 0.0, 0.0))
    for args in ((error, moving, push), (far, rest, push), (error, rest, pushing)):
        np.testing.assert_array_equal(integrate_goal_error(held, *args, DT_S, gate), held)
    np.testing.assert_allclose(
        integrate_goal_error(held, error, rest, push, 10.0, gate), (1e-3, -2e-4, -1e-3)
    )


def test_goal_integral_waits_for_eq_21s_limit_to_let_go() -> None:
    """Within the band but where eq. 21's limit still binds (farther than ``V_max kv / kp``) the
    integral is held. Catches a slow MOVE's cruise winding it up: at 2 mm/s (eq. 20-21 among
    obstacles) its last 3 mm built 1.4 m/s^2 of push, frozen once the tool ran past the goal faster
    than 5 mm/s, and the tool went on 44 mm beyond its goal at 23 mm/s (a MOVE BY 10 mm)."""
    gate = (1e-3, 3e-3, 5e-3, 2.0)
    held = np.zeros(3)
    error = np.array((0.0, -2e-3, 0.0, 0.0, 0.0, 0.0))  # 2 mm short, moving at its 2 mm/s
    cruising = np.array((0.0, 2e-3, 0.0, 0.0, 0.0, 0.0))
    reach = 2e-3 * 40.0 / 400.0  # V_max kv / kp: 0.2 mm
    np.testing.assert_array_equal(
        integrate_goal_error(held, error, cruising, np.zeros(6), DT_S, gate, reach), held
    )
    close = np.array((0.0, -1e-4, 0.0, 0.0, 0.0, 0.0))
    np.testing.assert_allclose(
        integrate_goal_error(held, close, cruising, np.zeros(6), DT_S, gate, reach), close[:3] * DT_S
    )
