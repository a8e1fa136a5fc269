"""What the arm does in the null space of a task that leaves some of its motion free (seed section 4).

A task that controls fewer directions than the arm has joints (a position-only
task on the six-joint PUMA: three; any task on a seven-joint arm: at least one)
leaves the self-motion ``N = I - Jbar J`` (eq. 28) free. The task's operational
dynamics are eq. 26-28 on the controlled rows only (``Lambda_r``): with the
controlled-axes projector ``C`` (``Omega + Omega_bar``, world axes),
``Lambda_r = C (C Lambda^-1 C + s (I - C))^-1 C``, so that the 6-row machinery of
:mod:`cosmos.osc.dynamics` and of the compiled servo serves any subset of axes:
the free rows get the inverse mass ``s`` (:data:`FREE_AXIS_INVERSE_MASS`), are
inverted exactly, and are then cut out. Joint torques ``N^T Gamma_0`` then produce
no acceleration of the controlled axes (eq. 34), and the null space serves
further objectives, in this order of the seed's list:

- stabilisation, eq. 34: ``-xi_q A N qd`` (the existing damping, which eq. 38 makes
  asymptotically stable): :func:`cosmos.osc.dynamics.null_space_damping`;
- a posture, :func:`posture_torque`: ``N^T A (-k_q (q - q_posture))``, a unit-mass
  joint spring that the damping above makes critically damped at ``k_q = xi_q^2 / 4``;
- the joint-limit potential and the links' obstacle field (section 6),
  :func:`through_null_space`: their torque acts through ``N^T`` as long as the
  joint or the link is not dangerously close (:class:`AbsorptionPolicy`); closer,
  the whole torque acts, and with it the part that moves the tool.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cosmos.osc._types import FloatArray

FREE_AXIS_INVERSE_MASS = 1.0e6
"""``s``: inverse effective mass given to a free task axis before it is cut out of Lambda [1/kg]."""


def task_lambda_inverse(lambda_inv: FloatArray, controlled: FloatArray) -> FloatArray:
    """``C Lambda^-1 C + s (I - C)``: the free axes made light so the controlled block inverts alone.

    Args:
        lambda_inv: ``J A^-1 J^T`` of the full task (eq. 27). # (m, m)
        controlled: C, the orthogonal projector onto the controlled task axes. # (m, m)

    Returns:
        The block-diagonal matrix whose inverse, cut by C, is Lambda_r (eq. 27). # (m, m)
    """
    free = np.eye(lambda_inv.shape[0]) - controlled
    return controlled.dot(lambda_inv).dot(controlled) + FREE_AXIS_INVERSE_MASS * free


def null_space_dimension(null_space_t: FloatArray) -> float:
    """``trace(N^T)``: the self-motion's dimension (n minus the task's rank, fractional at singularities)."""
    return float(np.trace(null_space_t))


def posture_torque(
    null_space_t: FloatArray, inertia: FloatArray, q: FloatArray, q_posture: FloatArray, k_q: float
) -> FloatArray:
    """The posture task in the null space: ``N^T A (-k_q (q - q_posture))``, in [N m].

    Args:
        null_space_t: N^T = I - J^T Jbar^T of the task (eq. 28, 34). # (n, n)
        inertia: A(q). # (n, n)
        q: Joint positions, in [rad]. # (n,)
        q_posture: The posture the arm returns to, in [rad]. # (n,)
        k_q: Unit-mass joint stiffness, in [1/s^2].

    Returns:
        Joint torques that leave the controlled axes unaccelerated. # (n,)
    """
    return null_space_t.dot(inertia.dot(-k_q * (q - q_posture)))


def null_space_intent(inertia_inv: FloatArray, torque: FloatArray, lookahead_s: float) -> FloatArray:
    """``L A^-1 Gamma_0``: where torques through the null space tell the joints to turn, in [rad/s].

    The Coulomb compensation (:mod:`cosmos.osc.friction`) turns toward ``qd`` plus
    ``Jbar (L a)``, the joint motion the task's command asks over a look-ahead L; a torque
    ``Gamma_0`` through ``N^T`` (eq. 34: a posture, a field on the links) asks
    ``qdd = A^-1 Gamma_0`` of joints that the task leaves still, and from rest its friction was
    compensated only once the joint was seen moving: the breakaway of joints 1-3 (25, 14, 7 N m)
    behind the wrist's motion moved the held tool (0.74 mm for `POSTURE home` on the ideal plant).

    Args:
        inertia_inv: A(q)^-1. # (n, n)
        torque: The torques applied, Gamma_0, in [N m]. # (n,)
        lookahead_s: L, in [s].

    Returns:
        The joint speeds to add to the friction's intent, in [rad/s]. # (n,)
    """
    return lookahead_s * inertia_inv.dot(torque)


@dataclass(frozen=True)
class AbsorptionPolicy:
    """When a potential field's torque acts through the null space only (safety first).

    A link (or a joint) farther than ``absorbed_from`` from what repels it gets only
    ``N^T Gamma``: the task does not feel it. Closer than ``full_below`` it gets the
    whole ``Gamma``, which also moves the tool. In between the weight of the part
    that reaches the tool ramps (smoothstep), so the torque stays continuous.

    Attributes:
        link_full_below_m: Link clearance under which the whole field acts, in [m].
        link_absorbed_from_m: Link clearance from which only ``N^T Gamma`` acts, in [m].
        joint_full_below_rad: Distance to a joint limit under which the whole potential acts, [rad].
        joint_absorbed_from_rad: Distance from which only its null-space part acts, [rad].
        min_dimension: Least ``trace(N^T)`` that counts as a null space (below it, the
            whole field acts: a full task on a six-joint arm away from singularities).
    """

    link_full_below_m: float = 0.02
    link_absorbed_from_m: float = 0.04
    joint_full_below_rad: float = 0.05
    joint_absorbed_from_rad: float = 0.10
    min_dimension: float = 0.5


DEFAULT_ABSORPTION = AbsorptionPolicy()


def absorbed_weight(distance: float, full_below: float, absorbed_from: float) -> float:
    """Share of a field that the null space takes: 0 below ``full_below``, 1 from ``absorbed_from``."""
    u = min(max((distance - full_below) / (absorbed_from - full_below), 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


def through_null_space(torque: FloatArray, null_space_t: FloatArray, weight: float) -> FloatArray:
    """``N^T Gamma + (1 - w) J^T Jbar^T Gamma``: the field with the part that reaches the tool weighted.

    ``N^T Gamma`` and ``J^T Jbar^T Gamma`` split Gamma into what the task does not
    feel and what it does (``Jbar^T`` of it is the operational force on the tool).

    Args:
        torque: The field's joint torques Gamma, in [N m]. # (n,)
        null_space_t: N^T of the task. # (n, n)
        weight: w, the share absorbed (:func:`absorbed_weight`); 0 applies Gamma whole.

    Returns:
        The joint torques to apply, in [N m]. # (n,)
    """
    projected = null_space_t.dot(torque)
    return projected + (1.0 - weight) * (torque - projected)
