"""The controller's compiled arithmetic (numba), each kernel citing the reference it mirrors.

The readable maths live in :mod:`cosmos.osc` (pure NumPy functions citing the
seed's equations); these run them in the loop, and ``tests/runtime/test_*kernel*.py``
compare each with its reference on seeded random inputs:

* :mod:`~cosmos.runtime.kernels.linear`: small products in plain loops (NumPy's ``@``).
* :mod:`~cosmos.runtime.kernels.evaluation`: one parameter evaluation from Pinocchio's
  ``computeAllTerms`` (Pinocchio's own frame, Jacobian and gravity functions).
* :mod:`~cosmos.runtime.kernels.parameter`: eq. 27-29 and 34 folded for the servo
  (:func:`cosmos.osc.dynamics.operational_dynamics`, :func:`cosmos.osc.unified.servo_matrices`,
  :func:`cosmos.osc.dynamics.null_space_damping`).
* :mod:`~cosmos.runtime.kernels.limits`: what the task gives up near joint limits and singular
  directions (:func:`cosmos.osc.limits.joint_limit_task_projection`,
  :func:`cosmos.osc.limits.joint_limit_constraint`).
* :mod:`~cosmos.runtime.kernels.commands`: the sensed wrench, the unit-mass motion command
  (:mod:`cosmos.osc.motion`) and the saturation (:func:`cosmos.osc.limits.saturate_torque`).
* :mod:`~cosmos.runtime.kernels.contact`: the latches (:mod:`cosmos.osc.contact`), admittance
  (:mod:`cosmos.osc.admittance`) and Coulomb compensation (:mod:`cosmos.osc.friction`).
* :mod:`~cosmos.runtime.kernels.hold_observer`: a free hold's disturbance observer
  (:func:`cosmos.osc.integral_action.observe_hold_disturbance`).
* :mod:`~cosmos.runtime.kernels.servo`: one servo tick composed of the above (and its packed layouts).
* :mod:`~cosmos.runtime.kernels.live`: that tick on the plant's live signals, in one flat workspace.

Task-space quantities (wrenches, twists, Lambda) have six entries; joint-space ones have the
arm's n (6 for the PUMA 560, 7 for the Panda), taken from the arrays' shapes.
"""
