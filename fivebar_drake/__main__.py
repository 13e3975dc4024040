"""The console entry point (`fivebar-drake`, `python -m fivebar_drake`): the command line, with a
Ctrl-C or SIGTERM while it loads (Drake and numba take seconds; pydrake turns an interrupt in
its initialisation into a fatal error) held until the loading is done, then ending quietly with
exit code 130 or 143, as one during a command does."""

from __future__ import annotations

import signal
import sys

HELD = {signal.SIGINT, signal.SIGTERM}


def main() -> int:
    signal.pthread_sigmask(signal.SIG_BLOCK, HELD)
    from fivebar_drake.cli import main as command_line

    pending = signal.sigpending() & HELD
    if pending:
        sig = min(pending)
        print(f"fivebar-drake: interrupted by {signal.Signals(sig).name} while loading: stopped",
              file=sys.stderr)
        return 128 + sig
    signal.pthread_sigmask(signal.SIG_UNBLOCK, HELD)
    return command_line()


if __name__ == "__main__":
    sys.exit(main())
