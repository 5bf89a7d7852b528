"""The one exit-code table of every ltl_stack tool, and the base class of every error a user can cause.

Every tool (``synthesize``, ``controller_executor``, ``analyze_graph``, ``ros_code_transfer``, the
proposition nodes …) exits with a code from ``Exit``; the README's table is this one. Errors a user
can fix (a bad file, a bad argument or parameter) derive from ``UserError`` and carry their exit
code, so a tool's ``main`` catches one class and prints one line (``ltl_stack.cli.run``).
"""
from __future__ import annotations

from enum import IntEnum


class Exit(IntEnum):
    """Exit codes shared by all tools."""

    OK = 0
    #: the tool ran and its answer is negative: findings with ``--fail-on-findings``, unresolved items,
    #: a goal not completed, cycles not reached
    NEGATIVE = 1
    #: a user mistake: bad file, argument or parameter (one message naming file/line/param)
    BAD_INPUT = 2
    #: no ROS master, or the server/topic the tool needs is not there
    NO_ROS = 3
    #: an output file could not be written (disk, permissions, no Graphviz …)
    WRITE_FAILED = 4
    #: a limit was reached: ``--timeout``, ``--max-states``, the memory cap
    LIMIT = 5
    #: the specification is unrealizable
    UNREALIZABLE = 10
    #: code transfer refused: the target robot cannot run the program safely
    REFUSED = 11
    #: interrupted by the user (Ctrl-C), as shells report SIGINT
    INTERRUPTED = 130


EXIT_TABLE = (
    (Exit.OK, "success (realizable, written, completed)"),
    (Exit.NEGATIVE, "ran, answer negative (findings with --fail-on-findings, unresolved items, not completed)"),
    (Exit.BAD_INPUT, "bad input: file, argument or parameter"),
    (Exit.NO_ROS, "no ROS master, server or topic"),
    (Exit.WRITE_FAILED, "an output could not be written"),
    (Exit.LIMIT, "a limit was reached (--timeout, --max-states, memory cap)"),
    (Exit.UNREALIZABLE, "the specification is unrealizable"),
    (Exit.REFUSED, "code transfer refused"),
)


def exit_codes_epilog(*codes: Exit) -> str:
    """The ``--help`` epilog line for the codes a tool uses (all of them when none is named)."""
    chosen = set(codes) if codes else {code for code, _ in EXIT_TABLE}
    return "exit codes: " + "; ".join(f"{int(c)} {text}" for c, text in EXIT_TABLE if c in chosen)


class UserError(Exception):
    """A problem the user can fix; ``str()`` is the one line to print, ``code`` the exit code."""

    code: Exit = Exit.BAD_INPUT

    def __init__(self, message: str, code: Exit | None = None):
        super().__init__(message)
        if code is not None:
            self.code = code


class InputError(UserError):
    """A file that cannot be read as what it should be; ``str()`` is ``file[:line]: message``."""

    def __init__(self, file: str, message: str, line: int = 0):
        self.file, self.line, self.message = file, line, message
        super().__init__(f"{file}:{line}: {message}" if line else f"{file}: {message}")


class OutputError(UserError):
    """An output that must not or could not be written."""
