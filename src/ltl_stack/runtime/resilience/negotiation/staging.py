"""Two-phase adoption files: phi* is written aside before a realizable status 2 is sent and renamed onto
the adopted-spec file only once both parties agreed (docs/negotiation.md, "Two-phase adoption")."""
from __future__ import annotations

import contextlib
from pathlib import Path

from ltl_stack.fileio import write_atomic
from ltl_stack.runtime.resilience.negotiation.messages import Adoption
from ltl_stack.spec import write_slugsin
from ltl_stack.spec.model import Spec


def write_adopted(adoption: Adoption, path: str | Path) -> None:
    """Write an adopted spec atomically (structured text; slugsin for a ``.slugsin`` path)."""
    path = Path(path)
    if path.suffix == ".slugsin":
        write_atomic(path, write_slugsin(adoption.spec, comments=True))
    else:
        write_atomic(path, adoption.text)


def stage_adopted(spec: Spec, text: str, path: str | Path, session: str) -> Path:
    """Phase one of a two-phase adoption: the spec written next to ``path`` under a name of its own
    (``OSError`` when it cannot be: the folder is gone, not writable, ``path`` is a folder). Returns
    the staged file for ``commit_adopted``."""
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(21, "is a folder", str(path))
    staged = path.with_name(f".{path.name}.{session.replace('>', '').replace('/', '_')}.staged")
    write_atomic(staged, write_slugsin(spec, comments=True) if path.suffix == ".slugsin" else text)
    return staged


def commit_adopted(staged: Path, path: str | Path) -> None:
    """Phase two: the staged file replaces ``path`` (one rename in one folder)."""
    staged.replace(path)


def discard_staged(staged: Path | None) -> None:
    """A negotiation that did not end in adoption leaves no staged file behind."""
    if staged is not None:
        with contextlib.suppress(OSError):
            staged.unlink()
