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


def joint_limit_task_projection(
    jacobian: FloatArray,
    q: FloatArray,
    q_min: FloatArray,
    q_max: FloatArray,
    goal_direction: FloatArray,
    margin_rad: float,
    whole_rad: float,
    translation_give_up: float,
) -> FloatArray:
    """A joint at its limit is a lost degree of freedom: the task gives up rotation, not its line.

    Section 6's joint-limit potential stops a joint at its limit, but the task
    command still asks for the motion that needs it; the other joints then make
    what they can of it, and the tool leaves its line (a 130 deg reorientation ran
    50-218 mm off it). Treated like a singular direction (section 5,
    :func:`cosmos.osc.dynamics.singular_task_projection`): the twists the arm can
    make without joint i are those with ``u_i^T t = 0``, ``u_i = J^-T e_i`` (row i
    of J^-1), and ``I - g d u_i^T / (u_i^T d)``, ``d = (translation_give_up
    u_lin, u_rot)``, removes joint i's share of a command by giving up rotation.
    It acts on a joint within ``margin_rad`` of a limit that the goal direction
    drives further in, with ``g = (margin_rad - distance) / (margin_rad - whole_rad)``
    up to 1: whole from ``whole_rad`` in, where the joint-limit potential begins.

    The command's damping along what is given up goes with it: joint i, driven by
    neither the task nor its damping, bounced off the potential and rang against it
    (a 0.3 s limit cycle, the tool turning back at 1.2 rad/s, before the failure).
    Section 5 treats the arm as redundant with respect to the directions kept, and
    so stabilises it as section 4 does: eq. 34's damping, here ``-g xi_q A e_i
    e_i^T qd``, slows joint i alone (``cosmos.runtime.kernels.parameter.refold``).

    Args:
        jacobian: J(q), rows linear then angular, world. # (6, 6)
        q: Joint positions, in [rad]. # (6,)
        q_min: Lower limits, in [rad]. # (6,)
        q_max: Upper limits, in [rad]. # (6,)
        goal_direction: The twist toward the goal, ``-(x - x_d)``, in [m, rad]. # (6,)
        margin_rad: Distance from a limit at which the projection starts, in [rad].
        whole_rad: Distance from a limit at which it is whole, in [rad].
        translation_give_up: Weight of translation in the direction given up.

    Returns:
        P (the identity when no joint is near a limit it is driven into). # (6, 6)
    """
    projection = np.eye(6)
    try:
        joint_rates = np.linalg.solve(jacobian, goal_direction)
        inverse_t = np.linalg.inv(jacobian).T
    except np.linalg.LinAlgError:
        return projection
    for i in range(q.shape[0]):
        below, above = q[i] - q_min[i], q_max[i] - q[i]
        distance = below if joint_rates[i] < 0.0 else above
        if joint_rates[i] == 0.0 or distance >= margin_rad:
            continue
        weight = min(1.0, (margin_rad - distance) / (margin_rad - whole_rad))
        u = inverse_t[:, i]
        d = u.copy()
        d[:3] *= translation_give_up
        ud = float(u.dot(d))
        if ud > 0.0:
            projection = (np.eye(6) - weight * np.outer(d, u) / ud).dot(projection)
    return projection


def joint_limit_constraint(
    inertia_inv: FloatArray,
    jacobian: FloatArray,
    q: FloatArray,
    q_min: FloatArray,
    q_max: FloatArray,
    goal_direction: FloatArray,
    margin_rad: float,
    whole_rad: float,
) -> FloatArray:
    """A redundant arm's joint at its limit leaves the task: ``N_c``, the task's Jacobian is ``J N_c``.

    On a redundant arm the task need not give up what a joint at its limit did
    (:func:`joint_limit_task_projection` does so for six joints, where nothing
    else can): the other joints can often do it. Eq. 26-28 written for the arm
    without joint i (the idea of Flacco, De Luca and Khatib's saturation in the
    null space, 2012, in the dynamically consistent form): with ``J_c = e_i^T``,
    ``N_c = I - A^-1 J_c^T (J_c A^-1 J_c^T)^-1 J_c`` and the task Jacobian
    ``J N_c``, whose ``Lambda_c = (J N_c A^-1 J^T)^-1``, ``Jbar_c = A^-1 N_c^T J^T
    Lambda_c`` (eq. 27-28) and torques ``N_c^T J^T Lambda_c F`` give the tool
    exactly ``F`` and joint i no acceleration (``e_i^T A^-1 N_c^T = 0``). What
    the other joints cannot do shows as a heavy direction of ``Lambda_c``, which
    section 5 gives up (:func:`cosmos.osc.dynamics.singular_task_projection`);
    joint i is left to the null space: eq. 34's damping, the joint-limit
    potential and the self-motion, which make room.

    Joint i is constrained within ``margin_rad`` of the limit that the goal
    drives it into (through the controller's own inverse Jbar of eq. 28), with
    weight ``g = (margin_rad - distance) / (margin_rad - whole_rad)`` up to 1,
    blended as a soft constraint: ``D = diag(a_ii (1 - g) / g)`` added to
    ``J_c A^-1 J_c^T`` (``a_ii = (A^-1)_ii``), so that one joint gets
    ``e_i^T N_c = (1 - g) e_i^T`` and ``N_c A^-1`` stays symmetric positive
    semi-definite for any number of joints.

    Args:
        inertia_inv: A^-1. # (n, n)
        jacobian: J(q), rows linear then angular, world. # (6, n)
        q: Joint positions, in [rad]. # (n,)
        q_min: Lower limits, in [rad]. # (n,)
        q_max: Upper limits, in [rad]. # (n,)
        goal_direction: The twist toward the goal, ``-(x - x_d)``, in [m, rad]. # (6,)
        margin_rad: Distance from a limit at which the constraint starts, in [rad].
        whole_rad: Distance from a limit at which it is whole, in [rad].

    Returns:
        N_c (the identity when no joint is near a limit it is driven into). # (n, n)
    """
    n = q.shape[0]
    try:
        lambda_ = np.linalg.inv(jacobian @ inertia_inv @ jacobian.T)  # eq. 27
    except np.linalg.LinAlgError:
        return np.eye(n)
    rates = inertia_inv @ jacobian.T @ lambda_ @ goal_direction  # Jbar (eq. 28) toward the goal
    joints, softness = [], []
    for i in range(n):
        distance = q[i] - q_min[i] if rates[i] < 0.0 else q_max[i] - q[i]
        if rates[i] == 0.0 or distance >= margin_rad:
            continue
        weight = min(1.0, (margin_rad - distance) / (margin_rad - whole_rad))
        joints.append(i)
        softness.append(inertia_inv[i, i] * (1.0 - weight) / weight)
    if not joints:
        return np.eye(n)
    coupling = inertia_inv[:, joints]  # A^-1 J_c^T # (n, k)
    block = coupling[joints, :] + np.diag(softness)  # J_c A^-1 J_c^T + D # (k, k)
    selector = np.zeros((len(joints), n))  # J_c
    selector[np.arange(len(joints)), joints] = 1.0
    return np.eye(n) - coupling @ np.linalg.solve(block, selector)
