"""Compiled kernels: the one decorator every numba kernel of cosmos uses.

``@kernel`` is numba's ``njit`` with the cache of :mod:`cosmos.jit.cache` (one
user cache per cosmos version, numba version and CPU, shared by every
environment; a temporary one if the home is read-only; none, with a warning, if
nothing can be written), and compilations are announced on stderr
(:mod:`cosmos.jit.notice`). ``@kernel("signature", ...)`` compiles (or loads)
those signatures at once and no others, as ``njit`` does.

``@kernel(read_only=("name", ...))`` compiles the named array arguments as
read-only whatever the caller passes: numba compiles a kernel again for every
new combination of writable and read-only arrays (a plan's arrays are
read-only, the controller's own copies are not), and a writable array converts
to a read-only one, so one compilation serves both.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

import numba
from numba.core import sigutils, types

from cosmos.jit import cache as kernel_cache
from cosmos.jit import notice
from cosmos.jit.cache import KernelCache, kernel_directory

__all__ = ["KernelCache", "kernel", "kernel_directory"]

_NOTICE = notice.install(str(kernel_directory() or "no cache"))
_warned: list[bool] = []


def _warn_fallback() -> None:
    """Say once why kernels are not kept in the user cache, if they are not."""
    reasons = kernel_cache.FALLBACK
    if _warned or not reasons:
        return
    _warned.append(True)
    directory = kernel_cache.kernel_directory()
    if directory is not None:
        notice.say(f"cannot keep compiled kernels in the user cache ({reasons[0]}); using {directory}")
    else:
        notice.say(
            f"cannot keep compiled kernels anywhere ({'; '.join(reasons)}): every run compiles them; "
            f"set {kernel_cache.CACHE_ENV} to a writable directory"
        )


def _compile_read_only(dispatcher: Any, function: Callable[..., Any], names: tuple[str, ...]) -> None:
    """Make ``dispatcher`` compile the arguments ``names`` as read-only arrays.

    The caller's own types are entered in the dispatcher's table too, pointing at
    the read-only compilation: numba calls a compiled kernel without going back to
    Python only for an exact match of the arguments' types.
    """
    parameters = list(inspect.signature(function).parameters)
    positions = {parameters.index(name) for name in names}
    compile_types = dispatcher.compile

    def compile(signature: Any) -> Any:
        args, returned = sigutils.normalize_signature(signature)
        frozen = tuple(
            arg.copy(readonly=True) if i in positions and isinstance(arg, types.Array) else arg
            for i, arg in enumerate(args)
        )
        entry = compile_types(frozen if returned is None else returned(*frozen))
        if frozen != tuple(args):
            dispatcher._insert([arg._code for arg in args], entry, False)
        return entry

    dispatcher.compile = compile


def _compiled(function: Callable[..., Any], signatures: tuple[str, ...], options: dict[str, Any]) -> Any:
    read_only = tuple(options.pop("read_only", ()))
    dispatcher = numba.njit(**options)(function)
    if read_only:
        _compile_read_only(dispatcher, function, read_only)
    cache = kernel_cache.make_cache(function)
    _warn_fallback()
    if cache is not None:
        dispatcher._cache = cache  # what njit(cache=True) sets, with cosmos's locator
    for signature in signatures:
        dispatcher.compile(signature)
    if signatures:
        dispatcher.disable_compile()
    return dispatcher


def kernel(*args: Any, **options: Any) -> Any:
    """``numba.njit``, cached in the cosmos kernel cache: ``@kernel`` or ``@kernel("sig", ...)``."""
    if len(args) == 1 and callable(args[0]) and not options:
        return _compiled(args[0], (), {})
    signatures = tuple(args)

    def decorate(function: Callable[..., Any]) -> Any:
        return _compiled(function, signatures, options)

    return decorate
