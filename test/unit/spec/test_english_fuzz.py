"""Any text given to the English reader gives a Spec or one SpecError (never another exception)."""
from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.spec.english_files import parse_english
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.structured_english import KEYWORDS, PHRASES, TEMPLATES

HEADER = "Sensors: person, door\nActions: move, stop\nActions with completion: pick\nMemory: seen\nRegions: r1, r2\n"
WORDS = sorted(KEYWORDS) + ["person", "door", "move", "stop", "pick", "seen", "r1", "r2", "r1_rc", "pick_ac",
                            "persn", "(", ")", ",", ".", "Always", "If", "Assume", ":", "#", "Map:", "Regions:"]
WORDS += [" ".join(p) for p in list(PHRASES)[:40]] + TEMPLATES


def _read(text: str) -> None:
    try:
        spec = parse_english(text, "fuzz.spec", base_dir="/nonexistent")
    except SpecError as e:
        assert e.file == "fuzz.spec" and e.line >= 0 and e.column >= 0
        assert str(e).startswith("fuzz.spec")
        return
    assert all(c.file == "fuzz.spec" for s in ("sys_safety", "env_safety", "sys_liveness") for c in spec.section(s))


@settings(max_examples=400, deadline=None)
@given(st.text(max_size=200))
def test_any_text(text):
    _read(text)


@settings(max_examples=600, deadline=None)
@given(st.lists(st.lists(st.sampled_from(WORDS), max_size=14).map(" ".join), max_size=6))
def test_sentence_like_text(lines):
    _read(HEADER + "\n".join(lines) + "\n")


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(WORDS), max_size=20).map(" ".join))
def test_sentence_like_declarations(line):
    _read(line + "\n" + HEADER + "Always move\n")
