"""The obstacle field's compiled arithmetic (numba), each kernel beside the reference it mirrors.

* :mod:`~cosmos.obstacles.kernels.distance`: closed-form capsule distances (MuJoCo's
  ``mjc_SphereCapsule``/``mjc_PlaneCapsule``; readable: :func:`cosmos.osc.firas.capsule_sphere`,
  :func:`cosmos.osc.firas.capsule_plane`) and a point's signed distance
  (:func:`cosmos.obstacles.proximity.signed_distances`).
* :mod:`~cosmos.obstacles.kernels.candidates`: which pairs to query at a measurement.
* :mod:`~cosmos.obstacles.kernels.field`: the chain's kinematics (Pinocchio's) and section 6's
  FIRAS torques (:func:`cosmos.osc.firas.repulsion_magnitude`).
* :mod:`~cosmos.obstacles.kernels.geometry`: closest points kept and estimated between measurements.
"""
