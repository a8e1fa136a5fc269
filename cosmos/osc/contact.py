"""When the servo considers the tool in contact (the two latches of a segment), and how a CONTACT lands.

Both are latched for the segment: once set they stay set until the next
segment starts, so that a bounce off the surface does not switch the control
law back and forth.

* The **touch latch** gates the force loop's integral action (eq. 17-18's
  ``k_i integral(F_d - F_s) dt``, Figure 2): in free space the force error
  cannot be closed and would wind up into an impact, so integration starts only
  once something pushes back along a force-controlled axis,
  ``max |Omega_bar F_s| > F_contact``. Until then the force command's
  acceleration counts toward the Coulomb intent (:mod:`cosmos.osc.friction`).
* The **contact latch** switches compliant moment axes from holding the
  segment's orientation to admittance control (:mod:`cosmos.osc.admittance`)
  at the first contact force of any direction, ``|f_s| > F_contact``.

The compiled kernels of :mod:`cosmos.runtime.kernels.contact` run the same
tests; these are their readable reference.

**The landing.** A CONTACT approaches with every axis motion-controlled (eq. 20-21 at its
SPEED) and switches its axis to force control (eq. 17-18, Figure 2) once the push felt along
the approach exceeds the touch threshold (2 N, or half the FORCE). On the steel contact the
switch alone comes too late: the arm's effective mass along the approach (some 40 kg with the
rotors' inertia, at the table's work point) lands with ``m v^2 / 2`` (18 mJ at 30 mm/s) that
the contact absorbs within a few tenths of a millimetre, and the sensor's reading crosses 2 N
1-5 ms after the first touch (the realistic sensor's 200 Hz filter). A 3 N CONTACT landed at
12 N at 30 mm/s and 32 N at 50 mm/s. So the approach brakes from the first push it feels,
before the threshold (:func:`touch_braking`): eq. 20-21's ``F*_m`` loses ``k_b (n^T xd - v_l) n``
along the push ``n`` it meets while the tool moves into it faster than ``v_l`` (5 mm/s), the
drives taking the momentum out. The hold then starts from a tool nearly at rest, its force reference ramped
from the sensed push to FORCE (the executor's ramp) and its integral held until the push
first reaches its goal (:func:`cosmos.osc.unified.force_goal_reached`) with the tool at rest
along it (:func:`push_landed`), or, at rest along it, once the ramp is over, short of its goal
or over it (the joints' friction would hold a light push there: 3 and 5 N CONTACTs on the
realistic plant's seed 2 never settled within 0.5 N, at 5-10 mm/s before the braking and at
every SPEED with it, where only the impact's spike had passed 90 % of the goal; and a held
block landed on another at 19 N stayed at 14 N for a 4 N CONTACT).
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray

TOUCH_BRAKING_N = 0.5
"""The push felt along a CONTACT's approach that starts its braking [N]: ten times the wrist
sensor's noise, above the free tool's inertia error in a cruise, below every touch threshold
that is not itself under 1 N."""

LANDED_SPEED_MPS = 0.005
"""A held push has landed once the tool moves along it slower than this [m/s]: above the
realistic plant's velocity noise (1-3 mm/s at rest in contact) ..."""

LANDED_PUSH = 1.1
"""... and pushes no more than this share of its goal (:func:`push_landed`)."""

TOUCH_BRAKING_N_PER_KG = 0.75
"""... and at least this much per kilogram below the sensor [N/kg]: the braking's own
deceleration, read by the sensor on a mass the commanded acceleration does not cancel, must not
pass for a push. With a gripper holding the peg (``grasp_and_insert.cos``, about 2 kg below the
sensor) an INSERT's approach braked at 0.5 N on the hand's inertia 35 ms into its descent,
read its own braking as a 2 N touch 1.6 mm above the hole, and the peg, pushed down at 20 mm/s,
jammed 8.3 mm in (seed 7 of tests/hand/test_grasp_and_insert.py). The peg tool alone (0.66 kg)
keeps 0.5 N."""

TOUCH_BRAKING_PER_S = 300.0
"""The braking's damping k_b, unit mass, at a 1 kHz servo [1/s] (``ServoGains.touch_braking``)."""

LANDING_SPEED_MPS = 0.005
"""The speed the braking leaves the tool landing at [m/s]: a landing at 5 mm/s peaked at
1.08 times FORCE at most before the braking (tests/run/contact_impact_grid.py)."""


def touch_latched(touching: bool, omega_bar: FloatArray, wrench: FloatArray, threshold_n: float) -> bool:
    """The force loop's touch latch after this tick's wrench.

    Args:
        touching: The latch before this tick.
        omega_bar: Omega_bar, the force-controlled axes (eq. 17), world. # (6, 6)
        wrench: F_s, the sensed wrench on the environment, world, [N, N m]. # (6,)
        threshold_n: F_contact, the contact threshold, in [N] (and [N m] on moment axes).

    Returns:
        ``touching or max |Omega_bar F_s| > F_contact``.
    """
    return touching or float(np.max(np.abs(np.asarray(omega_bar).dot(wrench)))) > threshold_n


def contact_latched(latched: bool, wrench: FloatArray, threshold_n: float) -> bool:
    """The admittance axes' contact latch after this tick's wrench.

    Args:
        latched: The latch before this tick.
        wrench: F_s, the sensed wrench on the environment, world, [N, N m]. # (6,)
        threshold_n: F_contact, the contact threshold, in [N].

    Returns:
        ``latched or |f_s| > F_contact``, f_s the force part of the wrench.
    """
    return latched or float(np.linalg.norm(np.asarray(wrench)[:3])) > threshold_n


def push_landed(
    force_goal: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    speed_mps: float = LANDED_SPEED_MPS,
    share: float = LANDED_PUSH,
) -> bool:
    """Whether a held push has landed: the tool at rest along it, its push not over the goal.

    ``|n^T xd| <= speed`` and ``n^T F_s <= share |F_d|``, ``n = F_d / |F_d|``. A held push
    (CONTACT, SLIDE, WAIT in contact) counts its goal as reached
    (:func:`cosmos.osc.unified.force_goal_reached`, which starts the force loop's integral,
    eq. 17-18) only once landed: a landing's impact passes through the goal on its way to a
    spike of a few times it, and an integral started there winds down against the spike and,
    as the contact springs back, lets the tool drift off the surface (a 3 N CONTACT at 30 mm/s
    fell to -0.1 N 70 ms after its touch on the ideal plant).

    Args:
        force_goal: F_d, world, [N, N m]. # (6,)
        force_sensed: F_s, world, [N, N m]. # (6,)
        velocity: Tool twist xd, world, [m/s, rad/s]. # (6,)
        speed_mps: The speed along the push under which the tool is at rest, in [m/s].
        share: The push, as a share of the goal, over which the impact is still spent.

    Returns:
        True when landed, or when F_d has no force.
    """
    goal = np.asarray(force_goal, dtype=float)[:3]
    push = float(np.linalg.norm(goal))
    if push == 0.0:
        return True
    n = goal / push
    along = abs(float(n.dot(np.asarray(velocity)[:3])))
    return along <= speed_mps and float(n.dot(np.asarray(force_sensed)[:3])) <= share * push


def touch_braking(
    motion: FloatArray,
    wrench: FloatArray,
    velocity: FloatArray,
    tool_mass_kg: float,
    threshold_n: float = TOUCH_BRAKING_N,
    gain_per_s: float = TOUCH_BRAKING_PER_S,
    landing_speed_mps: float = LANDING_SPEED_MPS,
) -> FloatArray:
    """A CONTACT's approach from its first felt push on: eq. 20-21's F*_m braked along it.

    With ``c = f_s - m_tool a`` the push the tool meets (``a`` = F*_m's translation: the
    tool's own inertia taken out of the sensed force), once ``|c|`` exceeds ``threshold_n`` and
    :data:`TOUCH_BRAKING_N_PER_KG` times the tool's mass, and the tool
    moves toward it faster than the landing speed (``n^T xd > v_l``, ``n = c / |c|``)::

        F*_m -= k_b (n^T xd - v_l) n

    a unit-mass damping of the motion into the surface above ``v_l`` (eq. 19-21's velocity
    term along n, made strong): the drives take the approach's momentum while the contact
    builds up, before the touch threshold ends the approach, and leave it landing at ``v_l``
    (braked to rest, the tool crept on at 0.6 mm/s against the braking, and a 10 N CONTACT at
    5 mm/s took 0.2 s more to reach its 2 N threshold). With ``v_l = 0`` this is
    :func:`cosmos.osc.held_push.touch_damping`, a COMPLY spring's touch.

    Args:
        motion: F*_m of eq. 20-21, unit-mass, world, [m/s^2, rad/s^2]. # (6,)
        wrench: F_s, the wrench the tool applies, world, [N, N m]. # (6,)
        velocity: Tool twist xd, world, [m/s, rad/s]. # (6,)
        tool_mass_kg: The mass below the wrist sensor, in [kg].
        threshold_n: The push that starts the braking, in [N].
        gain_per_s: k_b, in [1/s].
        landing_speed_mps: v_l, the speed the braking leaves, in [m/s].

    Returns:
        F*_m braked. # (6,)
    """
    out = np.array(motion, dtype=float)
    contact = np.asarray(wrench, dtype=float)[:3] - tool_mass_kg * out[:3]
    push = float(np.linalg.norm(contact))
    if not push > max(threshold_n, TOUCH_BRAKING_N_PER_KG * tool_mass_kg):
        return out
    n = contact / push
    along = float(n.dot(np.asarray(velocity)[:3])) - landing_speed_mps
    if along > 0.0:
        out[:3] -= gain_per_s * along * n
    return out
