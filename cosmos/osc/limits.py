"""Drive limits: torque saturation and the joint-limit potential (seed section 6).

Saturation. Clipping each joint on its own changes the direction of the
commanded torque, and so the direction of the operational force it produces
(eq. 16): a tool pressing straight down would also push sideways. Scaling the
whole command down keeps the direction, but also scales gravity compensation,
so a saturated arm sags. cosmos scales about a kept part, normally ``g(q)``::

    Gamma_sat = Gamma_keep + s (Gamma - Gamma_keep),  s in [0, 1] largest feasible

The dynamic part keeps its direction (the operational force is scaled, not
bent: the end effector slows down along its path instead of leaving it) while
gravity stays compensated. Only if the kept part itself exceeds a limit is
the result clipped per joint, the best that joint can do.

Joint limits. The seed satisfies "the manipulator internal joint constraints"
with potential fields; the FIRAS form (:mod:`cosmos.osc.firas`) applied to
the distance ``rho`` (in rad) from each joint to its nearer limit gives the
repulsive joint torque ``eta (1/rho - 1/rho_0) / rho^2`` inside ``rho_0``.
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.osc.firas import firas_magnitude


def saturate_torque(
    torque: FloatArray, torque_max: FloatArray, keep: FloatArray | None = None
) -> tuple[FloatArray, float]:
    """Scale the command about ``keep`` until every joint is within ``|Gamma_i| <= torque_max_i``.

    Args:
        torque: Commanded Gamma, in [N m]. # (n,)
        torque_max: Drive limits, > 0, in [N m]. # (n,)
        keep: Part that is not scaled, normally gravity g(q), in [N m]; zero if None. # (n,)

    Returns:
        ``(Gamma_sat, s)``: the feasible torque and the scale applied to ``Gamma - keep``
        (1.0 when nothing saturated).
    """
    if all(abs(t) <= m for t, m in zip(torque.tolist(), torque_max.tolist(), strict=True)):
        return torque, 1.0  # the common case, in plain floats (a third of numpy's cost)
    kept = np.zeros_like(torque) if keep is None else np.minimum(np.maximum(keep, -torque_max), torque_max)
    delta = torque - kept
    # Per joint, the largest s with |kept + s delta| <= max is (sign(delta) max - kept) / delta.
    with np.errstate(divide="ignore", invalid="ignore"):
        room = (np.copysign(torque_max, delta) - kept) / delta
    room[delta == 0.0] = np.inf
    scale = min(1.0, max(0.0, float(np.min(room))))
    return kept + scale * delta, scale


def joint_limit_torque(
    q: FloatArray,
    q_min: FloatArray,
    q_max: FloatArray,
    rho_0: float,
    eta: float,
    torque_cap: float,
) -> FloatArray:
    """FIRAS repulsion from joint limits: ``eta (1/rho - 1/rho_0)/rho^2`` away from the limit.

    ``rho`` is the distance to the limit in [rad]; zero torque for ``rho >= rho_0``;
    the magnitude is capped at ``torque_cap`` (reached before ``rho`` reaches 0,
    and kept past the limit). It is the negative gradient of the potential
    ``U = eta/2 (1/rho - 1/rho_0)^2``.

    Args:
        q: Joint positions, in [rad]. # (n,)
        q_min: Lower limits, in [rad]. # (n,)
        q_max: Upper limits, in [rad]. # (n,)
        rho_0: Influence distance, in [rad].
        eta: Gain, in [N m rad^3].
        torque_cap: Largest torque magnitude per joint, in [N m].

    Returns:
        Joint torques, positive away from q_min and negative away from q_max, in [N m]. # (n,)
    """
    n = q.shape[0]
    magnitude = firas_magnitude(np.concatenate((q - q_min, q_max - q)), rho_0, eta, torque_cap)
    return magnitude[:n] - magnitude[n:]
