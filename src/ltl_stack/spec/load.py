"""``load_spec``: read a spec file in whichever format it is written."""
from __future__ import annotations

from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.model import Spec
from ltl_stack.spec.slugsin import parse_slugsin
from ltl_stack.spec.structured import parse_structured
from ltl_stack.textio import read_text

STRUCTURED_SUFFIXES = (".structuredslugs", ".ltl")


def load_spec(path: str | Path) -> Spec:
    """Read ``path``: ``.slugsin`` as slugsin, ``.structuredslugs``/``.ltl`` as the structured format,
    ``.spec``/``.english`` as Structured English (``structured_english``) unless the file starts with a
    section header such as ``[INPUT]``.

    Any other name is tried as slugsin, then as structured; when both fail, the error of the reader
    that got further into the file is raised. Every problem is a ``SpecError`` naming the path (a
    file that is not text, e.g. binary or not UTF-8, too, with the line of the first bad byte; an
    empty file, which would be trivially realizable).
    """
    path = Path(path)
    file = str(path)
    try:
        text = read_text(path, "spec file")  # a byte-order mark is tolerated
    except InputError as e:  # missing, a folder, binary (NUL byte), not UTF-8: one line naming file[:line]
        raise SpecError(file, e.line, 0, e.message) from None
    if not text.strip():  # an empty spec would be "realizable" and mean nothing
        raise SpecError(file, 0, 0, "the spec file is empty")
    suffix = path.suffix.lower()
    if suffix == ".slugsin":
        return parse_slugsin(text, file)
    if suffix in STRUCTURED_SUFFIXES:
        return parse_structured(text, file)
    # imported here, not at the top: the English reader's phrase tables cost ~12 ms of every
    # command's start-up, and only a file that is neither slugsin nor structured may be English
    from ltl_stack.spec import structured_english

    if suffix in structured_english.ENGLISH_SUFFIXES and not structured_english.has_section_headers(text):
        from ltl_stack.spec.english_files import parse_english

        return parse_english(text, file)
    try:
        return parse_slugsin(text, file)
    except SpecError as as_slugsin:
        try:
            return parse_structured(text, file)
        except SpecError as as_structured:
            if (as_structured.line, as_structured.column) > (as_slugsin.line, as_slugsin.column):
                raise as_structured from None
            raise as_slugsin from None
