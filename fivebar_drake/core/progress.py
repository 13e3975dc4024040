"""A progress line on the console (stderr) for long runs: a simulation's simulated seconds, a
sweep's points, an envelope's maneuvers, a co-design's trials."""

from __future__ import annotations

import sys
import time

PROGRESS_EVERY_S = 1.0   # redraw at most this often on a terminal (ten times less in a log)


class Progress:
    """A progress line on stderr: done of total (items: "points", "maneuvers", "s simulated"),
    failures (if counted), time so far and left (from the mean rate so far) and a note (e.g. the
    best design so far, the real-time factor); redrawn in place on a terminal, else one line per
    PROGRESS_EVERY_S * 10."""

    def __init__(self, total: float, done: float, enabled: bool, job: str = "sweep",
                 items: str = "points", failures: bool = True):
        self.total, self.done, self.failed, self.enabled = total, done, 0, enabled
        self.job, self.items, self.note, self.failures = job, items, "", failures
        self.start, self.first, self.shown = time.perf_counter(), done, 0.0
        self.tty = sys.stderr.isatty()

    def add(self, count: float, failed: int = 0) -> None:
        """count more done, `failed` of them failed."""
        self.done += count
        self.failed += failed
        now = time.perf_counter()
        every = PROGRESS_EVERY_S * (1 if self.tty else 10)
        finished = self.done >= self.total * (1.0 - 1e-9)
        if self.enabled and (now - self.shown >= every or finished):
            self.shown = now
            elapsed, new = now - self.start, self.done - self.first
            left = elapsed / new * (self.total - self.done) if new else float("nan")
            bar = "#" * int(30 * min(self.done / self.total, 1.0))
            line = (f"{self.job} [{bar:<30}] {self.done:g}/{self.total:g} {self.items}, "
                    + (f"{self.failed} failed, " if self.failures else "")
                    + f"{elapsed:.0f} s, ~{left:.0f} s left"
                    + (f"; {self.note}" if self.note else ""))
            print(("\r" + line) if self.tty else line,
                  end="" if self.tty and not finished else "\n", file=sys.stderr, flush=True)
