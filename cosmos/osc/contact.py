"""When the servo considers the tool in contact: the two latches of a segment.

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
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray


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
