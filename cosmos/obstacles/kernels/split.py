"""One group's subtree of the world's hierarchy, split by the surface-area heuristic, compiled (numba).

:func:`cosmos.obstacles.hierarchy.layout` splits each group of leaves into a binary tree: at
every node the leaves sorted along each axis, every cut scored (:func:`cosmos.obstacles.hierarchy.
best_split`). In NumPy each node cost 30 to 60 us of small array calls, the world's 120 leaves 8 ms
at the first tick after an ``OBSTACLE`` (the executor's time); here a group is one call, with the
same arithmetic in the same order, so the tree is the same to the bit.
"""

from __future__ import annotations

import numpy as np
from numba.core import types

from cosmos.jit import kernel

FloatArray = np.ndarray
IntArray = np.ndarray


_INDEX = types.Array(types.int32, 1, "C")


@kernel
def _stable_order_into(keys: FloatArray, order: IntArray) -> None:
    """The indices that sort ``keys``, equal keys in their order (an insertion sort: a node has few)."""
    for j in range(keys.shape[0]):
        order[j] = j
        i = j
        while i > 0 and keys[order[i - 1]] > keys[j]:
            order[i] = order[i - 1]
            i -= 1
        order[i] = j


@kernel(
    types.int64(
        types.Array(types.float64, 2, "C", readonly=True),
        types.Array(types.int64, 1, "C", readonly=True),
        types.float64,
        types.int64,
        types.int64,
        types.Array(types.int32, 2, "C"),
        _INDEX,
        types.Array(types.float64, 2, "C"),
        _INDEX,
    )
)
def split_into(
    boxes: FloatArray,
    members: IntArray,
    reach_m: float,
    first: int,
    level: int,
    child: IntArray,
    leaf: IntArray,
    box: FloatArray,
    depth: IntArray,
) -> int:
    """Write the subtree over leaves ``members`` into the tree's arrays from node ``first`` on.

    Nodes are numbered as :func:`~cosmos.obstacles.hierarchy.layout` numbers them: each
    before its children, the first child's subtree before the second's.

    Args:
        boxes: Every leaf's box, centre and half-sizes, [m]. # (n, 6)
        members: The group's leaves (indices into ``boxes``). # (k,)
        reach_m: What is tested against the boxes reaches this far [m] (the heuristic's growth).
        first: The subtree's root node.
        level: The root's depth.
        child: Per node, its two children (-1 for none), written. # (nodes, 2)
        leaf: Per node, its leaf or -1, written. # (nodes,)
        box: Per node, its box, written. # (nodes, 6)
        depth: Per node, its depth, written. # (nodes,)

    Returns:
        The first node after the subtree.
    """
    count = members.shape[0]
    order = members.copy()  # the leaves, regrouped as they are split: a node owns order[lo:hi]
    stack = np.empty((count, 5), dtype=np.int64)  # lo, hi, depth, parent, side: a node to write
    stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3], stack[0, 4] = 0, count, level, -1, 0
    top = 1
    index = first
    for _ in range(2 * count - 1):
        top -= 1
        lo, hi, node_depth, parent, side = (
            stack[top, 0],
            stack[top, 1],
            stack[top, 2],
            stack[top, 3],
            stack[top, 4],
        )
        node = index
        index += 1
        if parent >= 0:
            child[parent, side] = node
        depth[node] = node_depth
        for a in range(3):  # cosmos.obstacles.hierarchy.union
            low, high = np.inf, -np.inf
            for j in range(lo, hi):
                b = boxes[order[j]]
                low = min(low, b[a] - b[a + 3])
                high = max(high, b[a] + b[a + 3])
            box[node, a] = (low + high) / 2.0
            box[node, a + 3] = (high - low) / 2.0
        k = hi - lo
        if k == 1:
            leaf[node] = order[lo]
            continue
        best_cost, best_axis, best_cut = np.inf, 0, 1
        sorted_along = np.empty((3, k), dtype=np.int64)
        head = np.empty(k)
        tail = np.empty(k)
        for a in range(3):  # cosmos.obstacles.hierarchy.best_split
            centres = np.empty(k)
            for j in range(k):
                centres[j] = boxes[order[lo + j], a]
            _stable_order_into(centres, sorted_along[a])  # as NumPy's "stable" argsort
            lows = np.empty((k, 3))
            highs = np.empty((k, 3))
            for j in range(k):
                b = boxes[order[lo + sorted_along[a, j]]]
                for i in range(3):
                    lows[j, i] = b[i] - b[i + 3] - reach_m
                    highs[j, i] = b[i] + b[i + 3] + reach_m
            x0, y0, z0, x1, y1, z1 = np.inf, np.inf, np.inf, -np.inf, -np.inf, -np.inf
            for j in range(k):  # the boxes of leaves 0..j
                x0, y0, z0 = min(x0, lows[j, 0]), min(y0, lows[j, 1]), min(z0, lows[j, 2])
                x1, y1, z1 = max(x1, highs[j, 0]), max(y1, highs[j, 1]), max(z1, highs[j, 2])
                ex, ey, ez = x1 - x0, y1 - y0, z1 - z0
                head[j] = ex * ey + ey * ez + ez * ex
            x0, y0, z0, x1, y1, z1 = np.inf, np.inf, np.inf, -np.inf, -np.inf, -np.inf
            for j in range(k - 1, -1, -1):  # the boxes of leaves j..k-1
                x0, y0, z0 = min(x0, lows[j, 0]), min(y0, lows[j, 1]), min(z0, lows[j, 2])
                x1, y1, z1 = max(x1, highs[j, 0]), max(y1, highs[j, 1]), max(z1, highs[j, 2])
                ex, ey, ez = x1 - x0, y1 - y0, z1 - z0
                tail[j] = ex * ey + ey * ez + ez * ex
            for cut in range(1, k):  # the first cheapest, axis by axis (NumPy's argmin)
                cost = head[cut - 1] * float(cut) + tail[cut] * float(k - cut)
                if cost < best_cost:
                    best_cost, best_axis, best_cut = cost, a, cut
        regrouped = np.empty(k, dtype=np.int64)
        for j in range(k):
            regrouped[j] = order[lo + sorted_along[best_axis, j]]
        order[lo:hi] = regrouped
        middle = lo + best_cut
        stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3], stack[top, 4] = (
            middle,
            hi,
            node_depth + 1,
            node,
            1,
        )
        stack[top + 1, 0], stack[top + 1, 1], stack[top + 1, 2], stack[top + 1, 3], stack[top + 1, 4] = (
            lo,
            middle,
            node_depth + 1,
            node,
            0,
        )
        top += 2
    return index
