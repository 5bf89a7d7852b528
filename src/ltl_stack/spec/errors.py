"""The one error every spec reader raises for bad input: where it is and what was expected."""
from __future__ import annotations

from ltl_stack.errors import UserError


class SpecError(UserError):
    """A problem in a specification file, located by file, line and column (both 1-based).

    ``str(error)`` is ``file:line:column: message``, the form editors and compilers use, so a
    command-line tool can print it as it is. File-level problems (a missing file) have line 0 and
    print as ``file: message``; a problem known by line only (column 0) prints as ``file:line: message``.
    It is a ``UserError`` (exit code 2, ``ltl_stack.errors``).
    """

    def __init__(self, file: str, line: int, column: int, message: str):
        self.file = file
        self.line = line
        self.column = column
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        if self.line <= 0:
            return f"{self.file}: {self.message}"
        if self.column <= 0:
            return f"{self.file}:{self.line}: {self.message}"
        return f"{self.file}:{self.line}:{self.column}: {self.message}"
