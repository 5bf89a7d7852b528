"""``load_spec``: read a spec file in whichever format it is written."""
from __future__ import annotations

from pathlib import Path

from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.model import Spec
from ltl_stack.spec.slugsin import parse_slugsin

STRUCTURED_SUFFIXES = (".structuredslugs", ".ltl")


def load_spec(path: str | Path) -> Spec:
    """Read ``path``: ``.slugsin`` as slugsin, ``.structuredslugs``/``.ltl`` as the structured format.

    Any other name is tried as slugsin, then as structured; when both fail, the error of the reader
    that got further into the file is raised. Every problem is a ``SpecError`` naming the path.
    """
    path = Path(path)
    file = str(path)
    try:
        text = path.read_text(encoding="utf-8-sig")  # tolerate a byte-order mark
    except FileNotFoundError:
        raise SpecError(file, 0, 0, "no such file") from None
    except IsADirectoryError:
        raise SpecError(file, 0, 0, "is a directory, not a spec file") from None
    except UnicodeDecodeError as e:
        raise SpecError(file, 0, 0, f"not a text file (not UTF-8 at byte {e.start})") from None
    except OSError as e:
        raise SpecError(file, 0, 0, f"cannot read: {e.strerror or e}") from None
    from ltl_stack.spec.structured import parse_structured

    suffix = path.suffix.lower()
    if suffix == ".slugsin":
        return parse_slugsin(text, file)
    if suffix in STRUCTURED_SUFFIXES:
        return parse_structured(text, file)
    try:
        return parse_slugsin(text, file)
    except SpecError as as_slugsin:
        try:
            return parse_structured(text, file)
        except SpecError as as_structured:
            if (as_structured.line, as_structured.column) > (as_slugsin.line, as_slugsin.column):
                raise as_structured from None
            raise as_slugsin from None
