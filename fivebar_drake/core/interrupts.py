"""SIGINT (Ctrl-C) and SIGTERM as requests: a simulation stops stepping and writes what it has;
everything else stops at once, with exit code 128 + the signal's number."""

from __future__ import annotations

import contextlib
import signal


SIGNALS = (signal.SIGINT, signal.SIGTERM)
RETRY = signal.SIGALRM   # a raise put off (Signals) is tried again on this timer's signal
RETRY_S = 0.001


def in_numba_boxing(frame) -> bool:
    """Whether the frame, or one it was called from, is numba's boxing of a compiled kernel's
    NamedTuple result: its class unpickled (numba.core.serialize._numba_unpickle) or its
    __new__ (a namedtuple's, compiled from "<string>")."""
    while frame is not None:
        code = frame.f_code
        if code.co_name == "_numba_unpickle" or (
                code.co_filename == "<string>"
                and frame.f_globals.get("__name__", "").startswith("namedtuple_")):
            return True
        frame = frame.f_back
    return False


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
    (or within gently()) the first one only sets .signum (a running simulate() polls it and
    stops at its next slice) and a second one raises. Outside the main thread, where handlers
    cannot be set, nothing changes.

    A raise that would land in numba's boxing of a compiled kernel's result (in_numba_boxing)
    is put off by RETRY_S and tried again (SIGALRM): numba calls Python there (the result's
    NamedTuple class, unpickled, and its __new__) and does not check for an exception on its
    return, so one raised by a handler crashed the process (a segmentation fault: 1 of 6
    SIGTERMs into `optimal --simulate`; every run of a loop calling a kernel that returns a
    NamedTuple while signals arrive every 0.2-5 ms, numba 0.68; none once put off:
    tests/core/test_interrupts.py)."""

    def __init__(self, stop_gently: bool = False):
        self.stop_gently = stop_gently
        self.signum = 0
        self._previous = {}
        self._put_off = 0

    def __enter__(self) -> "Signals":
        try:
            self._previous = {s: signal.signal(s, self._handle) for s in (*SIGNALS, RETRY)}
        except ValueError:            # not the main thread
            self._previous = {}
        return self

    def __exit__(self, *exc) -> None:
        if self._previous:
            signal.setitimer(signal.ITIMER_REAL, 0.0)
        for s, handler in self._previous.items():
            signal.signal(s, handler)

    def _handle(self, signum, frame) -> None:
        if signum == RETRY:                     # a raise put off (below), tried again
            if not self._put_off:
                return
            signum, self._put_off = self._put_off, 0
        else:
            first = not self.signum
            self.signum = self.signum or signum     # recorded always: a caller can tell a
            if self.stop_gently and first:          # signal came even where its exception
                return                              # was swallowed
        if in_numba_boxing(frame):
            self._put_off = signum
            signal.setitimer(signal.ITIMER_REAL, RETRY_S)
            return
        raise Interrupted(signum)

    @contextlib.contextmanager
    def gently(self):
        """Within: the first signal only sets .signum, as with stop_gently: a simulation under
        way polls it, stops at its next slice and returns what it simulated."""
        before, self.stop_gently = self.stop_gently, True
        try:
            yield self
        finally:
            self.stop_gently = before

    def raise_received(self) -> None:
        """Raise Interrupted for the signal received, if one was."""
        if self.signum:
            raise Interrupted(self.signum)

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
