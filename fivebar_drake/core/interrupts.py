"""SIGINT (Ctrl-C) and SIGTERM as requests: a simulation stops stepping and writes what it has;
everything else stops at once, with exit code 128 + the signal's number."""

from __future__ import annotations

import signal



SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Interrupted(BaseException):
    """The user asked the process to stop; like KeyboardInterrupt, no `except Exception` stops
    it. exit_code: 128 + the signal's number (130 SIGINT, 143 SIGTERM)."""

    def __init__(self, signum: int):
        super().__init__(f"interrupted by {signal.Signals(signum).name}")
        self.signum = signum
        self.exit_code = 128 + signum


class Signals:
    """While active (with-block), SIGINT and SIGTERM raise Interrupted, .signum recording the first
    (cli.main turns a command that still returned 0 into its exit code); with stop_gently=True
    the first one only sets .signum (a running simulate() polls it and stops at its next slice)
    and a second one raises. Outside the main thread, where handlers cannot be set, nothing changes."""

    def __init__(self, stop_gently: bool = False):
        self.stop_gently = stop_gently
        self.signum = 0
        self._previous = {}

    def __enter__(self) -> "Signals":
        try:
            self._previous = {s: signal.signal(s, self._handle) for s in SIGNALS}
        except ValueError:            # not the main thread
            self._previous = {}
        return self

    def __exit__(self, *exc) -> None:
        for s, handler in self._previous.items():
            signal.signal(s, handler)

    def _handle(self, signum, frame) -> None:
        first = not self.signum
        self.signum = self.signum or signum     # recorded always: a caller can tell a signal
        if self.stop_gently and first:          # came even where its exception was swallowed
            return
        raise Interrupted(signum)

    @property
    def name(self) -> str:
        """The signal received ("SIGINT", "SIGTERM"), "" if none."""
        return signal.Signals(self.signum).name if self.signum else ""


STOP_SLICE_S = 0.05    # simulated time between polls of a stop request in a study's run


def advance(simulator, t_end: float, stop=None) -> str:
    """Advance a Drake simulator to t_end (s) in slices of STOP_SLICE_S, polling stop() after
    each (a non-empty answer, a signal's name, ends the run there): the answer, "" if t_end was
    reached."""
    t = simulator.get_context().get_time()
    while t < t_end:
        t = min(t + STOP_SLICE_S, t_end)
        simulator.AdvanceTo(t)
        reason = stop() if stop else ""
        if reason:
            return reason
    return ""
