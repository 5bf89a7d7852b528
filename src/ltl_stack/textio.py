"""Reading a user's text file: one ``InputError`` naming the file (and line) for a missing file, a
folder, a binary file or text that is not UTF-8.

The part of ``ltl_stack.inputs`` that needs no YAML or JSON parser, so a command that only reads a
specification (``synthesize SPEC``) does not import PyYAML (~7 ms of its start-up);
``ltl_stack.inputs`` re-exports both functions, which stay the way every loader reads its file.
"""
from __future__ import annotations

import os
from pathlib import Path

from ltl_stack.errors import InputError


def read_text(path: str | os.PathLike, what: str = "file", max_bytes: int | None = None) -> str:
    """The text of ``path`` (UTF-8, a byte-order mark tolerated).

    Raises ``InputError`` naming the file for a missing file, a folder, a binary file (a NUL byte),
    text that is not UTF-8 (with the line of the first bad byte) or a file above ``max_bytes``.
    """
    file = str(path)
    try:
        if max_bytes is not None and os.path.getsize(path) > max_bytes:
            raise InputError(file, f"{what} is larger than {max_bytes} bytes")
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise InputError(file, "no such file") from None
    except IsADirectoryError:
        raise InputError(file, f"is a directory, not a {what}") from None
    except OSError as e:
        raise InputError(file, f"cannot read: {e.strerror or e}") from None
    return decode_text(raw, file, what)


def decode_text(raw: bytes, file: str, what: str = "file") -> str:
    """``raw`` as UTF-8 text, or ``InputError`` for binary data or bytes that are not UTF-8."""
    nul = raw.find(b"\0")
    if nul >= 0:
        raise InputError(file, f"not a text {what}: it holds a NUL byte", raw.count(b"\n", 0, nul) + 1)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = raw.count(b"\n", 0, e.start) + 1
        raise InputError(file, f"not a text {what}: not UTF-8 at byte {e.start}", line) from None
