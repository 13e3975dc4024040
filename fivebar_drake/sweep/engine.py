"""Run a sweep on Dask: a local cluster of process workers (one thread each) by default, or an
existing scheduler. Only plain data crosses to the workers (the parameters, the scenario, the
points); each worker builds its own Diagrams. Rows are appended to the table as points finish,
so an interrupted sweep keeps them, and a rerun into the same folder computes only the points
the table lacks. When all points are done the table is rewritten in point order: the same sweep
gives the same file whatever the number of workers.

Table: CSV, not Parquet: a row can be appended and flushed the moment its point finishes (a
Parquet file is written whole), it survives a kill, and every tool reads it.
"""

from __future__ import annotations

import csv
import io
import json
import logging
import os
import socket
import sys
import tempfile
import time
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import urlsplit

from fivebar_drake.core.files import lock_folder, read_input_text, say, write_atomic
from fivebar_drake.core.progress import Progress
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.robots.quadruped.config import (check_path, load_params, with_changes,
                                                   with_path_defaults)
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.sweep.points import (SCENARIO, analysis_rows, columns, scenario_with,
                                        simulation_rows)
from fivebar_drake.sweep.spec import SweepSpec

TABLE_FILE, SPEC_FILE = "points.csv", "sweep.json"
ANALYSIS_CHUNK = 500      # analysis points per task: whole groups of the vectorised evaluation
WORKERS_PER_CORE = 4      # process workers beyond a few per core only queue for the cores, and
#                           each simulation worker holds ~0.6 GB (a Drake plant and its run)
SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")   # Dask's comm protocols


@dataclass
class SweepResult:
    """What run_sweep did: the table's path, its rows (strings as in the file, point order),
    how many points were computed now, how many of all rows failed, and the base parameters
    the points changed."""

    table: Path
    rows: list[dict]
    computed: int
    failed: int
    params: Params
    dropped: int = 0


def base_inputs(spec: SweepSpec):
    """(parameters, scenario or None) the points change, validated; every varied parameter's
    values (a list's values, a range's ends) checked alone against the base, so a wrong path or
    an impossible value stops the sweep before it starts (ParameterError naming the field)."""
    scenario = None
    if spec.fidelity == "simulation":
        scenario = load_scenario(spec.scenario, duration_s=spec.duration_s)
        params = (with_path_defaults(load_params(spec.config), scenario.gait) if spec.config
                  else scenario.load_params())
    else:
        params = with_path_defaults(load_params(spec.config), spec.gait)
        check_path(params, spec.gait)
    for v in spec.vary:
        for value in (v.values or (v.low, v.high)):
            if v.path.startswith(SCENARIO):
                scenario_with(scenario, {v.path: value})
            else:
                with_changes(params, {v.path: value})
    return params, scenario


def check_workers(workers: int | None) -> None:
    """ParameterError unless workers is None or 1 .. WORKERS_PER_CORE x the cores."""
    most = WORKERS_PER_CORE * (os.cpu_count() or 1)
    if workers is not None and not 1 <= workers <= most:
        raise ParameterError(f"--workers = {workers}: must be 1 .. {most} ({WORKERS_PER_CORE} "
                             f"per core of this machine's {os.cpu_count()}: more only queue for "
                             "the cores, and each simulation worker holds ~0.6 GB)", "--workers",
                             "command line")


REACH_TIMEOUT_S = 5.0       # a scheduler's address must answer a TCP connection within this


def check_scheduler(address: str) -> None:
    """ParameterError unless address reads as a Dask scheduler's, SCHEME://HOST:PORT."""
    try:
        parts = urlsplit(address)
        port = parts.port
    except ValueError:
        parts, port = None, None
    if parts is None or parts.scheme not in SCHEDULER_SCHEMES or not parts.hostname or not port:
        raise ParameterError(f"--scheduler = {address!r}: not a Dask scheduler address; write "
                             f"SCHEME://HOST:PORT with SCHEME one of {list(SCHEDULER_SCHEMES)}, "
                             "e.g. tcp://127.0.0.1:8786", "--scheduler", "command line")
    if parts.scheme == "tcp":                # reached before any folder is made: a nested
        reach(address, parts.hostname, port)  # --out is never left behind by a missing one


def reach(address: str, host: str, port: int) -> None:
    """ParameterError naming --scheduler unless a TCP connection to host:port opens within
    REACH_TIMEOUT_S (tried again every 0.1 s: a scheduler that is still starting answers)."""
    deadline = time.monotonic() + REACH_TIMEOUT_S
    while True:
        try:
            socket.create_connection((host, port), REACH_TIMEOUT_S).close()
            return
        except OSError as err:
            if time.monotonic() >= deadline:
                raise ParameterError(f"--scheduler = {address!r}: nothing answers there "
                                     f"({err.strerror or err}; tried for {REACH_TIMEOUT_S:g} s): "
                                     "start the scheduler, or leave --scheduler out for a local "
                                     "cluster", "--scheduler", "command line") from None
            time.sleep(0.1)


def check_output_folder(out: Path) -> None:
    """ParameterError unless out is (or can be made as) a folder this process can write in;
    nothing is left behind by the check (the folders it had to make, every level, are removed
    again)."""
    where = f"--out {out}"
    if out.exists() and not out.is_dir():
        raise ParameterError("is a file; the output must be a folder", source=where)
    made = [p for p in (out, *out.parents) if not p.exists()]      # deepest first
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=out):
            pass
    except OSError as err:
        raise ParameterError(f"cannot create or write into this folder: "
                             f"{err.strerror or err}", source=where) from None
    finally:
        for folder in made:               # every level the check made, not only the last
            if folder.is_dir() and not any(folder.iterdir()):
                folder.rmdir()


def _refuse(out: Path, name: str, why: str) -> ParameterError:
    return ParameterError(f"{why}; it is not a file this sweep wrote: remove {name} (or the "
                          "folder) to compute every point again, or choose another --out",
                          "--out", str(out / name))


def _previous_rows(fingerprint: str, out: Path, header: list[str],
                   points: list[dict]) -> tuple[list[dict] | None, int]:
    """What out holds of this sweep, read only: (None: no sweep.json, a new sweep; else the
    rows of points.csv that belong to it, the number of rows dropped). Rows that do not belong
    (a point the sweep does not have, a repeated point, values that are not the point's, a row
    with extra cells, a last line cut short by a kill) are dropped and computed again; a
    sweep.json of another sweep, or files that are not this tool's, are refused
    (ParameterError naming the file and why)."""
    path = out / SPEC_FILE
    if not path.exists():
        return None, 0
    try:
        old = json.loads(read_input_text(path, "sweep record"))
    except json.JSONDecodeError as err:
        raise _refuse(out, SPEC_FILE, f"not valid JSON ({err.msg} at line {err.lineno})") \
            from None
    except RecursionError:
        raise _refuse(out, SPEC_FILE, "nested too deeply") from None
    if not isinstance(old, dict) or not isinstance(old.get("fingerprint"), str):
        raise _refuse(out, SPEC_FILE, "not a sweep record (an object with a fingerprint)")
    if old["fingerprint"] != fingerprint:
        raise ParameterError(f"{out} holds the results of another sweep ({old.get('spec')}), or "
                             "the spec or a file it reads (config, scenario, the scenario's "
                             "params_file) changed since: choose another --out or remove the "
                             "folder", "--out")
    table = out / TABLE_FILE
    if not table.exists():
        return [], 0
    text = read_input_text(table, "sweep table")
    lines = text.splitlines(keepends=True)
    if not lines or lines[0].rstrip("\r\n") != ",".join(header):
        raise _refuse(out, TABLE_FILE, "its header is not this sweep's columns")
    complete = text if text.endswith("\n") else text[:text.rfind("\n") + 1]
    rows, seen = [], set()
    records = list(csv.DictReader(io.StringIO(complete, newline="")))
    for row in records:
        try:
            point = int(row["point"])
        except (TypeError, ValueError):
            continue
        if (None in row or point in seen or not 0 <= point < len(points)
                or any(row.get(k) != str(v) for k, v in points[point].items())):
            continue
        seen.add(point)
        rows.append(row)
    return rows, len(records) - len(rows) + (complete != text)


@contextmanager
def dask_client(workers: int | None, scheduler: str | None, client=None):
    """client, if given (left open); else a Dask client of the scheduler at `scheduler`, or of
    a new local cluster of `workers` process workers with one thread each (default: one per
    core), closed with its local cluster when the block ends."""
    if client is not None:
        yield client
        return
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except Exception as err:  # noqa: BLE001  (any failure to connect is a bad address)
            raise ParameterError(f"--scheduler = {scheduler}: no Dask scheduler answers there "
                                 f"({type(err).__name__}: {err})"[:500], "--scheduler",
                                 "command line") from None
    else:
        # a task's error is ours to report, and a stopped command's workers losing their
        # scheduler (a Ctrl-C) are not news: their logs below CRITICAL are silent
        client = Client(LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1,
                                     processes=True, dashboard_address=":0",
                                     preload=["fivebar_drake.sweep.worker_setup"],  # no SIGINT
                                     silence_logs=logging.CRITICAL))
    try:
        yield client
    finally:
        cluster = client.cluster
        client.close()
        if cluster is not None and not scheduler:
            cluster.close()


def run_sweep(spec: SweepSpec, out: str | Path, workers: int | None = None,
              scheduler: str | None = None, progress: bool = True,
              client=None) -> SweepResult:
    """Run the sweep's missing points into out/points.csv (see the module's docstring).
    client: a Dask client to use (and leave open), e.g. one cluster for several sweeps;
    otherwise one of the scheduler, or of a new local cluster of `workers`, for this sweep."""
    out = Path(out)
    check_workers(workers)
    if scheduler:
        check_scheduler(scheduler)
    try:
        params, scenario = base_inputs(spec)
    except ParameterError as err:
        raise err.located(spec.source or "sweep spec") from None
    header = columns(spec.fidelity, spec.names)
    check_output_folder(out)
    points = spec.points()
    fingerprint = spec.fingerprint()          # reads the spec's files once
    rows, dropped = _previous_rows(fingerprint, out, header, points)
    if dropped and progress:
        say(f"{out / TABLE_FILE}: {dropped} row(s) do not belong to this sweep (a point it does "
            "not have, repeated, other values, or cut short): computing them again", sys.stderr)
    done = {int(r["point"]) for r in rows or ()}
    todo = [(i, p) for i, p in enumerate(points) if i not in done]
    bar = Progress(len(points), len(done), progress)
    computed = 0
    with dask_client(workers, scheduler, client) if todo else nullcontext() as dask:
        out.mkdir(parents=True, exist_ok=True)     # the inputs and the scheduler are good
        lock_folder(out, "--out")
        if rows is None:
            write_atomic(out / SPEC_FILE, json.dumps({"fingerprint": fingerprint,
                                                      "spec": spec.source, "columns": header},
                                                     indent=1))
        _write_table(out / TABLE_FILE, header, sorted(rows or (), key=lambda r: int(r["point"])))
        if todo:
            computed = _compute(dask, spec, params, scenario, todo, out / TABLE_FILE, header,
                                bar)
    rows, _ = _previous_rows(fingerprint, out, header, points)
    rows = sorted(rows, key=lambda r: int(r["point"]))
    _write_table(out / TABLE_FILE, header, rows)
    return SweepResult(table=out / TABLE_FILE, rows=rows, computed=computed,
                       failed=sum(r["status"] == "failed" for r in rows), params=params,
                       dropped=dropped)


def finished_points(spec: SweepSpec, out: Path) -> tuple[int, int]:
    """(points of the sweep in out's table, points of the sweep), for a message after an
    interruption."""
    points = spec.points()
    try:
        rows, _ = _previous_rows(spec.fingerprint(), Path(out),
                                 columns(spec.fidelity, spec.names), points)
    except ParameterError:
        rows = None
    return len(rows or ()), len(points)


# a task that failed because its worker was lost, not because the task raised (retry-worthy)
LOST_WORKER = ("KilledWorker", "CommClosedError", "StreamClosedError", "FutureCancelledError",
               "CancelledError", "TimeoutError")


def raised_by_task(error: str) -> bool:
    """Whether a finished_tasks error text is an exception the task itself raised (a bug or
    a fault in the worker's machine), not a lost worker."""
    return bool(error) and error.split(":", 1)[0] not in LOST_WORKER


def finished_tasks(client, task, args: tuple, chunks: list):
    """Submit task(*args, chunk) for every chunk; yield (chunk, result, error) as each task
    finishes, in finishing order: error "" when it returned, else the exception's type and text
    (raised by the task, or a lost worker) and result None. Large args go scattered
    (client.scatter) by the caller."""
    from dask.distributed import as_completed

    futures = {client.submit(task, *args, chunk, pure=False): chunk for chunk in chunks}
    for future in as_completed(futures):
        try:
            result = future.result()
        except Exception as err:  # noqa: BLE001  (a lost worker: its chunk fails, not the job)
            yield futures[future], None, f"{type(err).__name__}: {err}"
        else:
            yield futures[future], result, ""


def _compute(client, spec, params, scenario, todo, table: Path, header, bar: Progress) -> int:
    """Submit the points, append each finished task's rows to the table; returns the number
    of rows written."""
    base = client.scatter(params, broadcast=True)
    if spec.fidelity == "analysis":     # tasks of ANALYSIS_CHUNK points, one point each else
        task, size, first = analysis_rows, ANALYSIS_CHUNK, (spec.gait, spec.model)
    else:
        task, size, first = simulation_rows, 1, (scenario, spec.step_check)
    chunks = [todo[i:i + size] for i in range(0, len(todo), size)]
    fresh = not table.exists()
    written = 0
    with open(table, "a", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=header, restval="")
        if fresh:
            writer.writeheader()
        for chunk, rows, error in finished_tasks(client, task, (base, first), chunks):
            if error:
                rows = [{"point": i, **c, "status": "failed", "error": error} for i, c in chunk]
            writer.writerows(rows)
            f.flush()
            written += len(rows)
            bar.add(len(rows), sum(r.get("status") == "failed" for r in rows))
    return written


def _write_table(path: Path, header: list[str], rows: list[dict]) -> None:
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=header, restval="")
    writer.writeheader()
    writer.writerows(rows)
    write_atomic(path, text.getvalue())


def sweep(spec: SweepSpec, out: str | Path, workers: int | None = None,
          scheduler: str | None = None, progress: bool = True, client=None):
    """run_sweep, then the plots and sweep.md. Returns (SweepResult, summary dict, the paths
    written: table, plots, report)."""
    from fivebar_drake.sweep.plots import write_sweep_plots
    from fivebar_drake.verdicts.checks import thresholds_text
    from fivebar_drake.sweep.report import summarize_sweep, write_sweep_report

    result = run_sweep(spec, out, workers, scheduler, progress, client)
    checks = result.params.checks
    summary = summarize_sweep(result.rows, spec.names, checks.sf_pass)
    written = [result.table, *write_sweep_plots(result.rows, spec.plot, spec.fidelity,
                                                checks.sf_pass, Path(out), spec.names,
                                                checks.sf_warn),
               write_sweep_report(summary, spec.names, spec.fidelity, Path(out),
                                  thresholds_text(checks),
                                  spec.gait if spec.fidelity == "analysis" else "")]
    return result, summary, written
