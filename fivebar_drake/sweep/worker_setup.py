"""Preloaded into each worker of a local Dask cluster (sweep.engine.dask_client): the worker
ignores SIGINT. A terminal's Ctrl-C reaches the whole process group; the command's own process
stops and closes the cluster (each worker printed the traceback of its KeyboardInterrupt)."""

import signal


def dask_setup(worker) -> None:
    """Dask's preload hook, in the worker's process at its start."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
