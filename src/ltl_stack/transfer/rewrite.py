"""Rewriting a program by replacing byte spans only: every byte outside an edit stays as it was."""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .errors import TransferError
from .source_ast import Span


@dataclass(frozen=True)
class Edit:
    span: Span
    text: str


def apply_edits(data: bytes, edits: list[Edit]) -> bytes:
    """Replace each span by its text; equal duplicate edits collapse, overlapping ones are a bug."""
    unique = sorted(set(edits), key=lambda e: (e.span.start, e.span.end))
    for before, after in zip(unique, unique[1:], strict=False):
        if after.span.start < before.span.end:
            raise ValueError(f"overlapping edits at line {before.span.line}: {before.text!r} / {after.text!r}")
    out = bytearray(data)
    for edit in reversed(unique):
        out[edit.span.start:edit.span.end] = edit.text.encode("utf-8")
    return bytes(out)


def write_atomic(path: str | Path, data: bytes | str, mode: int | None = None) -> None:
    """Write through a temporary file and ``os.replace``, so no half-written file is ever left."""
    path = Path(path)
    if isinstance(data, str):
        data = data.encode("utf-8")
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    except OSError as err:
        raise TransferError(f"cannot write: {err.strerror}", str(path)) from None
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        if mode is not None:
            os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
