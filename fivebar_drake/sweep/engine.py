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
import os
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from fivebar_drake.analysis.design_points import with_changes
from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.robots.quadruped.config import load_params
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.sweep.points import (SCENARIO, analysis_rows, columns, scenario_with,
                                        simulation_rows)
from fivebar_drake.sweep.spec import SweepSpec

TABLE_FILE, SPEC_FILE = "points.csv", "sweep.json"
ANALYSIS_CHUNK = 500      # analysis points per task: whole groups of the vectorised evaluation
PROGRESS_EVERY_S = 1.0


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


def base_inputs(spec: SweepSpec):
    """(parameters, scenario or None) the points change, validated; every varied parameter's
    values (a list's values, a range's ends) checked alone against the base, so a wrong path or
    an impossible value stops the sweep before it starts (ParameterError naming the field)."""
    scenario = None
    if spec.fidelity == "simulation":
        scenario = load_scenario(spec.scenario, duration_s=spec.duration_s)
        params = load_params(spec.config) if spec.config else scenario.load_params()
    else:
        params = load_params(spec.config)
    for v in spec.vary:
        for value in (v.values or (v.low, v.high)):
            if v.path.startswith(SCENARIO):
                scenario_with(scenario, {v.path: value})
            else:
                with_changes(params, {v.path: value})
    return params, scenario


def _read_rows(table: Path) -> list[dict]:
    """The table's complete rows; a last line cut short (the sweep was killed while writing it)
    is removed from the file, so its point is computed again."""
    if not table.exists():
        return []
    text = table.read_text(encoding="utf-8")
    if text and not text.endswith("\n"):
        text = text[:text.rfind("\n") + 1]
        write_atomic(table, text)
    return list(csv.DictReader(io.StringIO(text, newline="")))


def _open_output(spec: SweepSpec, out: Path, header: list[str]) -> list[dict]:
    """Prepare out for the sweep: a new folder gets sweep.json; a folder of the same sweep
    keeps its rows (returned); a folder of another sweep is refused (ParameterError)."""
    out.mkdir(parents=True, exist_ok=True)
    record = {"fingerprint": spec.fingerprint(), "spec": spec.source, "columns": header}
    path = out / SPEC_FILE
    if path.exists():
        old = json.loads(path.read_text())
        if old.get("fingerprint") != record["fingerprint"]:
            raise ParameterError(f"{out} holds the results of another sweep ({old.get('spec')}); "
                                 "choose another --out or remove the folder", "--out")
        return _read_rows(out / TABLE_FILE)
    (out / TABLE_FILE).unlink(missing_ok=True)
    write_atomic(path, json.dumps(record, indent=1))
    return []


class Progress:
    """A progress line on stderr: points done of all, failures, time left (from the mean rate
    so far); redrawn in place on a terminal, else one line per PROGRESS_EVERY_S * 10."""

    def __init__(self, total: int, done: int, enabled: bool):
        self.total, self.done, self.failed, self.enabled = total, done, 0, enabled
        self.start, self.first, self.shown = time.perf_counter(), done, 0.0
        self.tty = sys.stderr.isatty()

    def add(self, rows: list[dict]) -> None:
        self.done += len(rows)
        self.failed += sum(r.get("status") == "failed" for r in rows)
        now = time.perf_counter()
        every = PROGRESS_EVERY_S * (1 if self.tty else 10)
        if self.enabled and (now - self.shown >= every or self.done == self.total):
            self.shown = now
            elapsed, new = now - self.start, self.done - self.first
            left = elapsed / new * (self.total - self.done) if new else float("nan")
            bar = "#" * int(30 * self.done / self.total)
            line = (f"sweep [{bar:<30}] {self.done}/{self.total} points, {self.failed} failed, "
                    f"{elapsed:.0f} s, ~{left:.0f} s left")
            print(("\r" + line) if self.tty else line, end="" if self.tty and
                  self.done < self.total else "\n", file=sys.stderr, flush=True)


@contextmanager
def _client(workers: int | None, scheduler: str | None, client=None):
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
        except (OSError, TimeoutError) as err:
            raise ParameterError(f"--scheduler = {scheduler}: no Dask scheduler answers there "
                                 f"({err})", "--scheduler") from None
    else:
        client = Client(LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1,
                                     processes=True, dashboard_address=":0"))
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
    params, scenario = base_inputs(spec)
    header = columns(spec.fidelity, spec.names)
    rows = _open_output(spec, out, header)
    done = {int(r["point"]) for r in rows}
    todo = [(i, p) for i, p in enumerate(spec.points()) if i not in done]
    bar = Progress(len(done) + len(todo), len(done), progress)
    computed = 0
    if todo:
        with _client(workers, scheduler, client) as dask:
            computed = _compute(dask, spec, params, scenario, todo, out / TABLE_FILE, header,
                                bar)
    rows = sorted(_read_rows(out / TABLE_FILE), key=lambda r: int(r["point"]))
    _write_table(out / TABLE_FILE, header, rows)
    return SweepResult(table=out / TABLE_FILE, rows=rows, computed=computed,
                       failed=sum(r["status"] == "failed" for r in rows), params=params)


def _compute(client, spec, params, scenario, todo, table: Path, header, bar: Progress) -> int:
    """Submit the points, append each finished task's rows to the table; returns the number
    of rows written."""
    from dask.distributed import as_completed

    base = client.scatter(params, broadcast=True)
    if spec.fidelity == "analysis":     # tasks of ANALYSIS_CHUNK points, one point each else
        task, size, first = analysis_rows, ANALYSIS_CHUNK, (spec.gait, spec.model)
    else:
        task, size, first = simulation_rows, 1, (scenario, spec.step_check)
    chunks = [todo[i:i + size] for i in range(0, len(todo), size)]
    futures = {client.submit(task, base, first, chunk, pure=False): chunk for chunk in chunks}
    fresh = not table.exists()
    written = 0
    with open(table, "a", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=header, restval="")
        if fresh:
            writer.writeheader()
        for future in as_completed(futures):
            try:
                rows = future.result()
            except Exception as err:  # noqa: BLE001  (a lost worker: its points fail, not the sweep)
                rows = [{"point": i, **c, "status": "failed",
                         "error": f"{type(err).__name__}: {err}"} for i, c in futures[future]]
            writer.writerows(rows)
            f.flush()
            written += len(rows)
            bar.add(rows)
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
    from fivebar_drake.sweep.report import summarize_sweep, write_sweep_report

    result = run_sweep(spec, out, workers, scheduler, progress, client)
    sf_pass = result.params.checks.sf_pass
    summary = summarize_sweep(result.rows, spec.names, sf_pass)
    written = [result.table, *write_sweep_plots(result.rows, spec.plot, spec.fidelity, sf_pass,
                                                Path(out)),
               write_sweep_report(summary, spec.names, spec.fidelity, Path(out))]
    return result, summary, written
