"""Operational-space control maths (Khatib 1987): pure functions of numpy arrays.

One module per concept, each citing the seed's equations; each is the readable
reference of the compiled kernels that run it (``cosmos/runtime``, ``cosmos/obstacles/kernels``):

* :mod:`~cosmos.osc.dynamics`: Lambda, Jbar, mu, p, N^T (eq. 13, 26-28), singularities (section 5),
  null-space damping (eq. 34).
* :mod:`~cosmos.osc.force`: the selection matrices (Figure 2).
* :mod:`~cosmos.osc.motion`: motion commands F*_m (eq. 19-21, 36-37), timed trajectories.
* :mod:`~cosmos.osc.orientation`: so(3) exp/log, the orientation error, quaternions, RPY.
* :mod:`~cosmos.osc.unified`: the unified motion and force command (eq. 17-18, 29).
* :mod:`~cosmos.osc.held_push`: a push held against a surface, eq. 18 stiffened along it.
* :mod:`~cosmos.osc.limits`: torque saturation and the joint-limit potential (section 6).
* :mod:`~cosmos.osc.firas`: FIRAS repulsion and capsule-to-obstacle proximity (section 6).
* :mod:`~cosmos.osc.friction`: Coulomb friction compensation toward the commanded motion.
* :mod:`~cosmos.osc.contact`: the segment's touch latch (force integral) and contact latch.
* :mod:`~cosmos.osc.admittance`: admittance control of compliant moment axes in contact.

Conventions: world axes; twists and wrenches are ``[linear; angular]``; the
operational error is ``x - x_d = (p - p_d, log(R R_d^T))``.
"""
