"""Any text at all gives either a Spec or one SpecError, never another exception."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.spec import Spec, SpecError, parse_slugsin, parse_structured

WORDS = ["[INPUT]", "[OUTPUT]", "[SYS_TRANS]", "[ENV_INIT]", "[SYS_LIVENESS]", "[FOO]", "[", "]",
         "a", "b", "a'", "b''", "x", "x'", "x:0...5", "y: 2...4", "z:3...1", "x@1", "x@0.0.5",
         "&", "|", "!", "^", "~", "$", "$2", "?", "?0", "? 1", "0", "1", "2", "17", "TRUE", "FALSE",
         "(", ")", "->", "<->", "=", "!=", "<", ">=", "+", "-", "*", "#", "'", "%", ":", "..."]

texts = st.lists(st.tuples(st.sampled_from(WORDS), st.sampled_from([" ", " ", "\n", ""])), max_size=40).map(
    lambda parts: "".join(w + sep for w, sep in parts))


@pytest.mark.parametrize("parse", [parse_slugsin, parse_structured])
@settings(max_examples=400, deadline=None)
@given(text=texts)
def test_readers_never_crash(parse, text):
    try:
        assert isinstance(parse(text, "f"), Spec)
    except SpecError as e:
        assert e.file == "f" and e.line >= 1 and e.column >= 1 and e.message, e


@settings(max_examples=300, deadline=None)
@given(st.lists(st.sampled_from(WORDS[6:]), min_size=1, max_size=25))
def test_clause_lines_never_crash(words):
    header = "[INPUT]\na\nb\nx:0...5\n[OUTPUT]\ny: 2...4\n[SYS_TRANS]\n"
    for parse in (parse_slugsin, parse_structured):
        try:
            parse(header + " ".join(words) + "\n", "f")
        except SpecError as e:
            assert (e.line, e.column >= 1) == (8, True), e
