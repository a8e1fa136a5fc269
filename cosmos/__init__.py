"""COSMOS: Control in Operational Space of a Manipulator-with-Obstacles System.

The Python API (docs/python.md)::

    import cosmos

    run = cosmos.run("programs/peg_in_hole.cos", seed=0)  # a path or program text
    run.ok, run.outcome, run.events, run.states, run.log_path, run.plot()
    cosmos.load(run.log_path) == run
    cosmos.check("MOVE BY (0, 0, 50 mm)")  # the plan, or CosmosError with its location

``import cosmos`` loads none of the heavy modules (MuJoCo, Pinocchio, numba,
pandas, matplotlib): the API's names are imported on first use.
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

from cosmos.errors import CosmosError, ProgramError, TaskFailure, UsageError

if TYPE_CHECKING:
    from cosmos.api import CosmosWarning, check, load, run
    from cosmos.run_result import Failure, OutcomeKind, Run

__version__ = "0.1.0"
"""The package's version, read by the build (``[tool.hatch.version]``): no metadata lookup at start-up."""

_LAZY = {
    "run": "cosmos.api",
    "load": "cosmos.api",
    "check": "cosmos.api",
    "CosmosWarning": "cosmos.api",
    "Run": "cosmos.run_result",
    "Failure": "cosmos.run_result",
    "OutcomeKind": "cosmos.run_result",
}

__all__ = [
    "CosmosError",
    "CosmosWarning",
    "Failure",
    "OutcomeKind",
    "ProgramError",
    "Run",
    "TaskFailure",
    "UsageError",
    "__version__",
    "check",
    "load",
    "run",
]


def __getattr__(name: str) -> Any:
    """The API's functions and classes, imported on first use."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'cosmos' has no attribute '{name}'")
    value = getattr(import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
