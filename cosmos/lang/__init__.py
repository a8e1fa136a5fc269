"""The COSMOS task language: parse, check and compile programs to plans.

The subpackages read as the pipeline: ``parse`` (file and text to the syntax
tree of :mod:`cosmos.lang.ast`), ``check`` (what a statement alone can tell),
``evaluate`` (expressions and units, :mod:`cosmos.lang.units`) and ``compile``
(statements to plan steps). Entry points (imported lazily):

- :func:`compile_program` (source, file, fixtures) -> :class:`cosmos.plan.Plan`
- :class:`Compiler` for statement-by-statement compilation (the REPL), with
  :class:`CompileState` carried between inputs
- :func:`parse_program` (source, file) -> :class:`cosmos.lang.ast.Program`
- :func:`needs_more_input` (text) -> whether a REPL input has an open block
- :func:`parse_unit` (text) -> :class:`~cosmos.lang.units.Unit` (factor to SI, dimension)
- :func:`read_program` (path) -> the text of a program file, read with bounds
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from cosmos.lang.compile.compiler import (
        Compiler,
        ProgramErrors,
        StatementResult,
        compile_program,
        statement_text,
    )
    from cosmos.lang.compile.state import CompileState, Defaults, HeldContact
    from cosmos.lang.parse.parser import needs_more_input, parse_program
    from cosmos.lang.parse.source_file import decode_source, read_program, read_source
    from cosmos.lang.units import UnknownUnit, parse_unit

_EXPORTS = {
    "Compiler": "cosmos.lang.compile.compiler",
    "ProgramErrors": "cosmos.lang.compile.compiler",
    "StatementResult": "cosmos.lang.compile.compiler",
    "compile_program": "cosmos.lang.compile.compiler",
    "statement_text": "cosmos.lang.compile.compiler",
    "needs_more_input": "cosmos.lang.parse.parser",
    "parse_program": "cosmos.lang.parse.parser",
    "decode_source": "cosmos.lang.parse.source_file",
    "read_program": "cosmos.lang.parse.source_file",
    "read_source": "cosmos.lang.parse.source_file",
    "CompileState": "cosmos.lang.compile.state",
    "Defaults": "cosmos.lang.compile.state",
    "HeldContact": "cosmos.lang.compile.state",
    "UnknownUnit": "cosmos.lang.units",
    "parse_unit": "cosmos.lang.units",
}

__all__ = [
    "CompileState",
    "Compiler",
    "Defaults",
    "HeldContact",
    "ProgramErrors",
    "StatementResult",
    "UnknownUnit",
    "compile_program",
    "decode_source",
    "needs_more_input",
    "parse_program",
    "parse_unit",
    "read_program",
    "read_source",
    "statement_text",
]


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'cosmos.lang' has no attribute '{name}'")
