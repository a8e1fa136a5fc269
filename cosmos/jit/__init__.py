"""Compiled kernels: the one decorator every numba kernel of cosmos uses.

``@kernel`` is numba's ``njit`` with the cache of :mod:`cosmos.jit.cache` (one
user cache per cosmos version, numba version and CPU, shared by every
environment; a temporary one if the home is read-only; none, with a warning, if
nothing can be written), and compilations are announced on stderr
(:mod:`cosmos.jit.notice`). ``@kernel("signature", ...)`` compiles (or loads)
those signatures and no others, as ``njit`` does, but at the first call (from
Python or from another kernel) instead of at import: a kernel that only other
kernels call is compiled into them, and a run whose kernels are cached never
loads it on its own. Any call whose arguments convert to a declared signature
(a C-contiguous array to an any-layout one, a writable one to a read-only one, a
literal to its type) uses it: no second compilation. ``beside=True`` compiles it,
on a first run, in a second process beside this one (:mod:`cosmos.jit.beside`).

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
from numba.core.compiler_lock import global_compiler_lock

from cosmos.jit import argument_types, notice
from cosmos.jit import beside as helpers
from cosmos.jit import cache as kernel_cache
from cosmos.jit.cache import KernelCache, kernel_directory

__all__ = ["KernelCache", "kernel", "kernel_directory"]

argument_types.install()
_NOTICE = notice.install(str(kernel_directory() or "no cache"))
_NOTICE.on_first_compile = lambda: helpers.start(kernel_directory())
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


def _compile_declared(dispatcher: Any, signatures: tuple[Any, ...]) -> None:
    """Make ``dispatcher`` compile (or load) ``signatures`` at its first compilation, and no others.

    The first request, whatever its argument types, compiles the declared signatures and
    closes the dispatcher to new ones; numba then converts every call's arguments to them.
    """
    compile_types = dispatcher.compile

    def compile_declared() -> None:
        with global_compiler_lock:  # runs in two threads at once compile it once
            if dispatcher._can_compile:
                helpers.wait_for(dispatcher)  # a helper may be compiling it into the cache
                for declared in signatures:
                    compile_types(declared)
                dispatcher.disable_compile()

    def compile(signature: Any) -> Any:
        compile_declared()
        asked, _ = sigutils.normalize_signature(signature)
        typing = dispatcher.typingctx
        for declared in signatures:
            args, _ = sigutils.normalize_signature(declared)
            if len(args) == len(asked) and all(
                typing.can_convert(have, want) is not None for have, want in zip(asked, args, strict=True)
            ):
                return dispatcher.overloads[tuple(args)].entry_point
        raise TypeError(f"{dispatcher.py_func.__name__}: no declared signature takes {asked}")

    dispatcher.compile = compile
    dispatcher.compile_declared = compile_declared


def _compiled(function: Callable[..., Any], signatures: tuple[Any, ...], options: dict[str, Any]) -> Any:
    read_only = tuple(options.pop("read_only", ()))
    compile_beside = bool(options.pop("beside", False))
    dispatcher = numba.njit(**options)(function)
    if read_only:
        _compile_read_only(dispatcher, function, read_only)
    cache = kernel_cache.make_cache(function)
    _warn_fallback()
    if cache is not None:
        dispatcher._cache = cache  # what njit(cache=True) sets, with cosmos's locator
    if signatures:
        _compile_declared(dispatcher, signatures)
        if compile_beside:
            helpers.register(dispatcher)
    return dispatcher


def kernel(*args: Any, **options: Any) -> Any:
    """``numba.njit``, cached in the cosmos kernel cache: ``@kernel`` or ``@kernel("sig", ...)``."""
    if len(args) == 1 and callable(args[0]) and not options:
        return _compiled(args[0], (), {})
    signatures = tuple(args)

    def decorate(function: Callable[..., Any]) -> Any:
        return _compiled(function, signatures, options)

    return decorate
