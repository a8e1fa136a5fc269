"""A push held against a surface: eq. 18's force command stiffened along the push, and its speed limit.

CONTACT, SLIDE and a WAIT in contact hold a push against a surface (:func:`held_push`). Unlike
INSERT's (:func:`cosmos.osc.unified.speed_limited_push` on its speed reference) the push is not
held to a speed while it presses; but where it loses its surface (a peg sliding off the hole's
chamfer into the bore) nothing resists it, and it must not run away (:func:`held_push_cap`).
The compiled kernels :func:`cosmos.runtime.kernels.contact.held_push_into` and
:func:`cosmos.runtime.kernels.contact.held_push_capped_into` run the same arithmetic.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.osc.contact import LANDED_SPEED_MPS, touch_braking
from cosmos.osc.landing import landing_limit
from cosmos.osc.unified import push_axis, speed_limited_push

STIFF_HELD_K_FH = 0.3
"""The held push's proportional gain ``k_fh`` on a stiff surface [1]: with eq. 18's ``k_f`` (0.6,
``cosmos.runtime.servo_gains.ServoGains.force``) the loop's gain on the sensed push is 0.9, under 1
(:func:`held_gains`)."""


RAMPED = 1e-9
"""The ramped F_d is at the segment's once within this share of it (:func:`ramp_over`)."""


def ramp_over(force_goal: FloatArray, setpoint: FloatArray) -> bool:
    """Whether the ramped F_d has reached the segment's: ``(F_d - F_r) . F_d <= RAMPED |F_d|^2`` (forces)."""
    goal = np.asarray(force_goal, dtype=float)[:3]
    return float((goal - np.asarray(setpoint, dtype=float)[:3]).dot(goal)) <= RAMPED * float(goal.dot(goal))


def held_on_steel(landing_mps: float, landed: bool, force_goal: FloatArray, setpoint: FloatArray) -> bool:
    """Whether a held push is held on steel: :func:`steel_damping`'s gate.

    A landing set (``v_l > 0``: a stiff surface ahead along the push,
    :func:`cosmos.runtime.landing_zone.with_landing`), the push landed (the force loop's goal
    latch: at rest along it, near its goal) and its setpoint's ramp over (0.25 s after the touch).
    The impact is over by then: the goal latch alone also sets while the impact's rise passes its
    goal at under 5 mm/s, and the band then takes the damping out of the impact.
    """
    return landing_mps > 0.0 and landed and ramp_over(force_goal, setpoint)


def held_gains(gains: tuple[float, float, float, float], stiff: bool) -> tuple[float, float, float, float]:
    """The held push's ``(k_fh, k_ih, k_vh, limit)``: ``k_fh`` at most STIFF_HELD_K_FH on steel.

    On steel the push follows the command within a servo tick: ``F_s(k+1) = F_a(k)``, and eq. 18's
    proportional terms ``F_a = (1 + k) F_d - k F_s`` make that loop ``F_s(k+1) = -k F_s(k) + ...``,
    a pole at ``-k``, ``k = k_f + k_fh``; over 1 it rings up, every other tick. With ``k`` = 1.4 (the
    table's gains) the Panda's ``CONTACT DOWN FORCE 30 N`` on the hole's top face (ideal plant; the
    contact stiffens as it presses) rang from 28 N into a bounce between 0 and 62 N and failed; with
    0.9 it settles at 30 N (``python tests/run/contact_impact_grid.py --robot panda --surfaces hole``).
    The table's 1.5 mm cushion keeps the loop slower than a tick, and its slides keep 0.8
    (``cosmos.runtime.servo_gains.ServoGains.held_push``). A hold knows its surface is stiff by its
    landing (:func:`cosmos.runtime.landing_zone.with_landing`: a stiff surface ahead along the push),
    and takes the gain once landed (the force loop's goal latch, at rest near its goal): during the
    impact the contact is still building up, and the table's gain takes more of it (FORCE 8 N at
    5 mm/s peaked at 9.9-12.2 N with 0.9 from the touch, against 9.4-11.1 N). The Panda's 30 N
    starts to ring as its push, ramped, passes 27 N: with the gain from the end of the ramp
    (:func:`held_on_steel`) it peaked at 31.3-33.4 N, from the goal latch at 30.2 N.

    Args:
        gains: ``(k_fh [1], k_ih [1/s], k_vh [1/s], limit [N s])``.
        stiff: Whether the push presses on a stiff surface.
    """
    k_fh, k_ih, k_vh, limit = gains
    return (min(k_fh, STIFF_HELD_K_FH) if stiff else k_fh), k_ih, k_vh, limit


def held_push(
    feedback: FloatArray,
    force_goal: FloatArray,
    setpoint: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    lambda_inv_omega_bar: FloatArray,
    gains: tuple[float, float, float, float],
    integral: float,
    integrate: bool,
    dt_s: float,
) -> tuple[FloatArray, float]:
    """A push held against a surface (CONTACT, SLIDE, WAIT in contact): eq. 18's F_a stiffened along it.

    Eq. 18's ``F_a`` with the gains of :class:`cosmos.osc.unified.ForceGains` must also serve INSERT,
    whose push moves, and the compliant axes at zero force. A push held against a
    stiff surface needs more along its own direction ``n = F_d / |F_d|``: the
    steel contact passes a force disturbance (the friction of a slide, the arm's
    coupling as it accelerates) straight to the push, and an impact's momentum
    (some 20 kg of rotor inertia at 20 mm/s) to the sensor within milliseconds. So
    along n, where the push is not held to a speed (no :func:`cosmos.osc.unified.speed_limited_push`),
    once it is felt (:func:`cosmos.osc.contact.touch_latched`; before, the servo passes zero gains)::

        F_fb += n (k_fh e + k_ih integral(e) dt - k_vh m_n n^T xd),
        e = n^T (F_d - F_s),  m_n = 1 / (n^T Lambda^-1 n)

    extending eq. 18 with a higher proportional and integral gain along n (the
    integral clamped to ``+-limit``, grown only while touching with the goal
    reached, :func:`cosmos.osc.unified.force_goal_reached`) and a strong damping of the motion along
    n (``k_vh``, 50/s by default): it takes an impact's momentum into the drives rather
    than the contact, and damps the force loop on a stiff surface, which lets the
    integral be fast.

    Args:
        feedback: F_fb from :func:`cosmos.osc.unified.force_feedback`, world, [N, N m]. # (6,)
        force_goal: The segment's F_d (not ramped), world. # (6,)
        setpoint: F_d ramped, world. # (6,)
        force_sensed: F_s, world. # (6,)
        velocity: Tool twist xd, world. # (6,)
        lambda_inv_omega_bar: ``Lambda^-1 Omega_bar``. # (6, 6)
        gains: ``(k_fh [1], k_ih [1/s], k_vh [1/s], limit [N s])``.
        integral: ``integral(e) dt`` so far, in [N s].
        integrate: Whether it grows this tick.
        dt_s: Servo period, in [s].

    Returns:
        ``(F_fb, integral)``: the feedback with the held push's terms, the updated integral.
    """
    n, inverse_mass = push_axis(force_goal, lambda_inv_omega_bar)
    if not inverse_mass > 0.0:
        return feedback, integral
    k_fh, k_ih, k_vh, limit = gains
    error = float(n.dot(setpoint[:3] - force_sensed[:3]))
    if integrate:
        integral = min(max(integral + error * dt_s, -limit), limit)
    added = k_fh * error + k_ih * integral - k_vh * float(n.dot(velocity[:3])) / inverse_mass
    out = np.array(feedback, dtype=float)
    out[:3] += added * n
    return out, integral


def steel_damping(
    feedback: FloatArray,
    force_goal: FloatArray,
    velocity: FloatArray,
    lambda_inv_omega_bar: FloatArray,
    k_vf: float,
    band_mps: float = LANDED_SPEED_MPS,
) -> tuple[FloatArray, FloatArray]:
    """A push landed on steel: its damping acts on the speed along it beyond the velocity observer's noise.

    On steel a push at rest moves micrometres along itself (each is 0.1-1 N), so a speed under
    ``band`` sensed there is the velocity observer's answer to an encoder count
    (:mod:`cosmos.realism.encoders`: one count through the 40 Hz observer is some 4 mm/s at the
    PUMA's tool), not a motion. Damped by eq. 18's ``k_vf`` and the held push's ``k_vh`` (80/s
    times ``m_n``, 18.5 kg), each count kicked the push by up to 6 N: the PUMA's ``CONTACT DOWN
    FORCE 3 N SPEED 5 mm/s`` on the hole's top face (realistic plant, seed 0) rang between 2.3 and
    3.8 N every 0.15 s and was not settled in 3 s. So once held on steel (:func:`held_on_steel`),
    along ``n = F_d / |F_d|``::

        v_b = sign(v_n) max(|v_n| - band, 0),  v_n = n^T xd
        F_fb += k_vf m_n (v_n - v_b) n,         xd <- xd + (v_b - v_n) n  (for the held push's k_vh)

    the first cancels eq. 18's damping of the band's speed (``m_n`` of its ``n^T Lambda n``), the
    second leaves the held push's damping :func:`held_push` the speed beyond it: 2.8-3.25 N,
    settled 0.41 s after the touch. Gated by :func:`held_on_steel`: the impact is over by then; a
    push that loses its surface runs faster than the band, where both damp it as before.

    Args:
        feedback: F_fb, world, [N, N m]. # (6,)
        force_goal: The segment's F_d (not ramped), world. # (6,)
        velocity: Tool twist xd, world. # (6,)
        lambda_inv_omega_bar: ``Lambda^-1 Omega_bar``. # (6, 6)
        k_vf: Eq. 18's damping gain of the force axes [1/s].
        band_mps: The observer's noise along the push [m/s].

    Returns:
        ``(F_fb, xd)``: the feedback with eq. 18's damping of the band's speed given back, and the
        twist whose speed along n the held push damps.
    """
    n, inverse_mass = push_axis(force_goal, lambda_inv_omega_bar)
    if not inverse_mass > 0.0:
        return feedback, velocity
    along = float(n.dot(velocity[:3]))
    beyond = math.copysign(max(abs(along) - band_mps, 0.0), along)
    out, damped = np.array(feedback, dtype=float), np.array(velocity, dtype=float)
    out[:3] += k_vf * (along - beyond) / inverse_mass * n
    damped[:3] += (beyond - along) * n
    return out, damped


def held_push_cap(
    feedback: FloatArray,
    force_goal: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    lambda_inv_omega_bar: FloatArray,
    error: FloatArray,
    max_speed_mps: float,
    landing: tuple[float, float, float],
    kv: float,
    k_vf: float,
) -> tuple[FloatArray, bool]:
    """A held push's speed limit: eq. 21's ``V_max`` along the force axis, braked before a stiff surface.

    Eq. 17-21's unified command holds the force axis with eq. 18's ``F_a`` alone, which has no
    speed limit: eq. 21 limits the motion axes' goal motion only. A push that loses its surface is
    then a force ``F_d`` (plus its integrals, wound by the error the lost push leaves) on a free
    mass: the peg that slid off the hole's chamfer into the bore (``CONTACT DOWN FORCE 8 N SPEED
    10 mm/s`` 0.5 mm off the hole's axis, realistic plant, seeds 1, 2 and 4) fell 43 mm at up to
    80-82 mm/s, bounded only by the held push's damping, and hit the bore's steel bottom at 169-201 N
    (the wrist at 1 kHz; protective stops at 133-170 N). Industrial force control limits the speed
    in force-controlled directions; here eq. 21's ``V_max`` is carried onto the force axis as
    INSERT's push carries it (:func:`cosmos.osc.unified.speed_limited_push`): along ``n = F_d / |F_d|``::

        n^T F_fb <- min(n^T F_fb, n^T F_s + m_n (-a_ff + kv (V - n^T xd) + k_vf n^T xd))
        (V, a_ff) = landing_limit(V_max, s, v_l, a),  s = -n^T (x - x_d) - s_l

    ``V_max`` the statement's SPEED (a CONTACT's approach speed, a SLIDE's own, CONTACT's default
    20 mm/s for a WAIT in contact), and ``V`` on the landing profile of
    :mod:`cosmos.osc.landing` toward the stiff surface the workcell model puts ahead of the tool
    point along ``n`` (``s_l`` measured from the hold's ``x_d``;
    :func:`cosmos.runtime.landing_zone.with_landing`): the push lost over the bore lands on its
    bottom at ``v_l``, as the approach lands on a face. While it binds the force loop's integral
    holds (an INSERT's does at its cap), and the held push's own integral (:func:`held_push`) is
    dropped: it was learnt against the surface the push lost (kept, it pushed the landing on the
    bore's bottom to 17.5-18.5 N).

    It binds only while the push moves along itself (``n^T xd > 0``). At rest it would cap a push
    held off its goal by the joints' stiction at ``m_n kv V`` over the sensed push (some 17 N for
    the PUMA at 3 mm/s, ``kv`` 300/s), short of what breaks the joints free, and hold the integral that
    does (the gripper's ``CONTACT DOWN FORCE 5 N SPEED 3 mm/s`` on the table, seed 2, held 1.7 N for
    3 s and failed). At a touch the push's own damping keeps it under the cap. Unlike at an
    INSERT's cap the joints' friction is not compensated toward ``V``: along a force
    axis it is left to damp the push (:mod:`cosmos.runtime.kernels.servo`), and the push runs under
    its SPEED (with the compensation the peg above ran at up to 12.6 mm/s and landed at 12.9-13.7 N).
    Those three seeds now slide into the bore at 6.3-6.7 mm/s on average (9.4-9.7 mm/s at the
    fastest), land on its bottom at 10.2-10.7 N and settle at FORCE
    (``tests/run/test_run_contact_lost.py``).

    Args:
        feedback: F_fb with the held push's terms (:func:`held_push`), world, [N, N m]. # (6,)
        force_goal: The segment's F_d (not ramped), world. # (6,)
        force_sensed: F_s, world. # (6,)
        velocity: Tool twist xd, world. # (6,)
        lambda_inv_omega_bar: ``Lambda^-1 Omega_bar``. # (6, 6)
        error: ``x - x_d``, world, [m, rad]. # (6,)
        max_speed_mps: ``V_max``, the statement's SPEED [m/s].
        landing: ``(s_l [m], v_l [m/s], a [m/s^2])``; ``v_l`` 0: no stiff surface ahead.
        kv: The speed servo's gain [1/s].
        k_vf: The force axes' damping gain (eq. 18), [1/s].

    Returns:
        ``(F_fb, limited)``: the feedback, capped where the limit binds, and whether it does.
    """
    n, inverse_mass = push_axis(force_goal, lambda_inv_omega_bar)
    if not inverse_mass > 0.0:
        return feedback, False
    limit, brake = held_push_limit(force_goal, error, max_speed_mps, landing)
    if not float(n.dot(velocity[:3])) > 0.0:
        return feedback, False
    return speed_limited_push(
        feedback, force_goal, force_sensed, velocity, lambda_inv_omega_bar, limit, kv, k_vf, -brake
    )


def held_push_limit(
    force_goal: FloatArray, error: FloatArray, max_speed_mps: float, landing: tuple[float, float, float]
) -> tuple[float, float]:
    """``(V [m/s], a_ff [m/s^2])``: :func:`held_push_cap`'s limit along the push, on its landing's profile.

    :func:`cosmos.osc.landing.landing_limit` at ``s = -n^T (x - x_d) - s_l``, ``n = F_d / |F_d|``;
    ``(V_max, 0)`` where ``F_d`` has no force.
    """
    push = float(np.linalg.norm(force_goal[:3]))
    if not push > 0.0:
        return max_speed_mps, 0.0
    to_go = -float(force_goal[:3].dot(error[:3])) / push - landing[0]
    return landing_limit(max_speed_mps, to_go, landing[1], landing[2])


def touch_damping(
    motion: FloatArray,
    wrench: FloatArray,
    velocity: FloatArray,
    gain: float,
    touch_n: float,
    tool_mass_kg: float,
) -> FloatArray:
    """A motion that runs into something, damped along the push it meets (eq. 19-21's F*_m).

    Where every axis is motion-controlled with gains per axis (a COMPLY spring, which expects
    contact; the servo looks for no touch where the gains are uniform), the tool may land on a
    surface at the motion's speed; on a steel contact the momentum (some 20 kg at 27 mm/s)
    would reach the sensor as a spike of 130 N. The push the tool meets is the sensed one
    less what its own inertia gives the sensor at the commanded acceleration,
    ``c = f_s - m_tool a`` (``a`` = F*_m's translation; a 5 cm step accelerates at 20 m/s^2,
    13 N on the 0.65 kg tool). Once ``|c| > touch_n`` and the tool moves toward it
    (``n^T xd > 0``, ``n = c / |c|``), F*_m loses ``k_vh (n^T xd) n``: the held push's
    damping (:func:`held_push`) on the motion into the surface.

    Args:
        motion: F*_m, unit-mass, world, [m/s^2, rad/s^2]. # (6,)
        wrench: F_s, world, [N, N m]. # (6,)
        velocity: Tool twist xd, world. # (6,)
        gain: k_vh, in [1/s].
        touch_n: The push that counts as a touch, in [N].
        tool_mass_kg: The mass below the wrist sensor, in [kg].

    Returns:
        F*_m with the damping. # (6,)
    """
    return touch_braking(motion, wrench, velocity, tool_mass_kg, touch_n, gain, 0.0)
