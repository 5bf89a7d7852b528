"""Structured English files as users have them: plain sentence files and LTLMoP project files.

``read_english`` tells the two apart and hands each to its reader: ``english_reader.read_sentences``
for declarations and sentences, ``ltlmop_project.read_project`` for an LTLMoP project
(``======== SETTINGS ========`` …), read as shipped with LTLMoP's meaning. The project reader builds
on the sentence reader, so the choice lives here, above both.
"""
from __future__ import annotations

from pathlib import Path

from ltl_stack.spec.english_reader import EnglishSpec, is_ltlmop_project, read_sentences
from ltl_stack.spec.ltlmop_project import read_project
from ltl_stack.spec.model import Spec


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


__all__ = ["parse_english", "read_english"]
