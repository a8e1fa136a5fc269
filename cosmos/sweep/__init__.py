"""Sweeps: a program run many times in varied workcells, and its success rate.

* :mod:`~cosmos.sweep.parameters`: what may vary, the distributions, each run's draws.
* :mod:`~cosmos.sweep.variation`: a run's varied workcell, applied to the plant's scene.
* :mod:`~cosmos.sweep.worker`: one run, in whatever process makes it; :mod:`~cosmos.sweep.tap`
  keeps what the sweep needs of the values its log is given.
* :mod:`~cosmos.sweep.engines`: the local pool of worker processes and the Dask cluster.
* :mod:`~cosmos.sweep.results`: the sweep's definition and its resumable results file.
* :mod:`~cosmos.sweep.report`, :mod:`~cosmos.sweep.plot`: the figures, for people and machines.

``cosmos sweep`` (``cosmos.commands.sweep``) ties them together; docs/sweep.md explains.
"""
