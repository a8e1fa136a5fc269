"""The package metadata numba's and MuJoCo's imports read, read only where a package declares something.

Both libraries look, when imported or first used, for what other installed packages add to
them: numba for its extensions (the entry-point group ``numba_extensions``, at its first
compilation or first load of a cached kernel), MuJoCo for its plugins (``mujoco.plugins``,
at import). They ask :mod:`importlib.metadata`, whose import (with :mod:`email`,
:mod:`socket` and the rest it needs: 10-30 ms) and two walks of every installed package's
metadata (5 ms each) are a warm ``cosmos run``'s, for groups that almost no environment
declares. :func:`unscanned` reads the packages' ``entry_points.txt`` files itself, as
:mod:`importlib.metadata` finds them, and where neither group is declared answers the two
libraries' questions itself: no extension, no plugin. Where one is declared, or the
packages cannot be read that way, the libraries ask as they do.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import os
import sys
import types
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

METADATA = "importlib.metadata"
GROUPS = ("numba_extensions", "mujoco.plugins")
"""The entry-point groups a run's libraries look for: numba's extensions, MuJoCo's plugins."""


def declared_groups(groups: tuple[str, ...] = GROUPS) -> set[str] | None:
    """Which of ``groups`` an installed package declares entry points in; None where that is not known.

    Read where :mod:`importlib.metadata` finds packages: the ``.dist-info`` and ``.egg-info``
    directories of each directory on :data:`sys.path`, a group counted if an ``entry_points.txt``
    names it. Not known: a path entry that is a file (a zip) or an egg, or an import finder that
    finds packages of its own.
    """
    for finder in sys.meta_path:
        if hasattr(finder, "find_distributions") and finder is not importlib.machinery.PathFinder:
            return None
    wanted = {group: f"[{group}]".encode() for group in groups}
    found: set[str] = set()
    for entry in sys.path:
        directory = entry or os.getcwd()
        if os.path.isfile(directory) or directory.lower().endswith(".egg"):
            return None
        try:
            with os.scandir(directory) as children:
                infos = [
                    child.path
                    for child in children
                    if child.name.lower().endswith((".dist-info", ".egg-info"))
                ]
        except OSError:  # no such directory: no packages there
            continue
        for info in infos:
            try:
                with open(os.path.join(info, "entry_points.txt"), "rb") as declared:
                    text = declared.read()
            except OSError:  # none declared, or an egg-info file
                continue
            found.update(group for group, header in wanted.items() if header in text)
    return found


class _Undeclared(types.ModuleType):
    """A stand-in for :mod:`importlib.metadata`: no entry points in ``groups``, the module for the rest."""

    def __init__(self, groups: frozenset[str]):
        super().__init__(METADATA)
        self._groups = groups

    def entry_points(self, **selection: Any) -> Any:
        """No entry points for a group in ``groups`` asked alone; otherwise :mod:`importlib.metadata`'s."""
        if set(selection) == {"group"} and selection["group"] in self._groups:
            return ()
        return _real().entry_points(**selection)

    def __getattr__(self, name: str) -> Any:
        return getattr(_real(), name)


def _real() -> types.ModuleType:
    """:mod:`importlib.metadata` itself, imported now if only the stand-in is."""
    if isinstance(sys.modules.get(METADATA), _Undeclared):
        del sys.modules[METADATA]
    return importlib.import_module(METADATA)


@contextmanager
def unscanned() -> Iterator[None]:
    """Within: numba and MuJoCo, if first imported here, find no extension or plugin without asking.

    Only where no installed package declares one (:func:`declared_groups`) and
    :mod:`importlib.metadata` is not imported yet; numba is then told it has loaded its
    extensions (it would have found none). Afterwards, the first that imports
    :mod:`importlib.metadata` gets the module itself.
    """
    parent = sys.modules["importlib"]
    if METADATA in sys.modules or hasattr(parent, "metadata"):
        yield
        return
    declared = declared_groups()
    if declared is None or declared & set(GROUPS):
        yield
        return
    stand_in = _Undeclared(frozenset(GROUPS))
    sys.modules[METADATA] = stand_in
    parent.metadata = stand_in  # type: ignore[attr-defined]  # ``import importlib.metadata as m`` reads it
    try:
        yield
    finally:
        if sys.modules.get(METADATA) is stand_in:
            del sys.modules[METADATA]
        if getattr(parent, "metadata", None) is stand_in:
            del parent.metadata
        found = sys.modules.get("numba.core.entrypoints")
        if found is not None:
            found._already_initialized = True  # type: ignore[attr-defined]  # no package declares one
