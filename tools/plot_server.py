#!/usr/bin/env python3
"""plot_spectra.py started ahead of its work: slidespec starts this when a run begins, so
that the interpreter and matplotlib load while the run simulates.

Usage: plot_server.py < ARG\\0ARG\\0...   (plot_spectra.py's arguments, each ended by NUL)

Reads its stdin to the end, then runs plot_spectra.py with those arguments; its exit
status is theirs. An empty stdin (the run ended without a figure) exits 0 having written
nothing.
"""

import gc
import os
import sys

# One figure, then exit: the cyclic collector would only walk matplotlib's objects again
# and again (a tenth of the import's CPU, taken from the run it overlaps).
gc.disable()

import plot_spectra  # noqa: E402  (the import is the start-up this process takes off the critical path)


def main():
    message = sys.stdin.buffer.read()
    if not message:
        return 0
    return plot_spectra.main([os.fsdecode(arg) for arg in message.split(b"\0")[:-1]])


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    sys.stderr.flush()
    # The figure is on disk and the run waits for this status: the interpreter's teardown
    # (matplotlib's modules, a few hundredths of a second) would only delay it.
    os._exit(status)
