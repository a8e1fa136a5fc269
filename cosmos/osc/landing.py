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
``Lambda_n`` meeting a spring ``k_c`` (:data:`LANDING_STIFFNESS_N_PER_M`, measured) peaks the
documented bar's least excess, ``F_x`` = 5 N (``max(1.5 F, F + 5 N)`` less ``F``), over its
static push::

    v_l = clip(F_x / sqrt(k_c Lambda_n), LANDING_MIN_MPS, V_max)

The cruise's integral keeps what it learnt at the SPEED while the profile binds (wound by the
braking, it stopped the tool above the face, then ran it in at twice ``v_l``), and the joints'
Coulomb levels learn from the feedback about the profile, not about ``V_max``
(:mod:`cosmos.runtime.kernels.cruise`). A surface the model does not know (an object, a fixture
moved) is met at the SPEED as before, and the touch braking
(:func:`cosmos.osc.contact.touch_braking`) takes what a 1 kHz loop can.
"""

from __future__ import annotations

import math

STIFF_RAMP_M = 0.001
"""A contact whose impedance reaches full within this [m] is stiff: the approach lands slowly.
The table's and the tilted plate's 1.5 mm cushion a landing at the SPEED
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

EXCESS_N = 5.0
"""The impact's excess over FORCE that the landing speed is chosen for [N]: the least of the bar's
``max(1.5 F, F + 5 N) - F``."""

LANDING_STIFFNESS_N_PER_M = 9.4e4
"""``k_c`` [N/m]: the stiff contact's effective stiffness, from the peak of a mass ``Lambda_n``
meeting it at ``v``, ``F_x = v sqrt(k_c Lambda_n)``. Fitted on the PUMA over the hole's top face
(``Lambda_n`` = 18.5 kg; FORCE 3 and 8 N at 20 mm/s, realistic seeds 0-2 and ideal): landing at
3 mm/s peaked at 3.1-3.9 N and 8.1-8.2 N but crept to the touch (0.2-0.3 s later than at the
SPEED) and two of the four 3 N holds hunted in the joints' stiction and never settled; at 3.8 mm/s
(this ``k_c``) 6.2-7.3 N and 8.1-8.3 N, 0.09-0.12 s later; at 4.9 mm/s 10.0-12.9 N and
10.0-13.6 N. The Panda (``Lambda_n`` 8.8 kg) lands at 5.5 mm/s: at 4.8 mm/s its 3 N CONTACTs
peaked at 5.4-6.6 N, at 8 mm/s at 8.1-10.7 N."""

LANDING_MIN_MPS = 0.002
"""The landing speed never falls below this [m/s]: slower, the realistic plant's joints stick."""


def landing_speed(mass_kg: float, max_speed_mps: float) -> float:
    """``v_l = clip(F_x / sqrt(k_c Lambda_n), v_min, V_max)`` [m/s].

    Args:
        mass_kg: ``Lambda_n``, the arm's effective mass along the approach [kg].
        max_speed_mps: The CONTACT's SPEED [m/s].
    """
    speed = EXCESS_N / math.sqrt(LANDING_STIFFNESS_N_PER_M * max(mass_kg, 1e-9))
    return min(max(speed, LANDING_MIN_MPS), max_speed_mps)


def landing_limit(
    max_speed_mps: float, to_go_m: float, landing_mps: float, deceleration_mps2: float
) -> tuple[float, float]:
    """Eq. 21's ``V_max`` on the braking profile, and the profile's deceleration while it binds.

    Args:
        max_speed_mps: ``V_max`` (ramped), [m/s].
        to_go_m: ``s``, the distance to where ``v_l`` must be held [m] (negative: past it).
        landing_mps: ``v_l`` [m/s]; 0 for no landing (``V_max`` returned).
        deceleration_mps2: ``a`` [m/s^2].

    Returns:
        ``(V, a_ff)``: the limit [m/s] and the feedforward deceleration [m/s^2] (0 unless the
        profile binds before ``v_l`` is reached).
    """
    if not landing_mps > 0.0:
        return max_speed_mps, 0.0
    profile = math.sqrt(landing_mps**2 + 2.0 * deceleration_mps2 * max(to_go_m, 0.0))
    if profile >= max_speed_mps:
        return max_speed_mps, 0.0
    return profile, deceleration_mps2 if to_go_m > 0.0 else 0.0
