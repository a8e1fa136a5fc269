"""Shared by the sweep tests: a short program whose success depends on a varied parameter."""

from __future__ import annotations

from pathlib import Path

TOUCH_TABLE = Path(__file__).with_name("touch_table.cos")
"""Touches the table below the home pose; fails (no contact in time) if the table is 25-40 mm lower.

On the realistic plant the approach's speed depends on the run's drawn friction and model error
(README, "Measured"), so where it fails depends on the run's seed between about 25 and 40 mm;
the ideal plant's 50.0 mm/s fails from about 15 mm."""
TABLE_Z = "table.z=uniform(-60mm, 0mm)"
