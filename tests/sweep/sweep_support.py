"""Shared by the sweep tests: a short program whose success depends on a varied parameter."""

from __future__ import annotations

from pathlib import Path

TOUCH_TABLE = Path(__file__).with_name("touch_table.cos")
"""Touches the table below the home pose; fails (no contact in time) if the table is ~15 mm lower."""
TABLE_Z = "table.z=uniform(-30mm, 0mm)"
