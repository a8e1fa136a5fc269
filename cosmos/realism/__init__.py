"""The realistic plant: how the simulated arm and its sensors differ from the model the controller has.

* :mod:`~cosmos.realism.arm_error`: link masses and inertias, rotor inertia, friction
  (with the published asymmetry), drawn from the run's seed;
* :mod:`~cosmos.realism.encoders`: encoder quantisation and the velocity observer;
* :mod:`~cosmos.realism.wrist_sensor`: the wrist sensor's bandwidth and bias;
* :mod:`~cosmos.realism.plant_realism`: all of it for one run (:class:`PlantRealism`);
* :mod:`~cosmos.realism.kernel`: the per-step sensing, compiled.

``--ideal`` (``cosmos run``, ``cosmos sweep``, ``cosmos.run(..., ideal=True)``) runs the
plant without any of it: the controller's own model, exact ``qpos``/``qvel``.
"""

from cosmos.realism.plant_realism import PlantRealism

__all__ = ["PlantRealism"]
