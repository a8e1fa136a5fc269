"""The obstacle field as the servo takes it: split by link, handed over only when it changed.

The runtime asks the field at every parameter evaluation (125 Hz). The servo's
``link_field`` setter folds the field into the held torques and reshapes them
through the null space (:mod:`cosmos.runtime.null_space`): it is the dearest part
of the hand-over, and it changes nothing when the field is the one the servo
holds and exerts no torque (the evaluation just folded that one in). So the
split is built once per evaluation of the field, and the same object is kept
while the field is held between evaluations or evaluates to nothing again
with the same nearest link.
"""

from __future__ import annotations

import numpy as np

from cosmos.obstacles import ObstacleField
from cosmos.runtime.null_space import LinkField

FloatArray = np.ndarray


class FieldSplit:
    """The last split of one obstacle field, and whether it pushes."""

    def __init__(self, dof: int) -> None:
        zeros = np.zeros(dof)
        self._split = LinkField(zeros, zeros)
        self._of: FloatArray | None = None  # the torque the split was made from
        self.pushing = False
        """Whether the last split exerts any torque."""

    def link_field(self, field: ObstacleField, q: FloatArray, qd: FloatArray, t_s: float) -> LinkField:
        """The field's torque at ``(q, qd, t_s)`` split into the tool's link and the others, with the nearest.

        The same object while the field is held between evaluations, or evaluates to
        nothing again with the same nearest link.
        """
        torque = field.torque(q, qd, t_s)
        if torque is self._of:
            return self._split
        self._of = torque
        nearest = field.nearest_link
        pushing = any(torque.tolist())  # (ndarray.any takes five times as long)
        held = self._split
        if pushing or self.pushing or nearest != (held.clearance_m, held.link, held.obstacle):
            links = field.link_torque
            self._split = LinkField(torque - links, links, *nearest)
        self.pushing = pushing
        return self._split
