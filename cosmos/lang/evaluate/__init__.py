"""Evaluate: expressions to values with units (``values``), by the ``evaluator``."""
