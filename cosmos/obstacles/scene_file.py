"""Where the workcell's MJCF with its obstacle slots is kept as a file for :class:`~cosmos.plant.Plant`.

In the user cache, named by its content: written once, shared by processes and kept between runs.
It was a temporary directory per process, left behind by every run (cosmos skips the interpreter's
teardown, and with it the directory's removal), and with no temporary directory at all a run died
with a traceback.
"""

from __future__ import annotations

import functools
import hashlib
import tempfile
import threading
from pathlib import Path

from cosmos.errors import CosmosError
from cosmos.user_cache import CACHE_ENV, user_cache_root, write_whole

_WRITING = threading.Lock()


@functools.cache
def _scene_dir() -> tempfile.TemporaryDirectory[str]:
    return tempfile.TemporaryDirectory(prefix="cosmos-obstacles-")


def kept_scene_file(name: str, text: str) -> Path:
    """A file holding the scene ``text``, named ``name`` and by its content.

    In the user cache; if it cannot be written, in one temporary directory of this process's.

    Raises:
        CosmosError: If neither can be written.
    """
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    cache = user_cache_root() / "scenes"
    path = cache / f"{name}-{digest}.xml"
    try:
        if not path.is_file():
            write_whole(path, text)  # whole or not at all: processes may start at once
        return path
    except OSError:
        pass
    try:
        with _WRITING:  # threads' first calls at once: one directory kept
            temporary = Path(_scene_dir().name) / f"{name}.xml"
            write_whole(temporary, text)
        return temporary
    except OSError as error:
        raise CosmosError(
            f"cannot write the workcell's scene with its obstacle slots in {cache} or a temporary "
            f"directory ({error.strerror or error}); set {CACHE_ENV} to a writable directory"
        ) from None
