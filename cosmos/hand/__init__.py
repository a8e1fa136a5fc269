"""The hand on the flange: the welded peg or a parallel two-finger gripper with finger sensing.

- :mod:`cosmos.hand.tool`: which hand a program runs with (``TOOL PEG`` / ``TOOL GRIPPER``)
  and the gripper's datasheet; no simulator, the language may import it.
- :mod:`cosmos.hand.gripper_scene`: the gripper mounted in a workcell's MuJoCo spec, below
  the wrist sensor.
- :mod:`cosmos.hand.fingers`: the plant's finger drive and finger force sensors.
"""
