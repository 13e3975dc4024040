"""Compilation of the numeric kernels with numba: each formula has one implementation, written
on flat float arrays, that the analysis calls on whole paths and grids and the simulation's
controller calls at every tick. Compiled code is cached on disk beside the sources.

error_model="numpy": a division by zero gives inf/nan as in numpy (singular poses), no exception.
"""

from __future__ import annotations

import numba


def jit(function):
    """Compile function in nopython mode (cached; numpy's floating-point error semantics)."""
    return numba.njit(cache=True, error_model="numpy")(function)


def jit_uncached(function):
    """jit without the disk cache, for a kernel that takes its callers' compiled functions and
    NamedTuples (a foot path's point function and constants): the cache's index would name their
    types, and every later process would have to import their modules (a gait defined in a script
    or a test would break the cache for all). Compiled once per process and path (0.2-0.6 s)."""
    return numba.njit(error_model="numpy")(function)


def bound(kernel, *args):
    """kernel's compiled entry point for the types of the example args (numba.typeof; compiled,
    or loaded from the cache, now; nothing is run): a call that skips the dispatcher's typing of
    its arguments, which for a NamedTuple of constants costs more than many kernels' work (3.4
    of 4.1 us per call for control_law.LawConstants, measured back to back). Every call must
    pass arguments of exactly these types (the same NamedTuple types, C-contiguous float arrays
    of the same dimensions): the entry point converts its arguments as typed, it does not check
    them. Where there is no entry point (numba disabled), the kernel itself."""
    if not hasattr(kernel, "overloads"):
        return kernel
    signature = tuple(numba.typeof(a) for a in args)
    kernel.compile(signature)
    return kernel.overloads[signature].entry_point
