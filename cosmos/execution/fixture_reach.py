"""Whether the tool is within a small distance of a fixture, touching or not (MuJoCo's distances).

A peg that slid into its bore's clearance touches nothing and is at the hole all the same; the
protective stops ask at each segment's start (:mod:`cosmos.execution.supervision`). A MuJoCo
distance costs 1-100 us a pair, and a tool and the fixtures make hundreds of pairs: only the
pairs whose bounding boxes (MuJoCo's ``geom_aabb``, turned into the world) come that close are
measured, and only for the fixtures whose box comes that close to the box around the whole tool.
Two geoms farther apart than that along a world axis are farther apart than that, so the answer
is the one every pair's distance gives.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.plant import Plant

FloatArray = np.ndarray


class FixtureReach:
    """The tool's geoms, the fixtures' geoms they may touch, and how near the tool is to them.

    Args:
        plant: The workcell.
        tool: Whether each geom is the tool's. # (ngeom,) bool
        tool_fixture: Whether each pair of geoms is the tool and a fixture. # (ngeom, ngeom) bool
    """

    def __init__(self, plant: Plant, tool: np.ndarray, tool_fixture: np.ndarray):
        model = plant.model
        self._model, self._data = model, plant.data
        tools = np.flatnonzero(tool)
        fixtures = np.flatnonzero(tool_fixture[tools].any(axis=0))
        self._geoms = np.concatenate((tools, fixtures))  # the boxes below: the tool's, then the fixtures'
        self._tools = len(tools)
        self._pairs = tool_fixture[np.ix_(tools, fixtures)]  # (tools, fixtures)
        aabb = model.geom_aabb[self._geoms]  # in each geom's frame: centre, half sizes
        self._centre, self._half = aabb[:, :3, None], aabb[:, 3:, None]
        self._plane = model.geom_type[fixtures] == mujoco.mjtGeom.mjGEOM_PLANE  # unbounded: measured
        self._paired = self._pairs.any(axis=0)  # each fixture geom paired with a geom of the tool
        self._any_pair = bool(self._paired.any())

    def within(self, distance_m: float) -> bool:
        """Whether a geom of the tool is within ``distance_m`` of a fixture's, now [m]."""
        if not self._any_pair:
            return False
        data, geoms, n = self._data, self._geoms, self._tools
        xmat = data.geom_xmat[geoms].reshape(-1, 3, 3)
        centre = data.geom_xpos[geoms] + (xmat @ self._centre)[:, :, 0]
        half = (np.abs(xmat) @ self._half)[:, :, 0]
        low, high = centre - half, centre + half
        tool_low, tool_high = low[:n].min(axis=0), high[:n].max(axis=0)
        near = ((low[n:] - tool_high < distance_m) & (tool_low - high[n:] < distance_m)).all(axis=1)
        near = np.flatnonzero((near | self._plane) & self._paired)
        if not len(near):
            return False
        # Each near fixture against each of the tool's geoms it pairs with: their boxes' gap.
        apart = np.maximum(low[n + near][None] - high[:n, None], low[:n, None] - high[n + near][None]).max(
            axis=2
        )
        close = np.argwhere(self._pairs[:, near] & ((apart < distance_m) | self._plane[near][None]))
        model, fromto = self._model, np.zeros(6)
        return any(
            mujoco.mj_geomDistance(model, data, int(geoms[t]), int(geoms[n + near[f]]), distance_m, fromto)
            < distance_m
            for t, f in close.tolist()
        )
