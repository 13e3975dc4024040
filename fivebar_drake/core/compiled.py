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
