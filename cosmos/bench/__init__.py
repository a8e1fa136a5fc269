"""The benchmarks behind ``cosmos bench``, together: each figure beside the floor it is judged against.

* :mod:`~cosmos.bench.servo`: the bench loop (a representative workload) per phase, and the floor
  (``mj_step`` + Pinocchio replaying the workload's torques).
* :mod:`~cosmos.bench.programs`: what users run: the shipped programs through the executor, whole
  ``cosmos run`` processes, start-up, a first run with an empty kernel cache.
* :mod:`~cosmos.bench.obstacles`: the servo tick among 0, 10 and 50 obstacles against a bare tick.
* :mod:`~cosmos.bench.language`: compiling a 10,000-line program; ``cosmos check`` end to end.
* :mod:`~cosmos.bench.suite`: all of them in one run, as one dictionary of figures.
"""
