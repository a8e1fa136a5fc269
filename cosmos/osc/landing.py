"""A CONTACT's landing on a stiff surface the workcell model knows: eq. 21's limit brought down before it.

**Why the approach must slow.** On steel (a contact whose impedance reaches full within
:data:`STIFF_RAMP_M`: the tool's own 0.3 mm against the hole fixture's top face) the push
rises at some 3 N per millisecond per 5 mm/s of approach speed, and the arm's effective mass
along the approach (``Lambda_n = n^T Lambda n``, rotors' inertia included: 18.5 kg on the PUMA
over the hole, 8.8 kg on the Panda) is stopped by the contact within a few milliseconds: sooner
than the wrist sensor's filter (200 Hz on the realistic plant) and a 1 kHz servo can take the
momentum ``Lambda_n v`` off the drives. The landing's peak is then set by the speed at the
touch, whatever the force loop does after it: CONTACT DOWN FORCE 8 N at 20 mm/s on the hole's
top face peaked at 53 N (MuJoCo's contact force; realistic plant, seed 0), a 3 N CONTACT at
5.7 mm/s at 15 N, at 3.5 mm/s at 5.7 N. Over that impact the push is close to a mass meeting a
spring at ``v``, ``F = v sqrt(k Lambda_n)`` over the static push; the table's 1.5 mm ramp
cushions it (a 3 N CONTACT lands at 30 mm/s under 8 N there), the hole's steel does not. No loop
at 1 kHz reading a 200 Hz sensor takes that impulse: what it can do is arrive slower.

**The landing.** So where the controller's own workcell model (the fixtures' solids, at their
nominal poses) puts a stiff surface ahead of the tool, the approach's speed limit (eq. 21's
``V_max``) falls along a braking profile to a landing speed ``v_l`` reached :data:`LANDING_ZONE_M`
before the modelled surface::

    V(s) = min(V_max, sqrt(v_l^2 + 2 a max(s, 0))),   s = u^T (x_d - x) - s_l

``s`` the distance still to go, along the approach's line ``u``, to where ``v_l`` must be held
(``s_l`` its distance from the approach's goal), ``a`` = :data:`LANDING_DECELERATION_MPS2`; eq.
20's velocity servo gets the profile's own deceleration ``-a u`` as a feedforward while it brakes
(with ``kv`` alone it lags ``a / kv`` behind it). The landing speed is the one at which a mass
``Lambda_n`` meeting a spring ``k_i`` (:data:`IMPACT_STIFFNESS_N_PER_M`, measured) peaks at the
push the CONTACT's FORCE ``F`` allows (:func:`landing_peak_n`): a share of the documented bar
``max(1.5 F, F + 5 N)``, at most :data:`IMPACT_MAX_N`::

    v_l = clip(P(F) / sqrt(k_i Lambda_n), LANDING_MIN_MPS, V_max)

The impact's peak is the arm's momentum met by the steel, not the force loop's: on the hole's
top face it comes 5-7 ms after the touch and the tool then leaves the face for a few
milliseconds, whatever the FORCE (``python tests/run/contact_impact_grid.py --surfaces hole``:
at 3.6 mm/s the 3 N CONTACT peaked at 8.2-9.7 N, the 8 N one at 9.4-11.1 N). So a light FORCE,
whose bar is close to that peak, lands slower than a heavy one.

A surface whose contact cushions the landing (the table's and the tilted plate's 1.5 mm) gets a
landing too, at :data:`CUSHIONED_LANDING_MPS`: the touch braking
(:func:`cosmos.osc.contact.touch_braking`) keeps a landing there under the bar up to that speed,
not at 50 mm/s. The cruise's integral keeps what it learnt at the SPEED while the profile binds
(wound by the braking, it stopped the tool above the face, then ran it in at twice ``v_l``), and
the joints' Coulomb levels learn from the feedback about the profile, not about ``V_max``
(:mod:`cosmos.runtime.kernels.cruise`). A surface the model does not know (an object, a fixture
moved) is met at the SPEED as before, and the touch braking takes what a 1 kHz loop can: once
the tool is :data:`LANDING_OVER_M` past where the model put the surface without a touch, the
landing is over and the approach goes on at its SPEED.
"""

from __future__ import annotations

import math

STIFF_RAMP_M = 0.001
"""A contact whose impedance reaches full within this [m] is stiff: the approach lands slowly.
The table's and the tilted plate's 1.5 mm cushion a landing at up to :data:`CUSHIONED_LANDING_MPS`
(tests/run/contact_impact_grid.py); the tool's 0.3 mm against the hole's top face, and the
bore's 1 mm, do not."""

LANDING_ZONE_M = 0.0003
"""The landing speed is reached this far before the modelled surface [m]: the tool point is
measured through the encoders within 0.1 mm, and the velocity servo settles on ``v_l`` over the
rest. With 0.5 mm the tool crept the last of it (stuck at rest on the realistic plant); with
0.1 mm it met the face before it had settled (15-18 N for 3 and 8 N CONTACTs)."""

LANDING_DECELERATION_MPS2 = 0.1
"""The braking profile's deceleration ``a`` [m/s^2]: 20 mm/s to 3.8 mm/s over 1.9 mm in 0.16 s.
At 0.5 m/s^2 the velocity servo, reading the 40 Hz observer's lagged speed, braked the tool to
rest 0.5 mm above the face, where the joints' static friction held it."""

IMPACT_STIFFNESS_N_PER_M = 3.3e5
"""``k_i`` [N/m]: the stiff contact's effective stiffness in an impact, from its peak ``P = v
sqrt(k_i Lambda_n)`` for a mass ``Lambda_n`` landing at ``v``. Fitted on the PUMA over the hole's
top face (``Lambda_n`` = 18.5 kg), ideal plant: a 3 N CONTACT touching at 3.64 mm/s peaked at
8.95 N, at 3.08 mm/s at 7.10 N (MuJoCo's contact force). Below that it is softer (2.1 mm/s: 4.0 N):
the contact's impedance still rises over its 0.3 mm. The Panda (``Lambda_n`` 8.8 kg) peaks
lower than this predicts (touching at 4.7-5.1 mm/s: 6.1-6.7 N, some ``k_i`` = 1.9e5)."""

IMPACT_SHARE = 0.75
"""The share of the bar ``max(1.5 F, F + 5 N)`` that the landing's peak is aimed at: the
realistic plant's joints stick and slip below 5 mm/s, and a landing aimed at ``v_l`` touched at
0.87-1.13 times it (3.3-4.3 mm/s at 3.8)."""

IMPACT_MAX_N = 9.4
"""The most a landing's peak is aimed at [N], whatever the FORCE: 3.8 mm/s on the PUMA, 5.5 mm/s
on the Panda, where FORCE 8 and 30 N peak at 1.0-1.4 times FORCE on both arms; faster landings
of heavy FORCEs were not measured."""

CUSHIONED_LANDING_MPS = 0.03
"""The landing speed on a modelled surface whose contact cushions (``STIFF_RAMP_M`` or more) [m/s]:
the table, the tilted plate and a task frame turned 45 deg, FORCE 3-30 N, met the bar at up to
30 mm/s (3 N peaked at 6.8 N) and not at 50 mm/s (3 N at 12-21 N, 8 N at 14-21 N)."""

LANDING_OVER_M = 0.002
"""A landing is over once the tool is this far past where ``v_l`` must be held without its touch
[m]: the surface is not where the model puts it (a fixture moved, a sweep's drawn workcell), and
the approach goes on at its SPEED, as to a surface the model does not know. More than a steel
landing sinks in before its touch (0.3 mm of contact ramp, the encoders' 0.1 mm), and than the
table's cushion (1.5 mm). Without it, ``CONTACT DOWN FORCE 5 N TIMEOUT 6 s`` over the hole
fixture moved 30 mm down crawled at 3.8 mm/s from the nominal face on and found no contact in
6 s (issue 14)."""

LANDING_MIN_MPS = 0.002
"""The landing speed never falls below this [m/s]: slower, the realistic plant's joints stick."""


IMPACT_MASS_KG = {"puma560": 18.5, "panda": 8.8}
"""``Lambda_n``, the arm's effective mass along an approach, rotors included [kg]: the PUMA's and the
Panda's over the hole fixture (the figures :data:`IMPACT_STIFFNESS_N_PER_M` was fitted with)."""


def impact_peak_n(speed_mps: float, mass_kg: float) -> float:
    """``P = v sqrt(k_i Lambda_n)`` [N]: a mass ``Lambda_n`` meeting steel at ``v``, over the static push."""
    return speed_mps * math.sqrt(IMPACT_STIFFNESS_N_PER_M * mass_kg)


def bar_n(force_n: float) -> float:
    """The documented bound on a landing's peak for a FORCE, ``max(1.5 F, F + 5 N)`` [N]."""
    return max(1.5 * force_n, force_n + 5.0)


def landing_peak_n(force_n: float) -> float:
    """``P(F) = min(IMPACT_SHARE bar(F), IMPACT_MAX_N)`` [N]; ``IMPACT_MAX_N`` for an unknown FORCE (0)."""
    if not force_n > 0.0:
        return IMPACT_MAX_N
    return min(IMPACT_SHARE * bar_n(force_n), IMPACT_MAX_N)


def landing_speed(mass_kg: float, max_speed_mps: float, force_n: float = 0.0) -> float:
    """``v_l = clip(P(F) / sqrt(k_i Lambda_n), v_min, V_max)`` [m/s].

    Args:
        mass_kg: ``Lambda_n``, the arm's effective mass along the approach [kg].
        max_speed_mps: The CONTACT's SPEED [m/s].
        force_n: The CONTACT's FORCE [N]; 0 if not known.
    """
    speed = landing_peak_n(force_n) / math.sqrt(IMPACT_STIFFNESS_N_PER_M * max(mass_kg, 1e-9))
    return min(max(speed, LANDING_MIN_MPS), max_speed_mps)


def landing_limit(
    max_speed_mps: float, to_go_m: float, landing_mps: float, deceleration_mps2: float
) -> tuple[float, float]:
    """Eq. 21's ``V_max`` on the braking profile, and the profile's deceleration while it binds.

    Args:
        max_speed_mps: ``V_max`` (ramped), [m/s].
        to_go_m: ``s``, the distance to where ``v_l`` must be held [m] (negative: past it; past
            it by more than :data:`LANDING_OVER_M`, the landing is over: ``V_max`` returned).
        landing_mps: ``v_l`` [m/s]; 0 for no landing (``V_max`` returned).
        deceleration_mps2: ``a`` [m/s^2].

    Returns:
        ``(V, a_ff)``: the limit [m/s] and the feedforward deceleration [m/s^2] (0 unless the
        profile binds before ``v_l`` is reached).
    """
    if not landing_mps > 0.0 or to_go_m < -LANDING_OVER_M:
        return max_speed_mps, 0.0
    profile = math.sqrt(landing_mps**2 + 2.0 * deceleration_mps2 * max(to_go_m, 0.0))
    if profile >= max_speed_mps:
        return max_speed_mps, 0.0
    return profile, deceleration_mps2 if to_go_m > 0.0 else 0.0
