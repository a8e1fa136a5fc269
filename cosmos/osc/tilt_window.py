"""An INSERT's compliant rotations turn within a window, as a compliance device's do.

INSERT's ``COMPLY ... RX RY`` axes run the admittance law of :mod:`cosmos.osc.admittance`
(the moment error sets the rotation speed ``w_a``, bounded as eq. 21 bounds a speed):
zero moment about the tool point, so nothing holds the peg's axis. A flat-ended peg whose
end lands partly on the fixture's top face (beyond the chamfers' 2.6 mm of capture, or a
SEARCH passing over the mouth) rests on the mouth's edge some 8 mm from the tool point, and
the 15 N push turns it about that edge at the admittance's top speed (0.3 rad/s): on steel
contacts it tipped 21-25 deg and wedged in the 0.24 mm clearance, 3.8-4.9 mm into the hole
(a compliant INSERT from 2 mm off and two spiral searches, on the realistic plant). A
remote-centre compliance device turns only within its travel; so here, beyond a window
``theta_w`` from the segment's orientation the axes get a stop::

    w_a <- w_a - k_w (|theta| - theta_w) theta / |theta|,   where |theta| > theta_w,

``theta`` the rotation error (tool orientation against the segment's goal) on the admittance
axes. Within the window the law is unchanged: a peg that lands 3.2 mm off still tips its
end into the mouth (to 11 deg) and rights itself as it goes in, and the slope's CONTACT
(not an INSERT) aligns freely. The compiled kernel
:func:`cosmos.runtime.kernels.contact.tilt_window_into` runs the same arithmetic.
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray


def tilt_window(speed: FloatArray, tilt: FloatArray, window_rad: float, rate: float) -> FloatArray:
    """The admittance speed with the window's stop.

    Args:
        speed: ``w_a`` from :func:`cosmos.osc.admittance.admittance_speed`, world. # (6,)
        tilt: ``Omega_a`` times the pose error (current against goal), world, [m, rad]. # (6,)
        window_rad: ``theta_w``, in [rad].
        rate: ``k_w``, the stop's speed per radian beyond the window, in [1/s].

    Returns:
        ``w_a`` with the stop: its rotation turned back toward the window. # (6,)
    """
    out = np.array(speed, dtype=float)
    size = float(np.linalg.norm(tilt[3:]))
    if size > window_rad:
        out[3:] -= rate * (size - window_rad) / size * np.asarray(tilt[3:])
    return out
