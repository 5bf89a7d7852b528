"""The errors a user can cause during code transfer (bad file, unknown robot, ...) and the refusal."""
from __future__ import annotations

from ltl_stack.errors import Exit, UserError


class TransferError(UserError):
    """A problem with the user's input; ``str()`` names the file and, when known, the element or line."""

    code = Exit.BAD_INPUT

    def __init__(self, message: str, file: str | None = None, where: str | None = None, code: Exit | None = None):
        self.message = message
        self.file = file
        self.where = where
        super().__init__(str(self), code)

    def __str__(self) -> str:
        prefix = ""
        if self.file:
            prefix = f"{self.file}: "
        if self.where:
            prefix += f"{self.where}: "
        return prefix + self.message


class TransferRefused(TransferError):
    """The transfer cannot be done safely at all (e.g. differential <-> holonomic velocity commands)."""

    code = Exit.REFUSED
