"""Shared by the sweep tests: a short program whose success depends on a varied parameter."""

from __future__ import annotations

from pathlib import Path

TOUCH_TABLE = Path(__file__).with_name("touch_table.cos")
"""Touches the table below the home pose; fails (no contact in time) if the table is about 15 mm lower.

The approach cruises at its 50 mm/s on either plant (cosmos.osc.cruise_speed; before, on the
realistic plant its speed depended on the run's drawn friction and model error and it failed
from 25-40 mm): with seed 5 the draws fail from 15.5-16.6 mm and succeed up to 15.2 mm."""
TABLE_Z = "table.z=uniform(-30mm, 0mm)"
