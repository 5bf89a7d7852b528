"""The mapping file with edited rows written back and everything else kept (``runtime.config.mapping_edit``), and
what the executor says it runs (``runtime.executor.running_spec``): ROS- and Qt-free, run under every Python."""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ltl_stack.runtime.config.mapping import INPUT, OUTPUT, parse_mapping
from ltl_stack.runtime.config.mapping_edit import EditedRow, rows_text, text_digest
from ltl_stack.runtime.executor.running_spec import read_spec, running_spec, spec_digest

TEXT = """\
# a comment at the top
namespace: 'demo'
expected_feedback:
  go: '*_rc'   # designed loop
inputs:
  seen:
    node: 'camera'        # the camera node
    node_publish_topic: 'seen'
    parameters:
      threshold: 1.0
outputs:
  go:
    - node: 'base'
      node_subscribe_topic: 'go'
      pkg: 'ltl_stack'
    # a second node for go
    - node: 'arm'
      node_subscribe_topic: 'go'
"""


def test_no_change_is_the_text_itself():
    rows = {(INPUT, "seen"): [EditedRow("camera", "seen", 0)],
            (OUTPUT, "go"): [EditedRow("base", "go", 0), EditedRow("arm", "go", 1)]}
    assert rows_text(TEXT, rows) == TEXT


def test_an_edit_changes_only_its_value():
    rows = {(INPUT, "seen"): [EditedRow("/eye", "seen", 0)],
            (OUTPUT, "go"): [EditedRow("base", "go", 0), EditedRow("arm", "go", 1)]}
    out = rows_text(TEXT, rows)
    assert out == TEXT.replace("node: 'camera'        #", "node: '/eye'          #", 1)  # the comment stays in its column
    assert parse_mapping(out).inputs["seen"][0].parameters == {"threshold": 1.0}


def test_deleted_added_and_reordered_rows_keep_their_own_keys_and_every_comment():
    rows = {(INPUT, "seen"): [EditedRow("camera", "seen", 0)],
            (OUTPUT, "go"): [EditedRow("arm", "go", 1), EditedRow("new", "", None)]}
    out = rows_text(TEXT, rows)
    back = parse_mapping(out)
    assert [(e.node, e.pkg) for e in back.outputs["go"]] == [("arm", None), ("new", None)]
    assert back.expected_feedback == parse_mapping(TEXT).expected_feedback and back.namespace == "demo"
    for comment in ("# a comment at the top", "# designed loop", "# the camera node"):
        assert comment in out


def test_a_file_with_a_proposition_written_twice_is_left_to_the_whole_writer():
    twice = "outputs:\n  go:\n    node: a\n  go:\n    node: b\n"
    assert rows_text(twice, {(OUTPUT, "go"): [EditedRow("c", "", 0)]}) is None


def test_what_the_executor_runs(tmp_path: Path):
    spec = tmp_path / "s.structuredslugs"
    spec.write_text("[INPUT]\na\n")
    options = SimpleNamespace(robotics_semantics=None, cooperative=False, strategy="", max_explicit_states=7)
    got = running_spec(str(spec), None, options)
    assert (got.spec_file, got.spec_text, got.spec_sha256) == (str(spec), "[INPUT]\na\n", spec_digest("[INPUT]\na\n"))
    assert (got.generation, got.robotics_semantics, got.cooperative, got.max_explicit_states) == (0, True, False, 7)
    assert read_spec(str(tmp_path / "missing")) == ("", "") and text_digest("x") == spec_digest("x")
