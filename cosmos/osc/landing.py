"""A CONTACT's landing on a stiff surface the workcell model knows: eq. 21's limit brought down before it.

**Why the approach must slow.** On steel (a contact whose impedance reaches full within
:data:`STIFF_RAMP_M`: the tool's own 0.3 mm against the hole fixture's top face) the push
rises at some 3 N per millisecond per 5 mm/s of approach speed, and the arm's effective mass
along the approach (``Lambda_n = n^T Lambda n``, some 20-40 kg on the PUMA with its rotors'
inertia) is stopped by the contact within a few milliseconds: sooner than the wrist sensor's
filter (200 Hz on the realistic plant) and a 1 kHz servo can take the momentum ``Lambda_n v``
off the drives. The landing's peak is then set by the speed at the touch, whatever the force
loop does after it: CONTACT DOWN FORCE 8 N at 20 mm/s on the hole's top face peaked at 53 N
(MuJoCo's contact force; realistic plant, seed 0), and a 3 N CONTACT at 5.7 mm/s at 15 N, at
3.5 mm/s at 5.7 N. Over that impact the push is close to a mass meeting a spring at ``v``:
``F = v sqrt(k Lambda_n)``, linear in ``v``; the table's 1.5 mm ramp cushions it (a 3 N
CONTACT lands at 30 mm/s under 8 N there), the hole's steel does not.

**The landing.** So where the controller's own workcell model (the fixtures' solids, at their
nominal poses) puts a stiff surface ahead of the tool, the approach's speed limit (eq. 21's
``V_max``) falls along a braking profile to a landing speed ``v_l`` reached :data:`LANDING_ZONE_M`
before the modelled surface::

    V(s) = min(V_max, sqrt(v_l^2 + 2 a max(s, 0))),   s = u^T (x_d - x) - s_l

``s`` the distance still to go, along the approach's line ``u``, to where ``v_l`` must be held
(``s_l`` its distance from the approach's goal), ``a`` = :data:`LANDING_DECELERATION_MPS2`; eq.
20's velocity servo gets the profile's own deceleration ``-a u`` as a feedforward while it brakes
(with ``kv`` alone it lags ``a / kv`` behind it). The landing speed is the one that keeps the
impact's excess under the documented bar's least, ``F_x`` = 5 N (``max(1.5 F, F + 5 N)`` less
``F``)::

    v_l = clip(T_l F_x / Lambda_n, LANDING_MIN_MPS, V_max)

with ``T_l`` = :data:`LANDING_TIME_S` measured (the excess per unit momentum at the touch). A
surface the model does not know (an object, a fixture moved) is met at the SPEED as before, and
the touch braking (:func:`cosmos.osc.contact.touch_braking`) takes what a 1 kHz loop can.
"""

from __future__ import annotations

import math

STIFF_RAMP_M = 0.001
"""A contact whose impedance reaches full within this [m] is stiff: the approach lands slowly.
The table's and the tilted plate's 1.5 mm cushion a landing at the SPEED
(tests/run/contact_impact_grid.py); the tool's 0.3 mm against the hole's top face, and the
bore's 1 mm, do not."""

LANDING_ZONE_M = 0.0005
"""The landing speed is reached this far before the modelled surface [m]: the tool point is
measured through the encoders within 0.1 mm, and the velocity servo settles on ``v_l`` over the
last of the profile."""

LANDING_DECELERATION_MPS2 = 0.1
"""The braking profile's deceleration ``a`` [m/s^2]: 20 mm/s to 3 mm/s over 0.4 mm in 34 ms."""

EXCESS_N = 5.0
"""The impact's excess over FORCE that the landing speed is chosen for [N]: the least of the bar's
``max(1.5 F, F + 5 N) - F``."""

LANDING_TIME_S = 0.011
"""``T_l`` [s]: the landing speed per unit of the excess over the effective mass. Measured on the
hole's top face (realistic plant, seed 0, PUMA): 3 N CONTACTs landing at 3.5 mm/s peaked at
5.7 N, at 5.7 mm/s at 15 N; with ``Lambda_n`` about 40 kg this gives 3 mm/s."""

LANDING_MIN_MPS = 0.002
"""The landing speed never falls below this [m/s]: slower, the realistic plant's joints stick."""


def landing_speed(mass_kg: float, max_speed_mps: float) -> float:
    """``v_l = clip(T_l F_x / Lambda_n, v_min, V_max)`` [m/s].

    Args:
        mass_kg: ``Lambda_n``, the arm's effective mass along the approach [kg].
        max_speed_mps: The CONTACT's SPEED [m/s].
    """
    speed = LANDING_TIME_S * EXCESS_N / max(mass_kg, 1e-9)
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
