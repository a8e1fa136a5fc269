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

Which window applies, and the push across the insertion that carries a part tipped on the
mouth's edge over it, depend on the depth (:func:`insert_compliance`, compiled as
:func:`cosmos.runtime.kernels.contact.insert_compliance_into`).
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


def insert_compliance(
    speed: FloatArray,
    tilt: FloatArray,
    error: FloatArray,
    velocity: FloatArray,
    force_goal: FloatArray,
    wrench: FloatArray,
    omega_bar: FloatArray,
    params: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """An INSERT's compliant axes: tip into the mouth and slide over its rim, then stand up in it.

    The unified command (eq. 17-18) keeps the seed's split: ``F*_m`` on the motion axes,
    ``F_a`` on the force axes. Here the window's ``theta_w`` and a share of the push across it
    depend on how deep the tool is along its push ``n`` (``d = n . (x - x_d)``, the INSERT's
    start its ``x_d``):

    * short of ``d_in`` the window is ``theta_w`` and the force axes get a push ``F_l``
      across ``n`` toward where the part leans, ``l = n x theta / |n x theta|``, in
      proportion to the push felt along ``n`` (``f_n = n . F_s`` within ``[0, |F_d|]``: what
      the contact's friction holds it by), fading as the tool's speed along ``l`` nears
      ``v_s`` (the push held to a speed, as eq. 21's ``nu`` holds a motion to ``V_max``),
      fed forward with F_d but kept out of the force error's integral (Figure 2's PI, which
      wound up while the tool moved instead of pushing, and threw it across the mouth)::

          F_l = s f_n min(1, |n x theta| / theta_w) max(0, 1 - l . xd / v_s) Omega_bar l
          F_a = (1 + k_f)(F_d + F_l) - k_f F_s + k_i int(F_d - F_s) dt
                (the integral's error less its part along F_l: :func:`integrated_force_error`)

      A part whose end rests on the fixture's top face beside the mouth tips its far side
      into it (the contact's moment about the tool point, zero-moment admittance) and then
      sits on the mouth's edge: the edge pushes it toward the hole with only
      ``F tan(theta)`` (2.3 N at 10.8 deg and 12 N), against a friction ``mu F`` (5-10 N at
      ``mu`` 0.4-0.8), so it crept over the edge at 0.5 mm/s or stayed. Pushed toward its
      lean (a compliance centre below the tip: the tilt carries the tip toward the mouth,
      as the seed's compliance on a motion axis is its gain, section 3, here on a force
      axis) it slides over the edge in tenths of a second. Off the edge, over the mouth, it
      feels no push and is pushed across no more, and never faster than ``v_s``: a SEARCH's
      peg tipped into the mouth, pushed off the edge at ``s |F_d|``, crossed the mouth at
      25 mm/s in free air onto the far wall (42 N; 21 N without the push).
    * from ``d_in`` on (the part is in the mouth: tipping on the edge lowers the tool point
      by at most ``r sin(theta_w)``, 1.5 mm for the 8.4 mm end at 10 deg) the push across
      ``n`` ends and the window closes to ``theta_in``: beyond it ``w_a`` loses any part
      that tips the part further and the stop turns it back at ``k_in`` (snapped back at
      ``k_w``, 3 rad/s from 10.8 deg, the peg's swing knocked the bore at 47 N; at ``k_in``
      against the admittance's 0.3 rad/s, a held peg's contact moment held it at 5.9 deg).
      A part in the mouth tilted by ``theta`` meets the bore in two points once ``theta``
      exceeds the clearance ratio ``c`` over the depth's share of the diameter, and wedges
      (Whitney) unless ``theta < c / mu`` (1.5 deg for the 0.24 mm clearance of a 20 mm
      peg, ``mu`` 0.45; ``theta_in`` adds the controller's own error in the tool's
      orientation, 0.5 deg, lest the stop hold the part against the bore); tilted it also
      meets the 45 deg chamfer at ``45 - theta`` deg, which friction holds at
      ``mu >= tan(45 - theta)`` (0.67 at 11 deg): stood up, the chamfer carries it in.

    Args:
        speed: ``w_a`` from :func:`cosmos.osc.admittance.admittance_speed`, world. # (6,)
        tilt: ``Omega_a`` times the pose error (current against goal), world, [m, rad]. # (6,)
        error: ``x - x_d``, world, [m, rad]; ``x_d`` the INSERT's start. # (6,)
        velocity: ``xd``, the tool's twist, world, [m/s, rad/s]. # (6,)
        force_goal: F_d, world (its force part gives ``n`` and ``|F_d|``), [N, N m]. # (6,)
        wrench: F_s, the wrench the tool applies, world, [N, N m]. # (6,)
        omega_bar: Omega_bar, the force axes' selection, world. # (6, 6)
        params: ``theta_w`` [rad], ``k_w`` [1/s], ``d_in`` [m], ``theta_in`` [rad], ``k_in``
            [1/s], ``s``, ``v_s`` [m/s]. # (7,)

    Returns:
        ``(w_a, F_l)``: the admittance speed with the window's stop, and the push across on
        the force axes, world. # (6,), (6,)
    """
    window_rad, rate, entry_depth_m, aligned_rad, aligning_rate, slide_share, slide_speed = (
        float(p) for p in params
    )
    push = np.asarray(force_goal, dtype=float)[:3]
    size = float(np.linalg.norm(push))
    slide = np.zeros(6)
    if not size > 0.0:
        return tilt_window(speed, tilt, window_rad, rate), slide
    n = push / size
    depth = float(n.dot(np.asarray(error)[:3]))
    if depth >= entry_depth_m:
        turning = np.array(speed, dtype=float)
        size_rad = float(np.linalg.norm(tilt[3:]))
        if size_rad > aligned_rad:  # no further over: the part of w_a along the tilt dropped
            out = np.asarray(tilt[3:]) / size_rad
            turning[3:] -= out * max(0.0, float(out.dot(turning[3:])))
        return tilt_window(turning, tilt, aligned_rad, aligning_rate), slide
    lean = np.cross(n, np.asarray(tilt)[3:])
    leaning = float(np.linalg.norm(lean))
    if not leaning > 0.0:
        return tilt_window(speed, tilt, window_rad, rate), slide
    lean /= leaning
    felt = min(max(float(n.dot(np.asarray(wrench)[:3])), 0.0), size)
    fading = max(0.0, 1.0 - float(lean.dot(np.asarray(velocity)[:3])) / slide_speed)
    slide[:3] = slide_share * felt * min(1.0, leaning / window_rad) * fading * lean
    return tilt_window(speed, tilt, window_rad, rate), np.asarray(omega_bar).dot(slide)


def integrated_force_error(
    omega_bar: FloatArray, force_setpoint: FloatArray, force_sensed: FloatArray, push_across: FloatArray
) -> FloatArray:
    """What Figure 2's force integral sums while an INSERT pushes across (:func:`insert_compliance`).

    ``Omega_bar (F_d - F_s)`` less its part along ``F_l``.

    ``F_l`` is fed forward, not tracked: the integral left alone drove the sensed force across
    back to F_d's (none) and took 6 of a 7 N push away, and, tracking it, wound up while the
    tool slid instead of pushing, then threw it across the mouth in free air.

    Args:
        omega_bar: Omega_bar, the force axes' selection, world. # (6, 6)
        force_setpoint: F_d, ramped, world, [N, N m]. # (6,)
        force_sensed: F_s, world, [N, N m]. # (6,)
        push_across: F_l from :func:`insert_compliance`, world (zeros: none). # (6,)

    Returns:
        The force error to integrate, world. # (6,)
    """
    error = np.asarray(omega_bar).dot(np.asarray(force_setpoint) - np.asarray(force_sensed))
    size = float(np.linalg.norm(push_across[:3]))
    if size > 0.0:
        along = np.asarray(push_across[:3]) / size
        error[:3] -= along * float(along.dot(error[:3]))
    return error
