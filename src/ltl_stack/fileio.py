"""Writing files so that a failure never leaves a half-written one (every layer uses this)."""
from __future__ import annotations

import errno
import os
import stat
import tempfile
from pathlib import Path

from ltl_stack.textio import file_kind


def output_refusal(path: str | os.PathLike) -> str | None:
    """Why ``path`` cannot be an output, or None when it is a new path or a regular file (also
    through a link). An output replaces its target by a regular file, so a FIFO, a device
    (``/dev/null``), a socket or a folder there is refused, never replaced."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return None
    except OSError:  # unreadable folder, a loop of links: the write itself will say what is wrong
        return None
    if stat.S_ISREG(mode):
        return None
    return f"it is a {file_kind(mode)}, not a regular file"



def write_atomic(path: str | Path, data: str | bytes, mode: int | None = None) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder and ``os.replace``.

    The file gets ``mode`` when given, else the permissions a new file gets under the umask.
    Raises OSError (nothing is left behind) when the folder cannot be written or ``path`` names
    something that is not a regular file (``output_refusal``).
    """
    path = Path(path)
    refusal = output_refusal(path)
    if refusal:
        raise OSError(errno.EINVAL, refusal)
    raw = data.encode("utf-8") if isinstance(data, str) else data
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=str(path.parent))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        if mode is None:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
