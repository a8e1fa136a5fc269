"""Whether the tool is within a small distance of a fixture, touching or not (MuJoCo's distances).

A peg that slid into its bore's clearance touches nothing and is at the hole all the same; the
protective stops ask at each segment's start (:mod:`cosmos.execution.supervision`). A MuJoCo
distance costs 1-100 us a pair, and a tool and the fixtures make hundreds of pairs: only the
pairs whose bounding boxes (MuJoCo's ``geom_aabb``, turned into the world) come that close are
measured. Two geoms farther apart than that along any world axis are farther apart than that,
so the answer is the one every pair's distance gives.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.plant import Plant

FloatArray = np.ndarray


class FixtureReach:
    """The tool's pairs of geoms with the fixtures, and how near the tool is to them.

    Args:
        plant: The workcell.
        tool_fixture: Whether each pair of geoms is the tool and a fixture. # (ngeom, ngeom) bool
    """

    def __init__(self, plant: Plant, tool_fixture: np.ndarray):
        model = plant.model
        self._model, self._data = model, plant.data
        self._pairs = pairs = np.argwhere(np.triu(tool_fixture))  # (k, 2)
        self._geoms = geoms = np.unique(pairs)
        self._rows = np.searchsorted(geoms, pairs)  # each pair's geoms as rows of the boxes below
        aabb = model.geom_aabb[geoms]  # in each geom's frame: centre, half sizes
        self._centre, self._half = aabb[:, :3], aabb[:, 3:]
        plane = model.geom_type[geoms] == mujoco.mjtGeom.mjGEOM_PLANE  # unbounded: always measured
        self._plane_pair = plane[self._rows[:, 0]] | plane[self._rows[:, 1]]

    def within(self, distance_m: float) -> bool:
        """Whether a geom of the tool is within ``distance_m`` of a fixture's, now [m]."""
        if not len(self._pairs):
            return False
        data, geoms = self._data, self._geoms
        xmat = data.geom_xmat[geoms].reshape(-1, 3, 3)
        centre = data.geom_xpos[geoms] + np.einsum("gij,gj->gi", xmat, self._centre)
        half = np.einsum("gij,gj->gi", np.abs(xmat), self._half)
        first, second = self._rows[:, 0], self._rows[:, 1]
        apart = (np.abs(centre[first] - centre[second]) - half[first] - half[second]).max(axis=1)
        close = self._pairs[(apart < distance_m) | self._plane_pair].tolist()
        model, fromto = self._model, np.zeros(6)
        return any(
            mujoco.mj_geomDistance(model, data, g1, g2, distance_m, fromto) < distance_m for g1, g2 in close
        )
