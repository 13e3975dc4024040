"""The console entry point (`fivebar-drake`, `python -m fivebar_drake`): the command line, with a
Ctrl-C or SIGTERM while it loads (Drake and numba take seconds; pydrake turns an interrupt in
its initialisation into a fatal error) held until the loading is done: one that came while the
modules were imported ends quietly with exit code 130 or 143; one after is held until the
command's own handlers are in place (cli.main unblocks it there), never lost."""

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
    return command_line()          # it unblocks them once its handlers are in place


if __name__ == "__main__":
    sys.exit(main())
