"""The one writer of spec text assembled at run time (characterization, negotiation): what it writes
reads back as the same clauses, in either format."""
from __future__ import annotations

from ltl_stack.spec import formula_to_slugsin, parse_slugsin, parse_structured
from ltl_stack.spec.writer import write_spec_text


def test_written_text_reads_back_in_both_formats():
    spec = parse_structured("[INPUT]\na\n[OUTPUT]\nb\n[ENV_TRANS]\na' -> !a\n[SYS_TRANS]\n!b' | a'\n", "s")
    sections = {"env_safety": ["# the assumption", spec.env_safety[0].formula],
                "sys_safety": [spec.sys_safety[0].formula], "sys_liveness": []}
    text = write_spec_text(sections, header=["# header"], inputs=spec.inputs, outputs=spec.outputs)
    assert text.splitlines()[:7] == ["# header", "[INPUT]", "a", "", "[OUTPUT]", "b", ""], text
    assert "[ENV_INIT]" not in text and "[SYS_LIVENESS]" in text
    again = parse_structured(text, "again")
    assert again.env_safety[0].formula == spec.env_safety[0].formula
    assert again.sys_safety[0].formula == spec.sys_safety[0].formula
    slugsin = parse_slugsin(write_spec_text(sections, inputs=spec.inputs, outputs=spec.outputs,
                                            render=formula_to_slugsin), "again.slugsin")
    assert slugsin.sys_safety[0].formula == spec.sys_safety[0].formula
