"""Reading a user's text file: one ``InputError`` naming the file (and line) for a missing file, a
folder, a device or FIFO, a file above the size cap, a binary file or text that is not UTF-8.

The part of ``ltl_stack.inputs`` that needs no YAML or JSON parser, so a command that only reads a
specification (``synthesize SPEC``) does not import PyYAML (~7 ms of its start-up);
``ltl_stack.inputs`` re-exports both functions, which stay the way every loader reads its file.
"""
from __future__ import annotations

import os
import stat

from ltl_stack.errors import InputError

#: the largest file any loader reads (the largest real input, a graph snapshot, is ~3 MB): a file
#: that grows while it is read, or is far too large, is refused instead of filling memory
MAX_INPUT_BYTES = 256 * 1024 * 1024


def file_kind(mode: int) -> str:
    """What a ``stat`` mode names, in words (for messages about something that is not a regular file)."""
    for test, kind in ((stat.S_ISDIR, "directory"), (stat.S_ISFIFO, "FIFO (named pipe)"),
                       (stat.S_ISCHR, "character device"), (stat.S_ISBLK, "block device"),
                       (stat.S_ISSOCK, "socket")):
        if test(mode):
            return kind
    return "regular file" if stat.S_ISREG(mode) else "special file"


def read_bytes(path: str | os.PathLike, what: str = "file", max_bytes: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of the regular file ``path``, at most ``max_bytes`` of them.

    The one bounded reader: anything but a regular file (a folder, ``/dev/zero``, a FIFO, a socket)
    is refused with ``InputError`` before a byte is read, so no input blocks or grows without end;
    the file is opened non-blocking, so a FIFO with no writer does not block the open either.
    """
    file = str(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except FileNotFoundError:
        raise InputError(file, "no such file") from None
    except OSError as e:
        raise InputError(file, f"cannot read: {e.strerror or e}") from None
    try:
        mode = os.fstat(fd).st_mode
        if stat.S_ISDIR(mode):
            raise InputError(file, f"is a directory, not a {what}")
        if not stat.S_ISREG(mode):
            raise InputError(file, f"is a {file_kind(mode)}, not a regular file ({what})")
        os.set_blocking(fd, True)
        raw = _read_at_most(fd, max_bytes + 1) if os.fstat(fd).st_size <= max_bytes else None
    except OSError as e:
        raise InputError(file, f"cannot read: {e.strerror or e}") from None
    finally:
        os.close(fd)
    if raw is None or len(raw) > max_bytes:
        raise InputError(file, f"{what} is larger than {max_bytes} bytes")
    return raw


def _read_at_most(fd: int, limit: int) -> bytes:
    chunks, left = [], limit
    while left > 0:
        chunk = os.read(fd, min(left, 1 << 20))
        if not chunk:
            break
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def read_text(path: str | os.PathLike, what: str = "file", max_bytes: int = MAX_INPUT_BYTES) -> str:
    """The text of ``path`` (UTF-8, a byte-order mark tolerated), read through ``read_bytes``.

    Raises ``InputError`` naming the file for a missing file, anything but a regular file, a file
    above ``max_bytes``, a binary file (a NUL byte) or text that is not UTF-8 (with the line of the
    first bad byte).
    """
    return decode_text(read_bytes(path, what, max_bytes), str(path), what)


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
