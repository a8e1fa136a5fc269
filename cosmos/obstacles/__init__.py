"""Real-time obstacle avoidance with artificial potential fields (seed section 6).

(The field's cost in the servo loop is measured by :mod:`cosmos.bench.obstacles`.)

* :mod:`~cosmos.obstacles.obstacle`: an obstacle (primitive, pose, velocity).
* :mod:`~cosmos.obstacles.scene`: obstacles as geoms of the MuJoCo workcell (:data:`CAPACITY` at once).
* :mod:`~cosmos.obstacles.gate`: MuJoCo's contact test off, for a step, for bodies clear of the world.
* :mod:`~cosmos.obstacles.capsules`: the arm's links and tool as capsules.
* :mod:`~cosmos.obstacles.proximity`: capsule-to-obstacle distances (firas; the reference).
* :mod:`~cosmos.obstacles.geometry`: the controller's geometric model for fast distances.
* :mod:`~cosmos.obstacles.kernels.distance`, :mod:`~cosmos.obstacles.kernels.candidates`,
  :mod:`~cosmos.obstacles.kernels.geometry`: its compiled arithmetic (closed-form distances,
  candidate lists, closest points, estimates).
* :mod:`~cosmos.obstacles.field`: the FIRAS field as joint torques (a runtime potential field).
* :mod:`~cosmos.obstacles.kernels.field`: the field's compiled arithmetic (kinematics, torques).
* :mod:`~cosmos.obstacles.kernels.gate`: the gate's proof, compiled.
* :mod:`~cosmos.obstacles.minima`: detection of local minima.
* :mod:`~cosmos.obstacles.collisions`: contacts the arm should not make.
"""

from cosmos.obstacles.capsules import ARM_BODIES, LINK_BODIES, LinkCapsules, arm_capsules
from cosmos.obstacles.collisions import Collision, collisions
from cosmos.obstacles.field import FieldParameters, Influence, ObstacleField
from cosmos.obstacles.gate import ContactGate
from cosmos.obstacles.minima import LocalMinimum, LocalMinimumDetector
from cosmos.obstacles.obstacle import Obstacle, from_step
from cosmos.obstacles.scene import CAPACITY, DEFAULT_SLOTS, ObstacleScene, obstacle_scene_xml

__all__ = [
    "ARM_BODIES",
    "CAPACITY",
    "DEFAULT_SLOTS",
    "LINK_BODIES",
    "Collision",
    "ContactGate",
    "FieldParameters",
    "Influence",
    "LinkCapsules",
    "LocalMinimum",
    "LocalMinimumDetector",
    "Obstacle",
    "ObstacleField",
    "ObstacleScene",
    "arm_capsules",
    "collisions",
    "from_step",
    "obstacle_scene_xml",
]
