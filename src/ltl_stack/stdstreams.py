"""Standard streams a process was started without (``tool >&-``, ``node 2>&-``).

Python then has no file behind descriptor 0, 1 or 2, and the next file the process opens takes
that number: a later write to "stdout" would land in it, and a ``print`` or a log line end in a
traceback. Importing this module (``ltl_stack.cli`` and ``ltl_stack.ros`` do, so every tool and
node) opens ``/dev/null`` on each missing descriptor; ``STDOUT_CLOSED`` says stdout was one of them,
and ``ltl_stack.cli`` turns a tool's writes to it into one error line (exit 4), as for a full disk;
a node's log lines on stdout are dropped.
"""
from __future__ import annotations

import fcntl
import os
import sys


def open_missing_std_streams() -> frozenset[int]:
    """Open ``/dev/null`` on each of descriptors 0-2 that is not open (or, for 1 and 2, open only
    for reading); returns the ones opened."""
    missing = set()
    for fd in (0, 1, 2):
        try:
            mode = fcntl.fcntl(fd, fcntl.F_GETFL) & os.O_ACCMODE
        except OSError:
            mode = None
        # stdout or stderr open for reading only is a file that took a closed descriptor's place
        # before this module ran (catkin's script wrappers read the script through it)
        if mode is None or (fd > 0 and mode == os.O_RDONLY):
            missing.add(fd)
            opened = os.open(os.devnull, os.O_RDWR)
            if opened != fd:
                os.dup2(opened, fd)
                os.close(opened)
    for fd, name in ((0, "stdin"), (1, "stdout"), (2, "stderr")):
        if getattr(sys, name) is None:
            setattr(sys, name, open(fd, "r" if fd == 0 else "w", closefd=False))  # noqa: SIM115
    return frozenset(missing)


#: the process was started with its standard output closed
STDOUT_CLOSED = 1 in open_missing_std_streams()
