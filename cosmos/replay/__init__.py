"""Offline use of run logs: statement timeline, text summary, plots."""
