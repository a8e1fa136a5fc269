"""The joints' Coulomb friction error, learnt, compiled: :func:`cosmos.osc.friction.adapt_coulomb_error`.

``tests/osc/test_osc_friction_adaptation.py`` checks it against the readable reference on seeded
random inputs. Its row in the servo's state is kernels.servo's FRICTION_ERROR.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.friction import COULOMB_ADAPTATION_RATE_PER_S, COULOMB_ERROR_RANGE

FloatArray = np.ndarray


@kernel
def adapted_levels(
    error: FloatArray,
    feedback: FloatArray,
    velocity: FloatArray,
    stacked: FloatArray,
    jbar_lookahead: FloatArray,
    published: tuple[FloatArray, FloatArray],
    adapt: bool,
    gains: FloatArray,
) -> FloatArray:
    """Step ``error`` (in place) where ``adapt``; return the levels ``(1 + eps) Gamma_c(+-)``. # (2, n).

    Args:
        error: eps per joint, stepped in place. # (n,)
        feedback: ``F*_fb``, the motion command's feedback (``F*_m`` less ``xdd_d``), world. # (6,)
        velocity: The sensed twist ``xd``, world. # (6,)
        stacked: Eq. 29 folded; its first six columns are ``J^T Lambda`` on F*_m. # (n, >= 6)
        jbar_lookahead: ``L Jbar P``. # (n, 6)
        published: The model's Gamma_c(+) and Gamma_c(-), in [N m]. # (n,) each
        adapt: Whether this tick learns (a free motion, no contact felt: no push over the cruise's quiet).
        gains: ``(kv [1/s], L [s], 1 / v_c [s/rad], dt [s])``.
    """
    kv, lookahead, intent_scale, dt = gains[0], gains[1], gains[2], gains[3]
    positive_nm, negative_nm = published
    n = error.shape[0]
    levels = np.empty((2, n))
    for i in range(n):
        if adapt:
            along, torque = 0.0, 0.0
            for k in range(6):
                along += jbar_lookahead[i, k] * (feedback[k] / kv + velocity[k])  # qd_r = Jbar v_r
                torque += stacked[i, k] * feedback[k]  # tau = J^T Lambda F*_fb
            sigma = min(max(along / lookahead * intent_scale, -1.0), 1.0)
            level = positive_nm[i] if sigma > 0.0 else negative_nm[i]
            if level > 0.0:
                step = COULOMB_ADAPTATION_RATE_PER_S * sigma * torque / level * dt
                error[i] = min(max(error[i] + step, -COULOMB_ERROR_RANGE), COULOMB_ERROR_RANGE)
        levels[0, i] = positive_nm[i] * (1.0 + error[i])
        levels[1, i] = negative_nm[i] * (1.0 + error[i])
    return levels
