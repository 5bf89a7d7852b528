"""Structured English files as users have them: plain sentence files and LTLMoP project files.

``read_english`` tells the two apart and hands each to its reader: ``structured_english.read_sentences``
for declarations and sentences, ``ltlmop_project.read_project`` for an LTLMoP project
(``======== SETTINGS ========`` …), read as shipped with LTLMoP's meaning. The project reader builds
on the sentence reader, so the choice lives here, above both. ``append_sentences`` adds sentences —
suggestions of the graph analysis, learned assumptions — to a file, atomically and only if the whole
file still reads.
"""
from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.fileio import write_atomic
from ltl_stack.inputs import read_text
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.ltlmop_project import read_project
from ltl_stack.spec.model import Spec
from ltl_stack.spec.structured_english import EnglishSpec, is_ltlmop_project, read_sentences


def read_english(text: str, file: str = "<string>",
                 base_dir: str | Path | None = None) -> EnglishSpec:
    """The spec of a Structured English text with its declarations and sentences (for rendering
    back); one ``SpecError`` naming file, line and column for a mistake. ``Map:`` paths are relative
    to ``base_dir`` (default: the folder of ``file``)."""
    if base_dir is None:
        base_dir = Path(file).parent if file and not file.startswith("<") else Path(".")
    if is_ltlmop_project(text):
        return read_project(text, file, Path(base_dir))
    return read_sentences(text, file, Path(base_dir))


def parse_english(text: str, file: str = "<string>", base_dir: str | Path | None = None) -> Spec:
    """``read_english``'s spec alone."""
    return read_english(text, file, base_dir).spec


def append_sentences(path: str | os.PathLike, sentences: Iterable[str]) -> EnglishSpec:
    """Append ``sentences`` (one per line) to the English spec at ``path``, atomically.

    The whole new text is read first; if it does not read (a sentence that does not parse, an
    unknown name) the ``SpecError`` is raised and the file is left as it was.
    """
    path = Path(path)
    try:
        old = read_text(path, "spec file")
    except InputError as e:
        raise SpecError(str(path), e.line, 0, e.message) from None
    added = [s.strip() for s in sentences if s.strip()]
    for s in added:
        if "\n" in s or "\r" in s:
            raise SpecError(str(path), 0, 0, f"a sentence is one line: {s!r}")
    text = old + ("" if not old or old.endswith("\n") else "\n") + "".join(s + "\n" for s in added)
    result = read_english(text, str(path))
    mode = path.stat().st_mode & 0o7777
    write_atomic(path, text, mode=mode)
    return result


__all__ = ["append_sentences", "parse_english", "read_english"]
