import json

import numpy as np
import pytest

from fivebar_drake.robots.quadruped.config import load_params


@pytest.fixture(scope="session")
def params():
    return load_params()


@pytest.fixture(scope="session")
def simulated():
    """run_simulation(load_scenario(**fields)) run once per session for each set of fields: the
    same scenario serves the modules that check it from different sides (the default trot's
    4.5 s with the ball closure: tests/simulation/test_simulation.py and tests/test_pipeline.py;
    its 2.5 s with the bushing: test_recording.py and test_summary_schema.py). The records are
    shared: read them, never change them."""
    from fivebar_drake.pipeline import run_simulation
    from fivebar_drake.simulation.scenario import load_scenario

    records = {}

    def run(**fields):
        key = json.dumps(fields, sort_keys=True)
        if key not in records:
            records[key] = run_simulation(load_scenario(**fields), progress=False)
        return records[key]

    return run


@pytest.fixture()
def rng():
    return np.random.default_rng(20261121)


@pytest.fixture(scope="session")
def shared_client():
    """One local Dask cluster (one process worker, one thread) for the sweeps and envelopes of
    tests that are not about how a cluster starts: a new one costs a fresh worker process
    (imports, compiled-code caches: 3-8 s). Cluster start-up stays covered by the tests that
    pass workers (two workers), a scheduler, or run the command line."""
    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                           dashboard_address=":0")
    client = Client(cluster)
    yield client
    client.close()
    cluster.close()


@pytest.fixture(scope="session")
def scheduler_address():
    """A Dask scheduler and one worker (one thread) started here as separate processes, as a
    user's remote cluster is, once for the tests that pass --scheduler (a sweep's and an
    envelope's): its address. Stopped at the session's end."""
    import socket
    import subprocess
    import sys

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    procs = [subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1",
                               "--port", str(port), "--no-dashboard"], **quiet)]
    try:
        procs.append(subprocess.Popen([sys.executable, "-m", "dask", "worker", address,
                                       "--nthreads", "1", "--no-dashboard"], **quiet))
        from dask.distributed import Client       # wait on the event: the scheduler answers
        with Client(address, timeout=120) as client:   # and its worker has joined
            client.wait_for_workers(1, timeout=120)
        yield address
    finally:
        for p in procs:
            p.terminate()
            p.wait(timeout=30)
