"""End-effector dynamics in operational space from the joint-space model (seed eq. 13, 26-28).

Given the joint-space model ``A qdd + b + g = Gamma`` (eq. 12) and the Jacobian,
the end effector obeys ``Lambda xdd + mu + p = F`` (eq. 9 / 26) with::

    Lambda^-1 = J A^-1 J^T                          (eq. 27)
    Jbar      = A^-1 J^T Lambda                     (eq. 28)
    mu        = Jbar^T b - Lambda h,  h = Jdot qd   (eq. 27, eq. 14)
    p         = Jbar^T g                            (eq. 27)
    N^T       = I - J^T Jbar^T                      (null-space projector of eq. 34)

For a square invertible J these are eq. 13 (``Lambda = J^-T A J^-1``); eq. 27 is
used throughout because it also covers redundancy and singularities.

Singularities (seed section 5). At a singular configuration ``Lambda^-1`` loses
rank: along the singular direction the effective mass ``1/s`` (s an eigenvalue
of ``Lambda^-1``) explodes. Following the seed, the arm is then treated as
redundant with respect to the motion in the subspace orthogonal to the singular
direction: ``Lambda`` is inverted only there. Each eigen-direction gets the
effective mass ``w(s)/s`` instead of ``1/s``, where ``w`` is a smoothstep from 0
at ``s_lo = 1/max_effective_mass_kg`` to 1 at ``s_hi = (1 + blend_width) s_lo``.
So directions with effective mass below ``max_effective_mass / (1 + blend_width)``
keep their exact Lambda; the effective mass never exceeds
``max_effective_mass_kg`` (torques stay bounded); and Lambda varies continuously
(C1 in s) as the arm passes through the singularity. ``N^T`` then projects onto
torques that do not accelerate the controlled subspace (exactly so outside the
blend zone; inside it a direction is only partly controlled).

Units: the eigenvalues of a 6x6 ``Lambda^-1`` mix 1/kg (translation) with
1/(kg m^2) (rotation). For a 6-row task ``[linear; angular]`` the angular rows
are scaled by ``length_scale_m`` first, so a rotational inertia ``I`` counts as
the mass ``I / L^2`` (the mass that, at radius L, has that inertia) and one
threshold in kg serves both.

Threshold choice (defaults of :class:`SingularityPolicy`, measured on a PUMA 560
model built from shared/reference/puma560.md with rotor inertias, tool point at
the wrist centre, L = 0.5 m): at the nominal pose qn the effective masses are
0.4 to 26 kg; over 2000 random configurations within the joint limits the
largest one has a median of 94 kg. It grows like the inverse square of the
distance to a singularity: from qn, 1000 kg is reached at q5 = 2.6 deg (wrist)
and 10.5 deg short of the stretched elbow, 2000 kg at 1.9 deg and 7.7 deg. So
with 2000 kg and a blend width of 1 the decoupling is exact until a few degrees
from a singularity, and the joint torque that a unit acceleration command can
demand along a singular direction stays below ``sqrt(a M)`` (a the joint
inertia involved; M = 2000 kg, or ``M L^2`` = 500 kg m^2 for rotations): about
10 N m per rad/s^2 at the wrist (a = 0.2 kg m^2), within its 20 N m drives.

The task in the orthogonal subspace (section 5). Dropping a direction from
Lambda is not enough: the end effector's acceleration is then ``F*`` with its
component along the singular direction removed *orthogonally* (in the scaled
metric), and at the PUMA's wrist that direction mixes a rotation with a
translation of the tool point (a moment about the lost axis plus the force
through the wrist centre that balances it on joints 1-3). A rotation error
about the lost axis then translates the tool: a 15 deg roll at q5 = 0.8 deg ran
the tool 100 mm sideways. So the command is projected first, obliquely: with
``u`` the singular wrench direction (``u^T t = 0`` for every twist t the arm can
make) and ``d`` the direction given up (u's rotation, its translation weighted
by TRANSLATION_GIVE_UP), ``P = I - g d u^T / (u^T d)`` makes ``u^T P F* = 0``
by changing only the rotation where the loss is rotational: the tool point
keeps its line and the rest of the task stays decoupled; the rotation about the
lost axis waits (:func:`singular_task_projection`; ``g`` ramps in with the
blend so P is continuous). At a translational singularity (the stretched
elbow) ``u`` has no rotation and ``d`` is its translation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple, cast

import numpy as np

from cosmos.osc._types import BoolArray, FloatArray


@dataclass(frozen=True)
class SingularityPolicy:
    """How Lambda is inverted near a kinematic singularity (seed section 5).

    Attributes:
        max_effective_mass_kg: Effective mass at which a direction counts as fully
            singular and is dropped from the controlled subspace, in [kg].
        blend_width: The blend runs from ``1/max`` to ``(1 + blend_width)/max`` in
            ``1/kg``; directions lighter than ``max / (1 + blend_width)`` are exact.
        length_scale_m: For a 6-row ``[linear; angular]`` task, the radius at which
            a rotational inertia counts as a mass, in [m].
    """

    max_effective_mass_kg: float = 2000.0
    blend_width: float = 1.0
    length_scale_m: float = 0.5

    def __post_init__(self) -> None:
        if not (self.max_effective_mass_kg > 0.0 and self.blend_width > 0.0):
            raise ValueError(
                "SingularityPolicy: max_effective_mass_kg and blend_width must be > 0, "
                f"got {self.max_effective_mass_kg} and {self.blend_width}"
            )
        if not self.length_scale_m > 0.0:
            raise ValueError(f"SingularityPolicy: length_scale_m must be > 0, got {self.length_scale_m}")


DEFAULT_POLICY = SingularityPolicy()

TRANSLATION_GIVE_UP = 1e-3
"""Weight of the translation in the direction a singular task gives up, relative to rotation."""
SINGULAR_GIVE_UP_RATE = 4.0
"""The projection's weight is ``min(1, rate (1 - blend))``: whole once a quarter of the blend is gone."""


class OperationalDynamics(NamedTuple):
    """The operational-space model at one configuration (eq. 26-28) and its singular directions.

    ``eigenvalues``, ``eigenvectors`` and ``blend`` describe the (row-scaled)
    ``Lambda^-1``; they are only computed when some direction is near-singular,
    otherwise ``eigenvectors`` is empty (shape (m, 0)) and ``blend`` is all ones.
    """

    jacobian: FloatArray  # (m, n)
    lambda_: FloatArray  # (m, m) kinetic energy matrix, singular directions removed
    lambda_inv: FloatArray  # (m, m) J A^-1 J^T
    jbar: FloatArray  # (n, m) dynamically consistent inverse
    mu: FloatArray  # (m,) Coriolis and centrifugal forces
    p: FloatArray  # (m,) gravity forces
    null_space_t: FloatArray  # (n, n) N^T = I - J^T Jbar^T
    compensation_torque: FloatArray  # (n,) b + g - J^T Lambda h (eq. 29, A2)
    eigenvalues: FloatArray  # (m,) or (0,): eigenvalues of scaled Lambda^-1, ascending, [1/kg]
    eigenvectors: FloatArray  # (m, m) or (m, 0): their unit eigenvectors (columns)
    blend: FloatArray  # (m,) or (0,): 1 controlled, 0 singular, per eigen-direction
    task_projection: FloatArray  # (m, m) P of section 5: what of F* the arm can do without bending it

    @property
    def singular(self) -> BoolArray:
        """Which eigen-directions are (partly) singular: blend < 1. # (k,)."""
        return self.blend < 1.0

    @property
    def singular_directions(self) -> FloatArray:
        """Unit directions (columns) not fully controlled; angular rows scaled. # (m, k)."""
        return self.eigenvectors[:, self.blend < 1.0]


def _row_scale(m: int, policy: SingularityPolicy) -> FloatArray | None:
    if m != 6:
        return None
    length = policy.length_scale_m
    return np.array((1.0, 1.0, 1.0, length, length, length))


def blend_weights(eigenvalues: FloatArray, policy: SingularityPolicy = DEFAULT_POLICY) -> FloatArray:
    """Smoothstep weight per eigenvalue of Lambda^-1: 0 at ``1/M``, 1 from ``(1+w)/M``.

    Args:
        eigenvalues: Inverse effective masses, in [1/kg]. # (k,)
        policy: The thresholds.

    Returns:
        Weights in [0, 1]. # (k,)
    """
    s_lo = 1.0 / policy.max_effective_mass_kg
    u = np.clip((eigenvalues - s_lo) / (policy.blend_width * s_lo), 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def operational_dynamics(
    inertia: FloatArray,
    jacobian: FloatArray,
    bias: FloatArray,
    gravity: FloatArray,
    jdot_qdot: FloatArray,
    *,
    inertia_inv: FloatArray | None = None,
    policy: SingularityPolicy = DEFAULT_POLICY,
) -> OperationalDynamics:
    """Lambda, Jbar, mu, p and N^T of eq. 27-28, with the singular directions of section 5 removed.

    Args:
        inertia: Joint-space kinetic energy matrix A(q), symmetric positive definite. # (n, n)
        jacobian: J(q), rows ``[linear; angular]`` for a 6-row task. # (m, n)
        bias: Joint Coriolis and centrifugal forces b(q, qd), in [N m]. # (n,)
        gravity: Joint gravity forces g(q), in [N m]. # (n,)
        jdot_qdot: h = Jdot qd (eq. 14), in [m/s^2] and [rad/s^2]. # (m,)
        inertia_inv: A^-1 if already known (the parameter level's evaluation has it); saves a solve. # (n, n)
        policy: Singularity thresholds.

    Returns:
        The operational-space model at this configuration.
    """
    m, n = jacobian.shape
    a_inv_jt = np.linalg.solve(inertia, jacobian.T) if inertia_inv is None else inertia_inv.dot(jacobian.T)
    lambda_inv = jacobian.dot(a_inv_jt)  # (m, m)
    lambda_, blended = kinetic_energy_matrix(lambda_inv, policy)
    empty = np.empty((m, 0))
    eigenvalues, eigenvectors, blend = empty[0], empty, np.ones(m)
    projection = np.eye(m)
    if blended is not None:
        eigenvalues, eigenvectors, blend = blended
        projection = singular_task_projection(eigenvectors, blend, _row_scale(m, policy))
    jbar = a_inv_jt.dot(lambda_)  # (n, m)
    jbar_t = jbar.T
    lambda_h = lambda_.dot(jdot_qdot)
    return OperationalDynamics(
        jacobian=jacobian,
        lambda_=lambda_,
        lambda_inv=lambda_inv,
        jbar=jbar,
        mu=jbar_t.dot(bias) - lambda_h,
        p=jbar_t.dot(gravity),
        null_space_t=np.eye(n) - jacobian.T.dot(jbar_t),
        compensation_torque=bias + gravity - jacobian.T.dot(lambda_h),
        eigenvalues=eigenvalues,
        eigenvectors=eigenvectors,
        blend=blend,
        task_projection=projection,
    )


def kinetic_energy_matrix(
    lambda_inv: FloatArray, policy: SingularityPolicy = DEFAULT_POLICY
) -> tuple[FloatArray, tuple[FloatArray, FloatArray, FloatArray] | None]:
    """Lambda from ``Lambda^-1 = J A^-1 J^T`` (eq. 27), section 5's singular directions removed.

    :func:`operational_dynamics`' Lambda, also asked for alone
    (:attr:`cosmos.runtime.parameters.Evaluation.lambda_`).

    Args:
        lambda_inv: ``J A^-1 J^T``. # (m, m)
        policy: Singularity thresholds.

    Returns:
        Lambda, and near a singular direction the scaled ``Lambda^-1``'s eigenvalues, eigenvectors
        and blend weights (:func:`blend_weights`); None where the plain inverse is exact.
    """
    scale = _row_scale(lambda_inv.shape[0], policy)
    lambda_ = _exact_inverse(lambda_inv, scale, policy)
    if lambda_ is not None:
        return lambda_, None
    lambda_, eigenvalues, eigenvectors, blend = _blended_inverse(lambda_inv, scale, policy)
    return lambda_, (eigenvalues, eigenvectors, blend)


def _exact_inverse(
    lambda_inv: FloatArray, scale: FloatArray | None, policy: SingularityPolicy
) -> FloatArray | None:
    """Plain inverse when it is certified far from singular, else None.

    The largest effective mass is below trace(Lambda) (Lambda is positive
    definite), so ``trace <= max_mass / (1 + blend_width)`` proves that every
    direction is in the exact zone without an eigendecomposition.
    """
    try:
        lambda_ = cast(FloatArray, np.linalg.inv(lambda_inv))
    except np.linalg.LinAlgError:
        return None
    diagonal = lambda_.diagonal()
    trace = float(diagonal.sum()) if scale is None else float(diagonal.dot(1.0 / (scale * scale)))
    limit = policy.max_effective_mass_kg / (1.0 + policy.blend_width)
    return lambda_ if 0.0 < trace <= limit else None


def _blended_inverse(
    lambda_inv: FloatArray, scale: FloatArray | None, policy: SingularityPolicy
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Eigen-decompose the scaled Lambda^-1 and invert it with the blend weights."""
    scaled = lambda_inv if scale is None else lambda_inv * np.outer(scale, scale)
    eigenvalues, eigenvectors = np.linalg.eigh(scaled)
    blend = blend_weights(eigenvalues, policy)
    safe = np.maximum(eigenvalues, 1.0 / policy.max_effective_mass_kg)
    lambda_scaled = (eigenvectors * (blend / safe)).dot(eigenvectors.T)
    lambda_ = lambda_scaled if scale is None else lambda_scaled * np.outer(scale, scale)
    return lambda_, eigenvalues, eigenvectors, blend


def singular_task_projection(
    eigenvectors: FloatArray, blend: FloatArray, scale: FloatArray | None
) -> FloatArray:
    """Section 5's projection of the motion command onto what the arm can do, position first.

    For each partly singular eigen-direction ``v`` (blend ``w < 1``) of the scaled
    Lambda^-1, the singular wrench is ``u = S v`` and the direction given up is
    ``d = (TRANSLATION_GIVE_UP u_lin, u_rot)``; the factor is
    ``I - g d u^T / (u^T d)`` with ``g = min(1, SINGULAR_GIVE_UP_RATE (1 - w))``,
    applied in ascending order of eigenvalue.

    Args:
        eigenvectors: Unit eigenvectors of the scaled Lambda^-1 (columns). # (m, m)
        blend: Their blend weights. # (m,)
        scale: Row scale S (None: none).

    Returns:
        P, with ``u^T P = (1 - g) u^T`` for each singular u. # (m, m)
    """
    m = eigenvectors.shape[0]
    projection = np.eye(m)
    for i in np.nonzero(blend < 1.0)[0]:
        u = eigenvectors[:, i] if scale is None else scale * eigenvectors[:, i]
        d = u.copy()
        if m == 6:
            d[:3] *= TRANSLATION_GIVE_UP
        ud = float(u.dot(d))
        if not ud > 0.0:
            continue
        weight = min(1.0, SINGULAR_GIVE_UP_RATE * (1.0 - float(blend[i])))
        projection = (np.eye(m) - weight * np.outer(d, u) / ud).dot(projection)
    return projection


def null_space_damping(
    dynamics: OperationalDynamics, inertia: FloatArray, qdot: FloatArray, xi_q: float
) -> FloatArray:
    """Stabilising null-space joint torque of eq. 34: ``-xi_q A (I - Jbar J) qd``.

    Computed as ``-xi_q (A qd - J^T Lambda J qd)`` (``A N = N^T A = A - J^T Lambda J``).

    Args:
        dynamics: The operational model at this configuration.
        inertia: A(q). # (n, n)
        qdot: Joint velocities, in [rad/s]. # (n,)
        xi_q: Joint damping gain, in [1/s].

    Returns:
        Gamma_s, in [N m]; it produces no acceleration in the controlled subspace. # (n,)
    """
    j = dynamics.jacobian
    return -xi_q * (inertia.dot(qdot) - j.T.dot(dynamics.lambda_.dot(j.dot(qdot))))
