"""An INSERT's push held to a speed reference that rises to its aim (eq. 20-21's V_max on a force axis).

An INSERT's SPEED limits the insertion axis (docs/language.md). Its push is capped by a
unit-mass velocity servo (:func:`cosmos.osc.unified.speed_limited_push`). On the realistic
plant (docs/plant.md) the velocity that servo sees is the 40 Hz observer's on the encoders'
counts (one count is 30-50 um of the tool's travel): +-3 mm/s of noise and an 8 ms lag. With
the cap aimed at the SPEED's aim outright, a dip (the landing on the chamfer slows the peg by
1-2 mm/s) was recovered at ``kv`` times the dip, and the lag let the speed past the aim by
``kv tau`` times the dip (2.4 at kv = 300/s): SPEED 5 mm/s peaked at 5.6-6.65 mm/s.

So the servo tracks a **speed reference** ``v_r`` that rises to the aim at ``rate`` aims a
second, its rise fed forward (eq. 19's ``xdd_d`` for a speed)::

    F*_n = a_r + kv (v_r - n^T xd),   dv_r/dt = a_r = rate aim  (0 once v_r = aim)

and, whenever the push is at its force rather than its speed (the cap does not bind: the
landing, a jam, pressing), ``v_r`` follows the tool's speed. A re-acceleration then rises at
``rate aim``, and the lag's overshoot is ``tau rate aim`` instead of ``kv tau`` times the
dip. The reference starts each segment at the tool's speed.

The aim is ``min(0.9 SPEED, SPEED - 1 mm/s)`` (at least half the SPEED): the ripple the
encoders' noise leaves in the true speed is absolute, about a millimetre per second whatever
the SPEED, so at SPEED 5 mm/s the push aims at 4 mm/s.

The approach (eq. 20-21 without integral action, kv = 40/s) leaves a model error's
``Lambda^-1 f / kv`` as a speed error, 2.7 mm/s on seed 1's drawn arm at every SPEED (12.7,
22.85, 32.8 mm/s at 10, 20, 30), so it runs 3 mm/s under 1.1 SPEED (:func:`approach_speed`).
The rate is 60 aims/s: slower, the peg lingers on the chamfer and the compliant wrist tilts.
Measured on both plants, seeds 0-4, the peak over 20 ms of MuJoCo's tool point: README,
"INSERT speed" (tests/run/insert_speed_seeds.py).

Measured and not kept (2026-11-24; realistic plant, seeds 0-4, unless said):

* The reference at 8 aims/s with kv 150/s kept every SPEED of 5-30 mm/s within 10 % on both
  plants; at 30 aims/s (kv 300/s) SPEED 5 peaked at 4.9-5.7 mm/s. But a peg slower through the
  chamfer let the compliant wrist tilt to its 10 deg window and jam: ``grasp_and_insert.cos``
  (the peg held in a gripper) seeds 4 and 6 jammed 8.3-8.6 mm in at 8 aims/s, and a Lissajous
  search (tests/run/test_run_search.py, seed 3) 4.9 mm in at 30. Without the reference, the
  slower approach's landing was recovered past SPEED 10 (11.55 mm/s, seed 0).
* The approach held by the push's servo (kv 150/s): the noise's acceleration on the gripper's
  1.8 kg read as a 2.5 N touch 12 ms into it (its gate is 2 N); at 40-80/s seed 1 still ran
  10.65-12.1 mm/s at SPEED 10. A position reference along the approach (eq. 19, its lead
  bounded to 0.5 mm) crawled at SPEED 5 (1 mm/s) and overshot at 10 (11.85 mm/s).
* Integral action on the push's speed error (100-300/s with 300-2,500/s^2, gated to a moving
  tool): the bore's grazes became stick-slip (1.5-7 mm/s at SPEED 5 on the ideal plant).

* The approach landing at 10 mm/s whatever the SPEED (with the cruise integral, or without it at
  8 mm/s), braked (:func:`cosmos.osc.contact.touch_braking`): the shipped peg sweep's INSERT
  peaked at 16.7 N at the 95th percentile, 23.0 N at most (run 7, a peg pressed on the mouth's
  edge 0.65 s after its touch), against 19.5 N and 37.4 N braked at its SPEED, and 60/60; but
  the insertion after that gentle landing stalled in the bore at SPEED 20 and 30 mm/s (the share
  of the insertion within half its SPEED 0.93 -> 0.40 at SPEED 30 on the ideal plant, 0.97 ->
  0.61 at SPEED 20 on the realistic plant's seed 1; tests/run/test_run_insert_speed.py fails).

SPEED 5 mm/s on the realistic plant peaked 30 % over (6.50 mm/s, seed 0) until the scenes'
collider tolerance went to 1e-8 (5.30 mm/s since: tests/run/test_run_insert_speed.py). What was
left of it then, measured (2026-11-24, seeds 0-4, peaks in mm/s):
the speed this servo reads. At 5 mm/s a joint turns one encoder count every 6-9 ms, and the
observer answers each count with a bump of 3-5 mm/s at the tool that dies in 10-20 ms: its
estimate swings between 0 and twice the speed. The servo (kv = 300/s, with the observer's lag a
loop damped at 0.12 near 30 Hz) turns those bumps into pushes, and on the chamfer, where the
compliant axes let the peg slide down, the true speed rings 1-8.5 mm/s. With everything else
realistic, the cap reading MuJoCo's tool speed peaks at 3.95-4.45 (main: 6.50, 5.85, 5.00, 5.30,
4.80); the encoders' counts made 10^4 times finer, the observer's 8 ms lag kept, at 4.15-4.85;
the joints' friction compensated with the noise taken out of its intent (the dead band) at 4.75-5.90.

Measured and not kept (2026-11-24; realistic plant, seeds 0-4, unless said):

* Catching up more slowly than braking (kv 300/s above the reference, less below it: a count's
  dip read as a real one is recovered at the lower gain): 200/s 4.50-5.15 mm/s, but the peg above
  half its SPEED for 40-52 % of the INSERT (main 46-58 %; the approach's crawl at 0.9 mm/s is a
  third of it), on the ideal plant 46-49 % (main 56-61 %); 225/s 4.45-5.20 on seeds 0-4 but 5.90
  and 6.30 on seeds 5 and 8 (main 5.55, 7.30); 250/s up to 5.80.
* A lower kv alone (the loop better damped): 150/s 4.40-6.10, 100/s 4.30-6.25 mm/s, the peak moved
  to the push's first 40 ms (the chamfer's slide outruns the weaker brake) and the peg slower.
* A model-based estimate of the speed along the push (the commanded unit-mass acceleration
  ``m_n^-1 (n^T F_fb - n^T F_s) - k_vf n^T xd`` integrated and corrected toward the observer's, with
  or without a bounded estimate of the disturbance): the joints' friction is most of the motion's
  dynamics at 5 mm/s and is not in the model: 3.9-7.6 mm/s with the peg crawling (some runs
  timed out), or, with the disturbance estimated, 4.45-12.6 mm/s (a stuck peg winds it up).
* A position reference along the push (eq. 19: ``kp`` on the travel the encoders' angles measure,
  its lead bounded to 0.1-0.3 mm, kv 40-100/s): 4.60-6.65 mm/s, a 0.3 mm lead 8.05-9.35 mm/s
  after each stick; kv 40/s failed two seeds.
* The joints' friction compensated toward at least 6 mm/s along the push while the cap binds (the
  commanded direction past the compensation's 0.01 rad/s ramp): on the ideal plant SPEED 3 mm/s, which
  crawls at 1.2 mm/s (aim 2) and times out at 20 s on every seed, went in within 17.3-18.1 s at
  2.80-2.95 mm/s, SPEED 5 at 4.10-4.40; on the realistic plant SPEED 5 peaked at 5.05-6.35 (seed 1
  worse, 6.35 against 5.85) and SPEED 3 at 3.2-3.9 mm/s, 2 of 5 in (main 1). Toward 10 mm/s,
  5.20-6.40 at SPEED 5; toward 6 mm/s with the catch-up at 200/s, 4.45-5.50: at the bar, not within.
* The speed from the counts' timing (the joints' travel between the newest count and one at least
  4-10 ms before it): 5.05-8.40 mm/s at 300/s (a later, staircase estimate), crawling at 100/s.

The compiled servo runs the same arithmetic (:mod:`cosmos.runtime.kernels.push_speed`).
"""

from __future__ import annotations

MIN_AIM_SHARE = 0.5
"""The aim is never below this share of the SPEED."""


def push_aim(max_speed: float, aim: float, margin_mps: float) -> float:
    """The speed an INSERT's push aims at: ``max(min(aim V, V - margin), V / 2)``, in [m/s].

    Args:
        max_speed: The INSERT's SPEED V, in [m/s].
        aim: The share of V aimed at (``ServoGains.push_speed_aim``).
        margin_mps: The least margin below V (``ServoGains.push_speed_margin_mps``), in [m/s].
    """
    return max(min(aim * max_speed, max_speed - margin_mps), MIN_AIM_SHARE * max_speed)


def speed_reference_step(
    reference: float | None, aim: float, along: float, rate: float, dt_s: float
) -> tuple[float, float]:
    """One step of the speed reference ``v_r`` toward ``aim`` (module docstring).

    Args:
        reference: ``v_r`` so far, in [m/s]; None on the first tick (it starts at the
            tool's speed, ``along`` clipped to ``[0, aim]``).
        aim: The speed aimed at, in [m/s].
        along: The tool's speed along the push, in [m/s].
        rate: The reference's rise, in aims per second [1/s].
        dt_s: Servo period, in [s].

    Returns:
        ``(v_r, a_r)``: the new reference [m/s] and its rate of rise this tick [m/s^2].
    """
    if reference is None:
        reference = min(max(along, 0.0), aim)
    step = min(rate * aim * dt_s, max(aim - reference, 0.0))
    return min(reference + step, aim), step / dt_s


def follow_the_tool(along: float, aim: float) -> float:
    """``v_r`` while the push is at its force, not its speed: the tool's speed within ``[0, aim]``."""
    return min(max(along, 0.0), aim)


APPROACH_MARGIN_SHARE = 0.25
"""The approach's margin never takes more than this share of its SPEED (it then runs at it)."""


def approach_speed(max_speed: float, margin_mps: float) -> float:
    """An INSERT's approach's speed limit, in [m/s]: ``min(V, 1.1 V - margin)``, or V below 0.75 V.

    The approach is eq. 20-21 (kv = 40/s, no integral: its 2 mm are too short for one), which
    leaves a model error's ``Lambda^-1 f / kv`` as a speed error: seed 1's drawn arm ran it
    2.7 mm/s fast at every SPEED (12.7, 22.85, 32.8 mm/s at 10, 20, 30). Aimed ``margin`` under
    the 10 % the SPEED allows, that error stays within it. Where the margin would take more than
    a quarter of the SPEED (below 8.6 mm/s at 3 mm/s) the approach keeps its SPEED: there eq. 20
    meets the joints' friction compensation's ramp and crawls anyway (1 mm/s at SPEED 5; at
    2.5 mm/s it crawled at 0.4-0.6 mm/s, the approach taking 6-12 s).

    Args:
        max_speed: The INSERT's SPEED V, in [m/s].
        margin_mps: ``ServoGains.approach_speed_margin_mps``, in [m/s].
    """
    speed = min(max_speed, 1.1 * max_speed - margin_mps)
    return speed if speed >= (1.0 - APPROACH_MARGIN_SHARE) * max_speed else max_speed
