"""The one error type a user can cause during code transfer (bad file, unknown robot, ...)."""
from __future__ import annotations


class TransferError(Exception):
    """A problem with the user's input; ``str()`` names the file and, when known, the element or line."""

    def __init__(self, message: str, file: str | None = None, where: str | None = None):
        self.message = message
        self.file = file
        self.where = where
        super().__init__(str(self))

    def __str__(self) -> str:
        prefix = ""
        if self.file:
            prefix = f"{self.file}: "
        if self.where:
            prefix += f"{self.where}: "
        return prefix + self.message
