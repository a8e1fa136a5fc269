"""The null space's figures for the README (issue 16 items 2-3), from runs' logs.

    python tests/run/null_space_figures.py    # a few seconds

Prints, for the scenes of tests/run/test_run_null_space.py: how fast the wrist's
self-motion decays after a kick with and without the null-space damping xi_q
(eq. 34, 38), what a POSTURE moves and how far the tool strays meanwhile, and
how far a ball closing on the forearm moves the tool with the links' field
projected into the null space and applied whole.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from tests.run.test_run_null_space import (  # noqa: E402
    BALL_TOWARD_FOREARM,
    HOLD_FREE,
    POSTURE_PROGRAM,
    ServoGains,
    kick_wrist,
    null_space_speed,
    run,
)


def main() -> None:
    """Print the figures."""
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        for xi_q in (20.0, 0.0):
            record = run(tmp, HOLD_FREE, gains=ServoGains(xi_q=xi_q), progress=kick_wrist)
            t, speed = record.state.t, null_space_speed(record)
            kicked = t[np.argmax(speed > 0.5)]
            after = t > kicked
            below = t[after & (speed < 1e-3)]
            settled = f"{below[0] - kicked:.2f} s" if below.size else "never"
            offset = np.linalg.norm(record.state.x - record.state.x[0], axis=1)
            print(
                f"kick {speed[after].max():.2f} rad/s, xi_q {xi_q:g}: |N qd| < 1e-3 rad/s after {settled}; "
                f"2 s on {speed[t > kicked + 2.0].max():.1e} rad/s; tool peak {offset.max() * 1e3:.2f} mm, "
                f"at the end {offset[-1] * 1e3:.3f} mm"
            )
        record = run(tmp, POSTURE_PROGRAM)
        q, t = record.state.q, record.state.t
        moved = np.degrees(q[-1] - q[np.searchsorted(t, 0.5)])
        offset = np.linalg.norm(record.state.x - record.state.x[0], axis=1)
        print(f"POSTURE: joints moved {np.round(moved, 1)} deg; tool within {offset.max() * 1e3:.2f} mm")
        for projected in (True, False):
            record = run(tmp, BALL_TOWARD_FOREARM, project_links=projected)
            offset = np.linalg.norm(record.state.x - record.state.x[0], axis=1)
            how = "through the null space" if projected else "whole"
            print(f"ball closing on the forearm, links' field {how}: tool moved {offset.max() * 1e3:.2f} mm")


if __name__ == "__main__":
    main()
