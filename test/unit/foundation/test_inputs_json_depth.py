"""The fast JSON nesting check of ``ltl_stack.inputs`` counts exactly what the JSON holds."""
from __future__ import annotations

import json

from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.inputs import _json_max_depth

TRICKY = st.text(alphabet='[]{}"\\\\ nu/é\n\t', max_size=8)
VALUES = st.recursive(st.none() | st.integers() | TRICKY,
                      lambda inner: st.lists(inner, max_size=3) | st.dictionaries(TRICKY, inner, max_size=3),
                      max_leaves=30)


def depth(value) -> int:
    if isinstance(value, list):
        return 1 + max((depth(v) for v in value), default=0)
    if isinstance(value, dict):
        return 1 + max((depth(v) for v in value.values()), default=0)
    return 0


@settings(max_examples=400, deadline=None)
@given(VALUES, st.booleans(), st.booleans())
def test_fast_depth_equals_the_nesting_of_the_value(value, ascii_only, indent):
    text = json.dumps(value, ensure_ascii=ascii_only, indent=1 if indent else None)
    assert _json_max_depth(text) == depth(value), text


def test_escaped_quotes_and_backslashes_do_not_hide_brackets():
    deep = "[" * 150 + "]" * 150
    assert _json_max_depth(json.dumps(["a\\", "\n", "\\\"", deep])) == 1
    assert _json_max_depth('["a\\\\", "\\n", ' + deep + "]") == 151
