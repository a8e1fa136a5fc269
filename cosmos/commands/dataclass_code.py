"""The methods ``@dataclass`` writes at import, compiled once and kept in the user cache.

Python keeps every module's bytecode (``__pycache__``) but not the methods ``@dataclass``
writes for each class as the class is defined (``__init__``, ``__repr__``, ``__eq__``,
``__hash__``, a frozen class's ``__setattr__`` ...): each is a text that every process
compiles again, about 740 of them for ``cosmos run`` (60 ms of its start-up). In the
command's process (:mod:`cosmos.commands.process`), :mod:`dataclasses` finds each text's
code in :data:`CACHE_NAME` first: the module calls ``exec`` by name, and a name in its own
namespace comes before the builtin. What it still had to compile is added to the file at
the process's exit; a file that cannot be read is ignored, one that cannot be written is
not kept. A text is its own key, so a changed class finds its new text compiled once.
Each code is kept marshalled on its own and read back only when its class is defined: the
file holds the classes of every command and of earlier versions (1,100 texts), which
took 10-25 ms to read whole where a run defines 500 of them.
"""

from __future__ import annotations

import atexit
import dataclasses
import importlib.util
import marshal
from pathlib import Path
from types import CodeType
from typing import Any

from cosmos.user_cache import user_cache_root, write_whole

CACHE_NAME = f"dataclass-code-2-{importlib.util.MAGIC_NUMBER.hex()}.marshal"
"""The cache file in the user cache, named by Python's bytecode version (the code objects' format)."""

MAX_KEPT = 8000
"""More texts than this in the file (old versions' classes piling up): keep only this process's."""


class CachedExec:
    """``exec`` for :mod:`dataclasses`: a text's code from :attr:`codes`, else compiled and added.

    Args:
        codes: Known texts and their code, or their code marshalled (read back when first used).
    """

    def __init__(self, codes: dict[str, CodeType | bytes]):
        self.codes = codes
        self.used: set[str] = set()
        self.compiled = 0

    def _code(self, source: str) -> CodeType:
        """The code of ``source``: kept (unmarshalled now if need be), else compiled as exec compiles it."""
        kept = self.codes.get(source)
        if type(kept) is bytes:
            try:
                kept = marshal.loads(kept)
            except (EOFError, ValueError, TypeError):
                kept = None
        if type(kept) is CodeType:
            code = kept
        else:  # as exec compiles it: no future statements of this module
            code = compile(source, "<string>", "exec", dont_inherit=True)
            self.compiled += 1
        self.codes[source] = code
        return code

    def __call__(self, source: Any, globals: Any = None, locals: Any = None, /) -> None:
        """``exec(source, globals, locals)``, a text's code compiled at most once."""
        if isinstance(source, str):
            self.used.add(source)
            source = self._code(source)
        exec(source, globals, locals)

    def keep(self, path: Path) -> None:
        """Write the codes to ``path`` if this process compiled any (whole or not at all)."""
        if not self.compiled:
            return
        texts = self.used if len(self.codes) > MAX_KEPT else self.codes
        kept = {text: self.codes[text] for text in texts}
        table = {text: code if type(code) is bytes else marshal.dumps(code) for text, code in kept.items()}
        try:
            write_whole(path, marshal.dumps(table))
        except (OSError, ValueError):
            return


def read_codes(path: Path) -> dict[str, CodeType | bytes]:
    """The texts and their marshalled code in ``path``; empty if it is missing, unreadable or not a table."""
    try:
        codes = marshal.loads(path.read_bytes())
    except (OSError, EOFError, ValueError, TypeError):
        return {}
    if not isinstance(codes, dict):
        return {}
    return {text: code for text, code in codes.items() if type(text) is str and type(code) is bytes}


def install() -> CachedExec | None:
    """Give :mod:`dataclasses` the cached ``exec`` for the rest of the process (None if it has one)."""
    if "exec" in vars(dataclasses):
        return None
    path = user_cache_root() / CACHE_NAME
    cached = CachedExec(read_codes(path))
    dataclasses.exec = cached  # type: ignore[attr-defined]
    atexit.register(cached.keep, path)
    return cached
