"""The COSMOS task language: parse, check and compile programs to plans.

Entry points (imported lazily, so that :mod:`cosmos.plan` can use the helpers
of this package without an import cycle):

- :func:`compile_program` (source, file, fixtures) -> :class:`cosmos.plan.Plan`
- :class:`Compiler` for statement-by-statement compilation (the REPL), with
  :class:`CompileState` carried between inputs
- :func:`parse_program` (source, file) -> :class:`cosmos.lang.ast.Program`
- :func:`needs_more_input` (text) -> whether a REPL input has an open block
- :func:`bench_compile` (lines) -> seconds to parse and compile a long program
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from cosmos.lang.bench import bench_compile, bench_program
    from cosmos.lang.compiler import (
        Compiler,
        ProgramErrors,
        StatementResult,
        compile_program,
        statement_text,
    )
    from cosmos.lang.parser import needs_more_input, parse_program
    from cosmos.lang.source import decode_source, read_source
    from cosmos.lang.state import CompileState, Defaults, HeldContact

_EXPORTS = {
    "bench_compile": "cosmos.lang.bench",
    "bench_program": "cosmos.lang.bench",
    "Compiler": "cosmos.lang.compiler",
    "ProgramErrors": "cosmos.lang.compiler",
    "StatementResult": "cosmos.lang.compiler",
    "compile_program": "cosmos.lang.compiler",
    "statement_text": "cosmos.lang.compiler",
    "needs_more_input": "cosmos.lang.parser",
    "parse_program": "cosmos.lang.parser",
    "decode_source": "cosmos.lang.source",
    "read_source": "cosmos.lang.source",
    "CompileState": "cosmos.lang.state",
    "Defaults": "cosmos.lang.state",
    "HeldContact": "cosmos.lang.state",
}

__all__ = [
    "CompileState",
    "Compiler",
    "Defaults",
    "HeldContact",
    "ProgramErrors",
    "StatementResult",
    "bench_compile",
    "bench_program",
    "compile_program",
    "decode_source",
    "needs_more_input",
    "parse_program",
    "read_source",
    "statement_text",
]


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'cosmos.lang' has no attribute '{name}'")
