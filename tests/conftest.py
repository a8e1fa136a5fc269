"""Set-up shared by the whole suite, before any test module imports MuJoCo."""

import os

# MuJoCo picks its OpenGL backend once, at its first import; without a display its default
# (GLFW) cannot render, and the tests that write a video (``cosmos replay --video``) failed
# whenever a test module imported MuJoCo before the replay could choose EGL itself
# (cosmos.replay.playback.prefer_headless_gl). The README's test command sets nothing.
os.environ.setdefault("MUJOCO_GL", "egl")
