"""The panels' Qt-free logic: DOT and layout, mapping document and validation, analysis tables and
suggestions, the controller model (ids, neighbourhood, hand-over between threads)."""
from __future__ import annotations

import shutil
import threading

import pytest
from gui_data import ANALYSIS_DATA, CLEAN_MAPPING, CLEAN_SPEC, SIMPLE_MAPPING, SIMPLE_SPEC, simple_snapshot
from gui_data import scenarios as analysis_scenarios
from helpers import require_shared
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.analysis.snapshot import Snapshot
from ltl_stack.gui.analysis_model import (
    FEEDBACK_KEY,
    TAB_KEYS,
    AnalysisView,
    apply_and_check,
    conflict_graph,
    names,
    run_analysis,
    suggestion_text,
)
from ltl_stack.gui.controller_model import (
    MAX_DRAWN_EDGES,
    ControllerModel,
    Latest,
    StateUpdate,
    ViewOptions,
    assemble_automaton,
    automaton_parts,
    executor_of,
    mode_text,
)
from ltl_stack.gui.dotgraph import DotGraph, layout_dot, layout_plain, parse_plain, sketch_layout
from ltl_stack.gui.mapping_model import INPUT, OUTPUT, LiveGraph, MappingDocument
from ltl_stack.runtime.config.mapping import load_mapping, parse_mapping
from ltl_stack.synthesis import Automaton

needs_dot = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz 'dot' is not installed")


# --- DOT ------------------------------------------------------------------------------------------

def test_dot_graph_gives_safe_ids_and_quotes_labels():
    g = DotGraph()
    a = g.add_node(("topic", "/cmd_vel"), 'say "hi"\nthere')
    assert g.add_node(("topic", "/cmd_vel"), "again") == a == "n0"
    g.add_node(7, "seven")
    g.add_edge(("topic", "/cmd_vel"), 7, "x")
    text = g.to_dot()
    assert 'n0 [label="say \\"hi\\"\\nthere"' in text and "n0 -> n1" in text


@needs_dot
def test_layouts_keep_the_node_ids():
    g = DotGraph()
    g.add_node("a", "12 (goal 1)\nmove", shape="box")
    g.add_node("b", "[/cmd_vel]", shape="ellipse", color="red")
    g.add_edge("a", "b", "person")
    plain = layout_plain(g.to_dot())
    assert set(plain.nodes) == {"n0", "n1"} and plain.nodes["n1"].color == "red"
    assert plain.edges[0].label == "person" and len(plain.edges[0].points) >= 4
    laid = layout_dot(g.to_dot())
    assert "pos=" in laid and "n1" in laid



@settings(max_examples=50, deadline=None)
@given(st.integers(1, 25).flatmap(lambda n: st.tuples(
    st.just(n), st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=60),
    st.integers(0, n - 1), st.lists(st.integers(0, 3), min_size=n, max_size=n))))
def test_a_sketch_places_every_node_apart_with_straight_edges_between_borders(case):
    """sketch_layout (drawn while Graphviz works): every node placed inside the picture, no two boxes
    overlap, nodes one step from the first in the next column, and each edge runs border to border."""
    n, pairs, first, lines = case
    g = DotGraph()
    for k in range(n):
        g.add_node(k, "\n".join([f"state {k}"] + ["x" * (k % 7)] * lines[k]))
    for s, t in pairs:
        g.add_edge(s, t)
    sketch = sketch_layout(g, g.key[first])
    boxes = {i: (p.x - p.width / 2, p.y - p.height / 2, p.x + p.width / 2, p.y + p.height / 2)
             for i, p in sketch.nodes.items()}
    assert set(boxes) == {node.id for node in g.nodes}
    eps = 1e-6
    for x0, y0, x1, y1 in boxes.values():
        assert -eps <= x0 and x1 <= sketch.width + eps and -eps <= y0 and y1 <= sketch.height + eps
    ids = sorted(boxes)
    for i, a in enumerate(ids):
        for b in ids[i + 1:]:
            (ax0, ay0, ax1, ay1), (bx0, by0, bx1, by1) = boxes[a], boxes[b]
            assert ax1 <= bx0 + eps or bx1 <= ax0 + eps or ay1 <= by0 + eps or by1 <= ay0 + eps, (a, b)
    first_x = sketch.nodes[g.key[first]].x
    for s, t in pairs:
        if first in (s, t) and s != t:
            other = sketch.nodes[g.key[t if s == first else s]]
            assert other.x > first_x
    drawn = [(e.source, e.target) for e in sketch.edges]
    assert drawn == [(g.key[s], g.key[t]) for s, t in pairs if s != t]
    for e in sketch.edges:
        for (x, y), node in ((e.points[0], e.source), (e.points[-1], e.target)):
            x0, y0, x1, y1 = boxes[node]
            on_side = min(abs(x - x0), abs(x - x1), abs(y - y0), abs(y - y1))
            assert x0 - eps <= x <= x1 + eps and y0 - eps <= y <= y1 + eps and on_side < 1e-6

def test_parse_plain_edges_with_and_without_labels():
    text = ("graph 1 3 0.5\nnode n0 0.5 0.25 1 0.5 \"a b\" solid box black lightgrey\n"
            "node n1 2.5 0.25 1 0.5 b solid ellipse red red\n"
            "edge n0 n1 4 1 0.25 1.3 0.25 1.6 0.25 1.9 0.25 \"x y\" 1.5 0.3 solid black\n"
            "edge n1 n0 4 2 0.2 1.8 0.2 1.5 0.2 1.2 0.2 solid blue\nstop\n")
    p = parse_plain(text)
    assert p.nodes["n0"].label == "a b" and p.nodes["n1"].shape == "ellipse"
    assert (p.edges[0].label, p.edges[0].label_pos) == ("x y", (1.5, 0.3))
    assert (p.edges[1].label, p.edges[1].color) == ("", "blue")


# --- mapping ----------------------------------------------------------------------------------------

def clean_graph() -> LiveGraph:
    """The clean-and-patrol proposition nodes as the generated launch file starts them."""
    pubs, subs, types = [], [], []
    doc = MappingDocument.load(str(CLEAN_SPEC), str(CLEAN_MAPPING))
    ns = "clean_and_patrol"
    mapping = load_mapping(CLEAN_MAPPING)
    for prop in doc.inputs:
        topic = f"/{ns}/inputs/{prop}"
        node = f"/{ns}/{mapping.inputs[prop][0].node}"  # e.g. one region_localization node for every R_rc
        pubs.append((topic, [node]))
        types.append((topic, "std_msgs/Bool"))
    for prop in doc.outputs:
        topic = f"/{ns}/outputs/{prop}"
        subs.append((topic, [f"/{ns}/{prop}"]))
        pubs.append((topic, [f"/{ns}/controller_executor"]))
        types.append((topic, "std_msgs/Bool"))
    pubs.append((f"/{ns}/cmd_vel", [f"/{ns}/stop", f"/{ns}/navigation"]))
    types.append((f"/{ns}/cmd_vel", "geometry_msgs/Twist"))
    return LiveGraph(Snapshot.from_system_state(pubs, subs, [], types))


def test_loading_lists_the_spec_propositions_and_the_mapping_rows():
    doc = MappingDocument.load(str(CLEAN_SPEC), str(CLEAN_MAPPING))
    assert doc.inputs[0] == "object" and "rightGround" in doc.outputs
    row = doc.row(INPUT, "object")
    assert (row.node, row.topic, row.base.filename) == ("object", "object", "topic_threshold_sensor")
    assert doc.scenario_namespace() == "clean_and_patrol"


def test_the_clean_and_patrol_mapping_is_clean_on_its_own_graph():
    doc = MappingDocument.load(str(CLEAN_SPEC), str(CLEAN_MAPPING))
    assert doc.validate(clean_graph()) == []


def test_save_round_trips_and_keeps_pkg_filename_parameters(tmp_path):
    doc = MappingDocument.load(str(CLEAN_SPEC), str(CLEAN_MAPPING))
    doc.set_node(INPUT, "object", 0, "/camera_object")
    i = doc.add_row("stop")
    doc.set_node(OUTPUT, "stop", i, "/brake")
    out = tmp_path / "edited.yaml"
    doc.save(str(out))
    again = load_mapping(out)
    original = load_mapping(CLEAN_MAPPING)
    obj = again.inputs["object"][0]
    assert (obj.node, obj.pkg, obj.filename, obj.parameters) == (
        "/camera_object", "ltl_stack", "topic_threshold_sensor", original.inputs["object"][0].parameters)
    assert [e.node for e in again.outputs["stop"]] == ["stop", "/brake"]
    assert again.outputs["stop"][1].topic == "stop"  # relative, as the mapping is: /clean_and_patrol/outputs/stop
    assert again.outputs["topLane"][0].parameters == original.outputs["topLane"][0].parameters
    reloaded = MappingDocument.load(str(CLEAN_SPEC), str(out))
    assert reloaded.text() == doc.text()


def test_saving_over_the_spec_is_refused(tmp_path):
    from ltl_stack.errors import UserError

    spec = tmp_path / "s.structuredslugs"
    spec.write_text(SIMPLE_SPEC.read_text())
    doc = MappingDocument.load(str(spec), str(SIMPLE_MAPPING))
    with pytest.raises(UserError):
        doc.save(str(spec))
    assert spec.read_text() == SIMPLE_SPEC.read_text()


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["node", "add", "delete"]), st.integers(0, 10),
                          st.sampled_from(["", "a", "/b/c", "rel_node"])), max_size=12))
def test_any_edit_sequence_saves_what_reloads(edits):
    doc = MappingDocument.load(str(SIMPLE_SPEC), str(SIMPLE_MAPPING))
    for op, k, name in edits:
        kind, prop = (INPUT, "person") if k % 3 == 0 else (OUTPUT, ["move", "stop"][k % 2])
        rows = doc.rows[(kind, prop)]
        if op == "add" and kind == OUTPUT:
            doc.add_row(prop)
        elif op == "delete" and rows:
            doc.delete_row(kind, prop, k % len(rows))
        elif rows:
            doc.set_node(kind, prop, k % len(rows), name)
    text = doc.text()
    back = parse_mapping(text, "x.yaml")
    mine = doc.to_mapping()
    for kind, section in ((INPUT, mine.inputs), (OUTPUT, mine.outputs)):
        other = back.inputs if kind == INPUT else back.outputs
        assert [(p, [(e.node, e.topic, e.parameters) for e in es]) for p, es in section.items()] == \
            [(p, [(e.node, e.topic, e.parameters) for e in es]) for p, es in other.items()]
    assert len(doc.rows[(INPUT, "person")]) >= 1


def test_validation_reports_unmapped_missing_nodes_extra_publishers_and_wrong_types():
    doc = MappingDocument.load(str(SIMPLE_SPEC), str(SIMPLE_MAPPING))
    graph = LiveGraph(simple_snapshot())
    assert doc.validate(graph) == []
    doc.delete_row(OUTPUT, "stop", 0)
    msgs = [f.message for f in doc.validate(graph)]
    assert any("'stop' is not mapped" in m for m in msgs), msgs
    doc = MappingDocument.load(str(SIMPLE_SPEC), str(SIMPLE_MAPPING))
    doc.set_node(INPUT, "person", 0, "/gone")
    doc.set_topic(INPUT, "person", 0, "/simple/cmd_vel")
    found = {(f.severity, f.message.split(":")[0]) for f in doc.validate(graph)}
    text = " | ".join(f.message for f in doc.validate(graph))
    assert "node /gone is not on the master" in text
    assert "other publishers (/simple/move, /simple/stop)" in text
    assert "type geometry_msgs/Twist" in text
    assert ("error", "input 'person'") in found


def test_the_input_of_an_output_node_is_that_node():
    doc = MappingDocument.load(str(CLEAN_SPEC), str(CLEAN_MAPPING))
    graph = clean_graph()
    assert doc.resolved_node(INPUT, "pickup", graph) == "/clean_and_patrol/pickup"
    assert doc.resolved_node(OUTPUT, "pickup") == "/clean_and_patrol/pickup"
    assert graph.topics_for(INPUT, "/clean_and_patrol/pickup") == ["/clean_and_patrol/inputs/pickup_ac"]


# --- analysis -----------------------------------------------------------------------------------------

def simple_result(tmp_path):
    path = tmp_path / "simple_graph.json"
    simple_snapshot().save(path)
    return run_analysis(str(SIMPLE_SPEC), str(SIMPLE_MAPPING), snapshot_path=str(path))


def test_simple_scenario_tables_and_suggestion_forms(tmp_path):
    result = simple_result(tmp_path)
    tables = result.tables()
    assert tables["E2"].rows == [
        ["[/simple/cmd_vel]", "move", "(/simple/move) -> [/simple/cmd_vel]"],
        ["", "stop", "(/simple/stop) -> [/simple/cmd_vel]"]]
    assert tables["E2"].rows_of(0) == [0, 1] and tables["E1"].rows == []
    assert "move and stop are mutually exclusive" in suggestion_text(result.suggestions, "english")
    assert "G((move & !stop) | (!move & stop) | (!move & !stop))" in suggestion_text(result.suggestions, "ltl")
    slugsin = suggestion_text(result.suggestions, "slugsin")
    assert "[SYS_TRANS]" in slugsin and "[SYS_INIT]" in slugsin
    g = conflict_graph(result, "E2", 0)
    labels = {n.label: n.color for n in g.nodes}
    assert labels == {"/simple/move": "blue", "/simple/cmd_vel": "red", "/simple/stop": "blue"}


def test_expected_feedback_has_its_own_table_not_counted_as_findings(tmp_path):
    spec = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.slugsin")
    snapshot = analysis_scenarios.scenario_snapshot(ANALYSIS_DATA / "clean_and_patrol.yaml")
    result = run_analysis(str(spec), str(spec.with_suffix(".yaml")), snapshot=snapshot)
    tables = result.tables()
    assert tables["E1"].rows == [] and result.counts()["E1"] == 0
    assert tables[FEEDBACK_KEY].rows == [  # thesis Fig. 3.6, shown apart
        ["pickup", "pickup_ac", "pickup_ac reports the completion of the action pickup",
         "(/pickup) -> [/move_group_and_move_base/outputs/pickup_status] -> (/pickup_ac)"],
        ["drop", "drop_ac", "drop_ac reports the completion of the action drop",
         "(/drop) -> [/move_group_and_move_base/outputs/drop_status] -> (/drop_ac)"]]
    assert result.counts()[FEEDBACK_KEY] == 2 and TAB_KEYS[-1] == FEEDBACK_KEY
    assert "expected feedback: 2 pair(s)" in result.summary() and "E1 0" in result.summary()
    chains, ends = result.witnesses(FEEDBACK_KEY, 0)
    assert [w.text for w in chains] == [tables[FEEDBACK_KEY].rows[0][3]] and ends == {"/pickup_ac"}
    assert len(conflict_graph(result, FEEDBACK_KEY, 0).nodes) == 3


@pytest.fixture(scope="module")
def feedback_result():
    spec = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.slugsin")
    snapshot = analysis_scenarios.scenario_snapshot(ANALYSIS_DATA / "clean_and_patrol.yaml")
    return run_analysis(str(spec), str(spec.with_suffix(".yaml")), snapshot=snapshot, robots=["a", "b"])


@settings(max_examples=25, deadline=None)
@given(chunk=st.integers(min_value=1, max_value=600))
def test_the_analysis_sent_in_parts_is_the_analysis(feedback_result, chunk):
    """What the analysis process sends in parts (``AnalysisResult.parts``), assembled again, shows the
    same tables, counts, summary, suggestions, problems and chains as the result itself."""
    result = feedback_result
    view = AnalysisView.assemble(result.parts(chunk=chunk))
    assert {k: (t.header, t.rows, t.finding) for k, t in view.tables().items()} == \
        {k: (t.header, t.rows, t.finding) for k, t in result.tables().items()}
    assert view.counts() == result.counts() and view.summary() == result.summary()
    assert [view.suggestion_text(f) for f in ("english", "ltl", "slugsin")] == \
        [result.suggestion_text(f) for f in ("english", "ltl", "slugsin")]
    assert view.problems == result.problems and view.spec_path == result.spec_path
    for key, count in result.counts().items():
        for i in range(count if key != "C2" else 0):
            assert view.witnesses(key, i) == result.witnesses(key, i)
            assert conflict_graph(view, key, i).to_dot() == conflict_graph(result, key, i).to_dot()
    assert all(len(part[2]) <= chunk for part in result.parts(chunk=chunk) if part[0] in ("rows", "witnesses"))


def test_apply_and_check_appends_english_sentences_to_an_english_spec(tmp_path):
    path = tmp_path / "simple_graph.json"
    simple_snapshot().save(path)
    spec = SIMPLE_SPEC.with_suffix(".spec")
    result = run_analysis(str(spec), str(SIMPLE_MAPPING), snapshot_path=str(path))
    out = tmp_path / "simple_exclusive.spec"
    applied = apply_and_check(result, str(out))
    assert applied["format"] == "english" and applied["sentences"] == ["move and stop are mutually exclusive"]
    assert out.read_text() == spec.read_text().rstrip("\n") + "\n" + \
        "# added by analyze_graph (ROS graph analysis, thesis 3.5.2.3)\nmove and stop are mutually exclusive\n"
    assert applied["realizable"] is False  # Example 7: always move, stop for a person


def test_apply_and_check_shows_example_7_unrealizable(tmp_path):
    result = simple_result(tmp_path)
    out = tmp_path / "simple_amended.slugsin"
    applied = apply_and_check(result, str(out))
    assert out.is_file() and applied["realizable_before"] and not applied["realizable"]
    assert "UNREALIZABLE" in applied["text"] and "simple.structuredslugs" in applied["text"]
    assert "| & move' ! stop' | & ! move' stop' & ! move' ! stop'" in out.read_text()
    assert "move and stop are mutually exclusive" in applied["text"]


def test_apply_and_check_never_writes_over_an_input(tmp_path):
    from ltl_stack.errors import UserError

    result = simple_result(tmp_path)
    before = SIMPLE_SPEC.read_text()
    with pytest.raises(UserError):
        apply_and_check(result, str(SIMPLE_SPEC))
    assert SIMPLE_SPEC.read_text() == before


def test_names_field():
    assert names(" a, b ;c,, ") == ["a", "b", "c"]


# --- controller -------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def clean_model():
    return ControllerModel.synthesize(str(CLEAN_SPEC), ViewOptions())


@settings(max_examples=20, deadline=None)
@given(chunk=st.integers(min_value=1, max_value=80))
def test_the_automaton_sent_in_parts_is_the_automaton(clean_model, chunk):
    """What the worker process sends of a synthesis (``automaton_parts``), assembled again, is the same
    automaton, and no part holds more than ``chunk`` states."""
    a = clean_model.automaton
    parts = list(automaton_parts(a, chunk=chunk))
    assert all(len(p[1]) <= chunk for p in parts if p[0] == "states")
    b = assemble_automaton(parts)
    assert (b.inputs, b.outputs, b.initial, b.goals, b.metadata) == (a.inputs, a.outputs, a.initial, a.goals, a.metadata)
    assert b.states == a.states
    model = ControllerModel.assemble(str(CLEAN_SPEC), ViewOptions(), parts)
    assert model.edge_count() == clean_model.edge_count() and model.predecessors(5) == clean_model.predecessors(5)


def test_state_ids_are_those_of_the_exported_automaton(clean_model, tmp_path):
    from ltl_stack.synthesis.cli import main as synthesize_main

    out = tmp_path / "clean.json"
    assert synthesize_main([str(CLEAN_SPEC), "--robotics-semantics", "--cooperative", "--strategy-json", str(out),
                            "--quiet"]) == 0
    exported = Automaton.load(out)
    assert len(exported) == len(clean_model.automaton)
    for s in exported.states:
        update = StateUpdate(123456, s.goal, s.inputs, s.outputs, True)
        assert clean_model.locate(update) == s.id


def test_states_are_located_by_their_id_while_the_readings_are_in_between(clean_model):
    """The executor publishes its readings, which may be inadmissible for a moment (two regions at once)."""
    from ltl_stack.synthesis.strategy import State

    a = clean_model.automaton
    s = a.states[a.states[a.initial[0]].successors[0]]
    between = {**s.inputs, "topLane_rc": True, "rightLane_rc": True}
    assert clean_model.locate(StateUpdate(s.id, s.goal, between, s.outputs, True)) == s.id  # explicit id
    symbolic = State(dict(s.inputs), dict(s.outputs), s.goal).id
    assert symbolic >= len(a)
    assert clean_model.locate(StateUpdate(symbolic, s.goal, between, s.outputs, True)) == s.id
    paused = {n: False for n in a.outputs}
    assert clean_model.locate(StateUpdate(symbolic, s.goal, between, paused, False)) == s.id
    assert clean_model.locate(StateUpdate(s.id, s.goal, between, paused, False)) == s.id


def test_neighbourhood_of_a_large_automaton(clean_model):
    model = ControllerModel(clean_model.spec_path, clean_model.automaton, ViewOptions(full_limit=10, radius=1))
    assert not model.whole
    center = model.automaton.initial[0]
    shown = model.shown_states(center)
    near = {center, *model.automaton.states[center].successors, *model.predecessors(center)}
    assert center in shown and set(shown) <= near and len(shown) <= 10
    g = model.graph(center)
    assert center in g.key and all(isinstance(k, int) for k in g.key)
    crowded = ControllerModel(clean_model.spec_path, clean_model.automaton, ViewOptions(full_limit=1000))
    assert not crowded.whole  # 64 states but 224 edges: more than a readable picture
    assert len(crowded.graph(center).edges) <= MAX_DRAWN_EDGES
    assert crowded.needs_new_layout(set(), None) and crowded.needs_new_layout({1}, 5)
    assert model.needs_new_layout(set(shown), 10**6) and not model.needs_new_layout(set(shown), center)


def test_before_the_start_and_foreign_states_are_not_located(clean_model):
    a = clean_model.automaton
    s = a.states[0]
    assert clean_model.locate(StateUpdate(-1, -1, s.inputs, s.outputs, True)) is None
    assert clean_model.locate(StateUpdate(5, s.goal, {}, s.outputs, True)) is None
    flipped = {**s.outputs, "pickup": True, "drop": True}
    assert clean_model.locate(StateUpdate(5, s.goal, s.inputs, flipped, True)) is None


def test_mode_and_executor_name():
    assert executor_of("/clean_and_patrol/controller_executor/state") == "/clean_and_patrol/controller_executor"
    u = StateUpdate(3, 0, {}, {}, False)
    assert mode_text(u, "").startswith("paused") and "violated" in mode_text(u, "x")
    waiting = StateUpdate(-1, -1, {}, {}, True)
    assert "waiting" not in mode_text(waiting, "")  # nothing said by the executor: nothing invented


def test_before_the_first_state_the_status_is_the_executors_own():
    """The view says why no state came (it said "waiting for every input to report" while the executor
    said every input had reported and no initial state matched, or that it was paused). The text is the
    executor's /diagnostics."""
    waiting, paused = StateUpdate(-1, -1, {}, {}, True), StateUpdate(-1, -1, {}, {}, False)
    no_init = {"inputs": (0, "every input has reported"),
               "controller": (2, "no initial state: no initial state matches person=1")}
    assert mode_text(waiting, "", no_init) == "executor: no initial state: no initial state matches person=1"
    silent = {"inputs": (1, "waiting for input(s) person, door"), "controller": (0, "waiting for every input to report")}
    assert mode_text(waiting, "", silent) == "executor: waiting for input(s) person, door"
    said_paused = {**silent, "controller": (0, "paused: every output is false")}
    assert mode_text(paused, "", said_paused) == "executor: paused: every output is false"
    assert "waiting" not in mode_text(paused, "", {})
    assert mode_text(StateUpdate(-1, -1, {}, {}, False, mode="aborted"), "", silent).startswith("aborted")


def test_goals_are_numbered_from_1_in_every_display():
    """One state has one goal number in RViz, rqt and controller_trace (it was "goal 3" in some, "goal 2" in others)."""
    from ltl_stack.runtime.runs.map_view import valuation_text
    from ltl_stack.runtime.runs.trace import TraceStep, describe
    from ltl_stack.synthesis.automaton import goal_text

    assert (goal_text(0), goal_text(2, 4), goal_text(-1)) == ("1", "3/4", "-")
    step = TraceStep(time=0.0, state_id=7, goal=2, inputs={}, outputs={}, running=True)
    assert " goal 3 " in describe(None, step) and " goal 3/4 " in describe(None, step, 4)
    assert "goal 3/4" in valuation_text({}, {}, 7, 2, 4) and "goal 3 " in valuation_text({}, {}, 7, 2)
    automaton = ControllerModel.synthesize(SIMPLE_SPEC).automaton
    state = automaton.states[0]
    assert f"{state.id} (goal {state.goal + 1})" in automaton.to_dot()
    model = ControllerModel.indexed(str(SIMPLE_SPEC), automaton, ViewOptions())
    assert f"{state.id} (goal {state.goal + 1})" in model.graph().to_dot()


def test_rviz_text_says_paused_aborted_and_stale_modes():
    """RViz shows a paused executor as paused, not "mode normal"."""
    from ltl_stack.runtime.runs.map_view import valuation_text

    assert "mode paused" in valuation_text({}, {}, 1, 0, None, "normal", running=False)
    assert "mode aborted" in valuation_text({}, {}, 1, 0, None, "aborted", running=False)
    assert "mode stale inputs" in valuation_text({}, {}, 1, 0, None, "stale_inputs")
    assert "mode recovering, paused" in valuation_text({}, {}, 1, 0, None, "recovering", running=False)


def test_latest_hands_over_only_the_newest_value():
    latest = Latest()
    assert latest.take() is None
    done = threading.Event()

    def put_many():
        for i in range(5000):
            latest.put(i)
        done.set()
    t = threading.Thread(target=put_many)
    t.start()
    taken = []
    while not done.is_set():
        v = latest.take()
        if v is not None:
            taken.append(v)
    t.join()
    v = latest.take()
    if v is not None:
        taken.append(v)
    assert taken and taken[-1] == 4999 and taken == sorted(taken)
    assert latest.put_count == 5000 and latest.take() is None


def _comments(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip().startswith("#")]


def test_saving_without_an_edit_writes_the_file_unchanged(tmp_path):
    """Save with no edit keeps expected_feedback: (without it: 36 E1 conflicts) and every comment."""
    out = tmp_path / "m.yaml"
    out.write_text(CLEAN_MAPPING.read_text())
    doc = MappingDocument.load(str(CLEAN_SPEC), str(out))
    doc.save(str(out))
    assert out.read_text() == CLEAN_MAPPING.read_text()
    assert load_mapping(out).expected_feedback == load_mapping(CLEAN_MAPPING).expected_feedback


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["node", "topic", "add"]), st.integers(0, 40),
                          st.sampled_from(["a", "/b/c", "rel_node", "object"])), min_size=1, max_size=8))
def test_any_edit_keeps_every_comment_and_every_key_it_did_not_touch(edits):
    doc = MappingDocument.load(str(CLEAN_SPEC), str(CLEAN_MAPPING))
    keys = sorted(k for k in doc.rows if doc.rows[k])
    for op, k, name in edits:
        kind, prop = keys[k % len(keys)]
        if op == "add" and kind == OUTPUT:
            doc.add_row(prop)
        elif op == "topic":
            doc.set_topic(kind, prop, 0, name)
        else:
            doc.set_node(kind, prop, 0, name)
    text = doc.text()
    original = CLEAN_MAPPING.read_text()
    assert _comments(text) == _comments(original)
    back, before = parse_mapping(text, "x.yaml"), load_mapping(CLEAN_MAPPING)
    assert (back.namespace, back.expected_feedback, back.negotiation) == (
        before.namespace, before.expected_feedback, before.negotiation)
    mine = doc.to_mapping()
    for section, other, old in ((mine.inputs, back.inputs, before.inputs), (mine.outputs, back.outputs, before.outputs)):
        assert {p: [(e.node, e.topic) for e in es] for p, es in section.items()} == \
            {p: [(e.node, e.topic) for e in es] for p, es in other.items()}
        for prop, entries in other.items():  # every key the panel does not edit, as loaded
            loaded = old.get(prop, [])
            for new, was in ((entries[i], loaded[i]) for i in range(min(len(entries), len(loaded)))):
                assert (new.pkg, new.filename, new.parameters, new.type, new.args) == (
                    was.pkg, was.filename, was.parameters, was.type, was.args)


def test_a_file_changed_on_disk_since_it_was_loaded_is_noticed(tmp_path):
    out = tmp_path / "m.yaml"
    out.write_text(CLEAN_MAPPING.read_text())
    doc = MappingDocument.load(str(CLEAN_SPEC), str(out))
    assert not doc.changed_on_disk()
    out.write_text(out.read_text() + "# edited in another editor\n")
    assert doc.changed_on_disk()
    doc.save(str(out))  # the document's own save is the new reference
    assert not doc.changed_on_disk()
    out.unlink()
    assert doc.changed_on_disk()


def _source(path, text, generation=0, started=1.0):
    from ltl_stack.gui.controller_model import ExecutorSource
    from ltl_stack.runtime.executor.running_spec import RunningSpec, spec_digest

    return ExecutorSource(RunningSpec(str(path), spec_digest(text), text, "", generation, True, True, 20000), started)


def test_the_view_draws_the_executors_spec_and_warns_when_the_named_one_differs(tmp_path):
    from ltl_stack.gui.controller_model import source_spec

    running = tmp_path / "running.structuredslugs"
    running.write_text(SIMPLE_SPEC.read_text())
    same = _source(running, SIMPLE_SPEC.read_text())
    assert source_spec(same, str(SIMPLE_SPEC)) == (str(running), "")  # same content: no banner
    other = tmp_path / "other.structuredslugs"
    other.write_text(SIMPLE_SPEC.read_text() + "\n[SYS_LIVENESS]\nmove\n")
    path, banner = source_spec(same, str(other))
    assert path == str(running) and str(running) in banner and str(other) in banner
    # the executor's file is not readable here (another machine) or changed since: its text is drawn
    gone = _source(tmp_path / "elsewhere" / "spec.structuredslugs", SIMPLE_SPEC.read_text())
    path, banner = source_spec(gone, "")
    assert path != gone.spec.spec_file and open(path).read() == SIMPLE_SPEC.read_text() and banner == ""
    running.write_text("changed")
    assert source_spec(same, "")[0] != str(running)
    # a later strategy (characterized, adopted) differs from the named spec by design: no banner
    assert source_spec(_source(other, other.read_text(), generation=2), str(SIMPLE_SPEC))[1] == ""
    nothing = _source("", "", generation=1)
    path, banner = source_spec(nothing, "")
    assert path is None and "cannot read" in banner


def test_liveness_says_why_the_executor_is_not_heard_from():
    from ltl_stack.gui.controller_model import CONNECT_GRACE, STALE_AFTER, liveness

    assert liveness(100.0, 99.0, 90.0, True, True, 0.0) == (True, "last state 10 s ago")
    assert liveness(100.0, 99.0, None, True, True, 0.0) == (True, "no state yet")
    alive, text = liveness(100.0, 99.0, 90.0, False, True, 0.0)
    assert not alive and "no executor publishes" in text
    assert liveness(1.0, 1.0, None, False, True, 1.0 - CONNECT_GRACE / 2)[0]  # just attached: connecting
    alive, text = liveness(100.0, 100.0 - STALE_AFTER - 1, 90.0, True, True, 0.0)
    assert not alive and "nothing from the executor" in text
    alive, text = liveness(100.0, 99.0, 90.0, True, False, 0.0)
    assert not alive and "no ROS master answers" in text


def test_undo_after_a_save_edits_the_right_entries(tmp_path):
    """The rows keep pointing at the loaded file's entries: deleting a node, saving, then taking the
    delete back writes each entry with its own keys again."""
    import copy

    out = tmp_path / "m.yaml"
    out.write_text(CLEAN_MAPPING.read_text())
    doc = MappingDocument.load(str(CLEAN_SPEC), str(out))
    doc.add_row("stop")
    doc.set_node(OUTPUT, "stop", 1, "/brake")
    doc.save(str(out))
    before = copy.deepcopy(doc.rows)
    doc.delete_row(OUTPUT, "stop", 0)
    doc.save(str(out))
    assert [e.node for e in load_mapping(out).outputs["stop"]] == ["/brake"]
    doc.rows = before  # Undo
    doc.save(str(out))
    again, original = load_mapping(out).outputs["stop"], load_mapping(CLEAN_MAPPING).outputs["stop"][0]
    assert [e.node for e in again] == ["stop", "/brake"]
    assert (again[0].pkg, again[0].filename, again[0].parameters) == (original.pkg, original.filename,
                                                                      original.parameters)
    assert again[1].pkg is None and again[1].parameters == {}
