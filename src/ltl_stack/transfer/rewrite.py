"""Rewriting a program by replacing byte spans only: every byte outside an edit stays as it was."""
from __future__ import annotations

from dataclasses import dataclass

from .source_ast import Span


@dataclass(frozen=True)
class Edit:
    span: Span
    text: str


def apply_edits(data: bytes, edits: list[Edit]) -> bytes:
    """Replace each span by its text; equal duplicate edits collapse, overlapping ones are a bug."""
    unique = sorted(set(edits), key=lambda e: (e.span.start, e.span.end))
    for before, after in zip(unique, unique[1:]):
        if after.span.start < before.span.end:
            raise ValueError(f"overlapping edits at line {before.span.line}: {before.text!r} / {after.text!r}")
    out = bytearray(data)
    for edit in reversed(unique):
        out[edit.span.start:edit.span.end] = edit.text.encode("utf-8")
    return bytes(out)
