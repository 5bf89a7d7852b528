"""analyze_graph on saved snapshots: reports, exit codes, errors, --apply with real synthesis."""
from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest
from analysis_data import DATA, scenarios
from helpers import require_shared

from ltl_stack.analysis.cli import main
from ltl_stack.errors import Exit
from ltl_stack.spec import load_spec
from ltl_stack.spec.formula import evaluate

ROBOTS = "sphero_wpw,sphero_ggw,sphero_rgw,sphero_wpp"


@pytest.fixture(scope="module")
def snapshots(tmp_path_factory):
    folder = tmp_path_factory.mktemp("snapshots")
    scenarios.scenario_snapshot(DATA / "clean_and_patrol.yaml").save(folder / "clean_and_patrol.yaml")
    scenarios.scenario_snapshot(DATA / "spheros.yaml").save(folder / "spheros.json")
    return folder


def clean_and_patrol_args(snapshots):
    spec = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.slugsin")
    mapping = spec.with_suffix(".yaml")
    return ["--spec", str(spec), "--mapping", str(mapping), "--snapshot", str(snapshots / "clean_and_patrol.yaml")]


def driver_types(robots) -> dict[str, str]:
    """A sphero driver's topics with their real types: velocity and colour in, odometry out (with one
    type for everything the driver would look like a relay, which forwards what it reads)."""
    return {f"/{r}/{t}": ty for r in robots for t, ty in (("cmd_vel", "geometry_msgs/Twist"),
                                                            ("set_color", "std_msgs/ColorRGBA"),
                                                            ("odom", "nav_msgs/Odometry"))}


def spheros_args(snapshots):
    spec = require_shared("specs", "spheros", "spheros.slugsin")
    return ["--spec", str(spec), "--mapping", str(DATA / "spheros_mapping.yaml"),
            "--snapshot", str(snapshots / "spheros.json")]


def test_text_report_shows_findings_chains_and_suggestions(snapshots, capsys):
    assert main(clean_and_patrol_args(snapshots)) == Exit.OK
    out = capsys.readouterr().out
    assert "E1  Output propositions publishing to input proposition nodes (thesis 3.5.2.2): none" in out
    feedback = out[out.index("Expected feedback, not findings"):out.index("Suggested additions")]
    assert feedback.splitlines()[1:] == [  # Fig. 3.6, apart from the findings
        "  pickup -> pickup_ac: pickup_ac reports the completion of the action pickup",
        "    (/pickup) -> [/move_group_and_move_base/outputs/pickup_status] -> (/pickup_ac)",
        "  drop -> drop_ac: drop_ac reports the completion of the action drop",
        "    (/drop) -> [/move_group_and_move_base/outputs/drop_status] -> (/drop_ac)", ""]
    assert out.endswith("7 finding(s). 2 expected feedback pair(s), not counted.\n")
    assert "E2  Output propositions publishing to the same topic or action (thesis 3.5.2.3): 7" in out
    assert "2. pickup and drop are mutually exclusive" in out
    assert "    the same outputs also compete on: [/joint_states], " \
           "(arm_1/arm_controller/follow_joint_trajectory/action_topics), (move_group/action_topics)" in out
    assert out.count("[/odom]") == 1, "channels with the same competing outputs are listed once"
    assert ".slugsin [SYS_TRANS]: | & pickup' ! drop' | & ! pickup' drop' & ! pickup' ! drop'" in out
    assert "In words: always ((pickup and not drop) or (not pickup and drop) or (not pickup and not drop))" in out


def test_json_report_for_tools(snapshots, capsys):
    assert main([*spheros_args(snapshots), "--robots", ROBOTS + ",sphero_wrb",
                 "--ignore-topics", "/collision,/diagnostics,/imu,/odom", "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    assert [(f["output"], f["suffix"], f["missing"]) for f in data["C1"]] == [("move_down", "/cmd_vel", ["sphero_wpw"])]
    assert [f["robot"] for f in data["C2"]] == ["sphero_wrb"]
    assert [(s["propositions"], s["slugsin"]["SYS_TRANS"]) for s in data["suggestions"]] == [
        (["move_left", "move_down"], "| & move_left' ! move_down' | & ! move_left' move_down' & ! move_left' ! move_down'")]
    assert data["apply"] is None and data["finding_count"] == len(data["E2"]) + 2
    assert data["graph"]["services"]["/sphero_ggw/driver/get_loggers"] == ["/sphero_ggw/driver"], \
        "services are listed (not analysed)"


def test_markdown_report_has_thesis_like_tables(snapshots, capsys):
    assert main([*clean_and_patrol_args(snapshots), "--markdown"]) == Exit.OK
    out = capsys.readouterr().out
    assert "| Output | Input | Why | Output-to-input chain |" in out  # Fig. 3.6, as expected feedback
    assert "7 finding(s). 2 expected feedback pair(s), not counted." in out
    assert "| /cmd_vel | pickup | `(/pickup) -> [/cmd_vel]` |" in out


def test_reach_listing(snapshots, capsys):
    assert main([*clean_and_patrol_args(snapshots), "--reach"]) == Exit.OK
    out = capsys.readouterr().out
    assert "pickup /pickup publish-reachable:" in out
    assert "    /move_group: (/pickup) -> (move_group/action_topics) -> (/move_group)" in out


def test_expected_feedback_alone_is_no_finding(snapshots, tmp_path, capsys):
    # only the completion nodes of clean and patrol: Fig. 3.6's pairs and nothing else
    snapshot = scenarios.scenario_snapshot(DATA / "clean_and_patrol.yaml")
    keep = {"/pickup", "/drop", "/pickup_ac", "/drop_ac"}
    for name in list(snapshot.topics):
        if not name.endswith(("pickup_status", "drop_status")):
            del snapshot.topics[name]
    snapshot.nodes[:] = [n for n in snapshot.nodes if n in keep]
    snapshot.save(tmp_path / "completions.json")
    args = [*clean_and_patrol_args(snapshots)[:4], "--snapshot", str(tmp_path / "completions.json")]
    assert main([*args, "--fail-on-findings", "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    assert data["E1"] == [] and data["finding_count"] == 0
    assert [(f["output"], f["input"], f["expected"], f["chains"][0]["chain"]) for f in data["expected_feedback"]] == [
        ("pickup", "pickup_ac", "action completion",
         "(/pickup) -> [/move_group_and_move_base/outputs/pickup_status] -> (/pickup_ac)"),
        ("drop", "drop_ac", "action completion",
         "(/drop) -> [/move_group_and_move_base/outputs/drop_status] -> (/drop_ac)")]
    assert main([*args, "--markdown"]) == Exit.OK
    out = capsys.readouterr().out
    assert "| pickup | pickup_ac | pickup_ac reports the completion of the action pickup | " in out
    assert "## E1: Output propositions publishing to input proposition nodes (thesis 3.5.2.2)\n\nNone." in out


def test_fail_on_findings_and_generic_topic_options(snapshots, capsys):
    assert main([*clean_and_patrol_args(snapshots), "--fail-on-findings"]) == Exit.NEGATIVE
    capsys.readouterr()
    assert main([*clean_and_patrol_args(snapshots), "--generic-topics", "", "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    assert data["graph"]["ignored_topics"] == [] and "/tf" in {g["topic"] for g in data["E2"]}, \
        "without the generic list /tf becomes a (false) conflict"
    assert main([*clean_and_patrol_args(snapshots), "--add-generic-topics", "/cmd_vel", "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    assert "/cmd_vel" in data["graph"]["ignored_topics"] and "/cmd_vel" not in {g["topic"] for g in data["E2"]}


def test_save_snapshot(snapshots, tmp_path, capsys):
    out = tmp_path / "copy.json"
    assert main([*clean_and_patrol_args(snapshots), "--save-snapshot", str(out)]) == Exit.OK
    assert json.loads(out.read_text())["format"] == "ltl_stack/graph_snapshot/1"


@pytest.mark.parametrize("case", ["spec", "mapping", "snapshot", "live", "suggestion", "output is input"])
def test_bad_input_is_one_line_and_exit_2(snapshots, tmp_path, capsys, case):
    args = clean_and_patrol_args(snapshots)
    code = Exit.BAD_INPUT
    if case == "spec":
        bad = tmp_path / "bad.slugsin"
        bad.write_text("[INPUT]\na\n[SYS_TRANS]\n& a\n")
        args[1] = str(bad)
        expect = str(bad)
    elif case == "mapping":
        bad = tmp_path / "bad.yaml"
        bad.write_text("outputs:\n  nosuch:\n    node: /x\n")
        args[3] = str(bad)
        expect = f"{bad}:2: output 'nosuch' is not a proposition of the spec"
    elif case == "snapshot":
        bad = tmp_path / "bad_snap.yaml"
        bad.write_text("topics: 3\n")
        args[5] = str(bad)
        expect = "'topics' must be a mapping"
    elif case == "live":
        args = [*args[:4], "--live"]
        expect = "--live needs ROS"
        code = Exit.NO_ROS
    elif case == "suggestion":
        args += ["--apply", str(tmp_path / "o.slugsin"), "--suggestions", "7"]
        expect = "--suggestions: '7' is not a suggestion number (there are 2)"
    else:
        args += ["--apply", str(tmp_path / "o.slugsin"), "--save-snapshot", args[1]]
        expect = f"{args[1]}: output would overwrite the input"
    before = {p: p.read_bytes() for p in map(Path, args[1:6:2])}
    assert main(args) == code
    captured = capsys.readouterr()
    assert captured.out == ""
    errors = [line for line in captured.err.splitlines() if "error:" in line]
    assert len(errors) == 1 and errors[0].startswith("analyze_graph: error: ") and expect in errors[0], captured.err
    assert errors[0].count("error:") == 1, errors  # it once said "error:" twice
    assert "Traceback" not in captured.err
    assert not (tmp_path / "o.slugsin").exists()
    assert {p: p.read_bytes() for p in before} == before


def test_apply_realizable_writes_the_spec_with_the_clauses(snapshots, tmp_path, capsys):
    out = tmp_path / "patched.slugsin"
    assert main([*clean_and_patrol_args(snapshots), "--apply", str(out), "--suggestions", "2"]) == Exit.OK
    text = capsys.readouterr().out
    assert f"--apply: wrote {out} with suggestion(s) 2." in text
    assert "The new spec is realizable" in text
    spec = load_spec(out)
    original = load_spec(clean_and_patrol_args(snapshots)[1])
    assert len(spec.sys_safety) == len(original.sys_safety) + 1
    assert len(spec.sys_init) == len(original.sys_init) + 1
    for pickup, drop in itertools.product([False, True], repeat=2):
        assert evaluate(spec.sys_safety[-1].formula, {}, {"pickup": pickup, "drop": drop}) == (not (pickup and drop))
        assert evaluate(spec.sys_init[-1].formula, {"pickup": pickup, "drop": drop}) == (not (pickup and drop))


def test_apply_unrealizable_explains_and_leads_to_input_exclusion(snapshots, tmp_path, capsys):
    out = tmp_path / "spheros_patched.slugsin"
    assert main([*spheros_args(snapshots), "--apply", str(out)]) == Exit.UNREALIZABLE
    text = capsys.readouterr().out
    assert "The new spec is UNREALIZABLE" in text
    assert "Explanation from the synthesis engine:" in text
    assert "The excluded outputs are driven by the inputs left_arrow, down_arrow. Assuming the environment " \
           "never makes two of them true at once makes the spec realizable again" in text
    assert "[ENV_TRANS]: | & left_arrow' ! down_arrow' | & ! left_arrow' down_arrow' & ! left_arrow' ! down_arrow'" in text
    assert out.exists(), "the spec is written even when unrealizable, for the user to edit"


def test_apply_json(snapshots, tmp_path, capsys):
    out = tmp_path / "o.slugsin"
    assert main([*spheros_args(snapshots), "--apply", str(out), "--json"]) == Exit.UNREALIZABLE
    applied = json.loads(capsys.readouterr().out)["apply"]
    assert (applied["realizable_before"], applied["realizable"]) == (True, False)
    assert applied["explanation"]["kind"] == "deadlock"
    assert applied["input_assumption"]["propositions"] == ["left_arrow", "down_arrow"]
    assert applied["input_assumption"]["restores_realizability"] is True


def test_thesis_example_9_on_the_shared_sphero_mapping(tmp_path, capsys):
    """All four spheros as the shared mapping has them: move_* and turn_* groups (Fig. 3.13); making
    them exclusive is unrealizable until the arrow/stop inputs are assumed exclusive."""
    import yaml

    mapping_path = require_shared("specs", "spheros", "spheros.yaml")
    mapping = yaml.safe_load(mapping_path.read_text())
    nodes = {}
    for entries in mapping["outputs"].values():
        for e in entries:
            nodes[e["node"]] = {"sub": [e["node_subscribe_topic"]], "pub": [e["parameters"]["publish_topic"]]}
    for robot in {e["parameters"]["publish_topic"].split("/")[1] for es in mapping["outputs"].values() for e in es}:
        nodes[f"/{robot}/driver"] = {"sub": [f"/{robot}/cmd_vel", f"/{robot}/set_color"], "pub": [f"/{robot}/odom"]}
    snapshot = tmp_path / "spheros.json"
    robots = [name.split("/")[1] for name in nodes if name.endswith("/driver")]
    scenarios.snapshot_of({"nodes": nodes, "topic_types": driver_types(robots)}).save(snapshot)
    out = tmp_path / "spheros_exclusive.slugsin"
    args = ["--spec", str(mapping_path.with_suffix(".slugsin")), "--mapping", str(mapping_path),
            "--snapshot", str(snapshot), "--apply", str(out), "--json"]
    assert main(args) == Exit.UNREALIZABLE
    data = json.loads(capsys.readouterr().out)
    assert sorted(tuple(s["propositions"]) for s in data["suggestions"]) == [
        ("move_left", "move_right", "move_up", "move_down", "stop"),
        ("turn_red", "turn_yellow", "turn_green", "turn_blue", "turn_purple", "turn_white")]
    hint = data["apply"]["input_assumption"]
    assert hint["propositions"] == ["left_arrow", "right_arrow", "up_arrow", "down_arrow", "stop_sign"]
    assert hint["restores_realizability"] is True
    lines = out.read_text().split("\n")
    added = [c for c in data["apply"]["explanation"]["core"] if c.get("file") == str(out)]
    assert added, data["apply"]["explanation"]["core"]
    for clause in added:
        assert clause["line"] > 0 and lines[clause["line"] - 1].startswith("| & move_left'"), clause


# --- --apply on a Structured English spec appends English sentences --------------------

ENGLISH = Path(__file__).resolve().parents[2] / "data" / "english"
SPEC3_MOVES = ["moveLeft", "moveRight", "moveUp", "moveDown", "stop"]
SPEC3_TURNS = ["turnPurple", "turnBlue", "turnGreen", "turnYellow", "turnRed", "turnWhite"]
SPEC3_ROBOTS = ["sphero_wpw", "sphero_ggw", "sphero_rgw", "sphero_wpp"]


def spec3_setup(folder: Path) -> list[str]:
    """Thesis Spec. 3 as printed (English) over four spheros: one node per output and robot, a
    driver per robot taking velocity and colour (Example 9, Fig. 3.13)."""
    nodes, outputs = {}, {}
    for prop in SPEC3_MOVES + SPEC3_TURNS:
        outputs[prop] = [f"/spheros/outputs/{r}/{prop}" for r in SPEC3_ROBOTS]
        topic = "cmd_vel" if prop in SPEC3_MOVES else "set_color"
        for r in SPEC3_ROBOTS:
            nodes[f"/spheros/outputs/{r}/{prop}"] = {"sub": [f"/t/outputs/{prop}"], "pub": [f"/{r}/{topic}"]}
    for r in SPEC3_ROBOTS:
        nodes[f"/{r}/driver"] = {"sub": [f"/{r}/cmd_vel", f"/{r}/set_color"], "pub": [f"/{r}/odom"]}
    scenarios.snapshot_of({"nodes": nodes, "topic_types": driver_types(SPEC3_ROBOTS)}).save(folder / "spheros.json")
    lines = ["outputs:"]
    for prop, ns in outputs.items():
        lines += [f"  {prop}:", *(f"    - {{node: '{n}', node_subscribe_topic: '/t/outputs/{prop}'}}" for n in ns)]
    (folder / "spheros.yaml").write_text("\n".join(lines) + "\n")
    return ["--spec", str(ENGLISH / "thesis_spec3.spec"), "--mapping", str(folder / "spheros.yaml"),
            "--snapshot", str(folder / "spheros.json")]


def test_apply_on_english_spec3_appends_sentences_and_names_the_assumption(tmp_path, capsys):
    from ltl_stack.spec.english_files import append_sentences
    from ltl_stack.synthesis import is_realizable

    args = spec3_setup(tmp_path)
    assert main([*args, "--json"]) == Exit.OK
    suggestions = json.loads(capsys.readouterr().out)["suggestions"]
    assert [s["propositions"] for s in suggestions] == [SPEC3_TURNS, SPEC3_MOVES]  # Fig. 3.13
    out = tmp_path / "spec3_exclusive.spec"
    # Example 9: the move outputs exclusive -> unrealizable
    assert main([*args, "--apply", str(out), "--suggestions", "2"]) == Exit.UNREALIZABLE
    report = capsys.readouterr().out
    original = (ENGLISH / "thesis_spec3.spec").read_text()
    text = out.read_text()
    assert text.startswith(original), "the user's sentences stay as they are"
    assert text[len(original):].splitlines() == [
        "# added by analyze_graph (ROS graph analysis, thesis 3.5.2.3)",
        "moveLeft, moveRight, moveUp, moveDown and stop are mutually exclusive"]
    assert "Sentences appended:\n  moveLeft, moveRight, moveUp, moveDown and stop are mutually exclusive\n" in report
    sentence = "Assume leftSignal, rightSignal, forwardSignal, backwardSignal and stopSignal are mutually exclusive"
    assert f"  Sentence to add: {sentence}\n" in report
    spec = load_spec(out)
    added = [c for c in spec.sys_safety if c.line == len(text.splitlines())]
    assert added and all(c.file == str(out) for c in added), "the clauses point at the appended sentence"
    assert not is_realizable(spec, robotics_semantics=True)
    # ... then the *Signal inputs assumed exclusive, as the report says -> realizable
    append_sentences(out, [sentence])
    assert is_realizable(load_spec(out), robotics_semantics=True)


def test_apply_on_english_spec_realizable_and_json(tmp_path, capsys):
    folder = tmp_path / "spec"
    folder.mkdir()
    config = Path(__file__).resolve().parents[3] / "config" / "clean_and_patrol"
    for name in ("clean_and_patrol.spec", "clean_and_patrol.regions"):  # the spec's Map: is beside it
        (folder / name).write_text((config / name).read_text())
    snapshot = tmp_path / "graph.yaml"
    scenarios.scenario_snapshot(DATA / "clean_and_patrol.yaml").save(snapshot)
    mapping = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.yaml")
    out = folder / "with_suggestions.spec"
    assert main(["--spec", str(folder / "clean_and_patrol.spec"), "--mapping", str(mapping), "--snapshot",
                 str(snapshot), "--apply", str(out), "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    applied = data["apply"]
    assert (applied["format"], applied["realizable"]) == ("english", True)
    # our Spec. 2 already keeps the regions, stop and pickup apart, and pickup and drop
    assert [s["already_in_spec"] for s in data["suggestions"]] == [True, True]
    assert applied["sentences"] == [
        "stop, pickup, topLane, bottomLane, leftLane, rightLane, leftGround and rightGround are mutually exclusive",
        "pickup and drop are mutually exclusive"]
    assert out.read_text().splitlines()[-2:] == applied["sentences"]
    spec = load_spec(out)
    assert sorted(spec.outputs) == sorted(load_spec(folder / "clean_and_patrol.spec").outputs)
    # an English spec with a .slugsin OUT gets the .slugsin text, as before
    out2 = folder / "with_suggestions.slugsin"
    assert main(["--spec", str(folder / "clean_and_patrol.spec"), "--mapping", str(mapping), "--snapshot",
                 str(snapshot), "--apply", str(out2), "--json", "--suggestions", "2"]) == Exit.OK
    assert json.loads(capsys.readouterr().out)["apply"]["format"] == "slugsin"
    assert out2.read_text().startswith("[INPUT]")


def test_fig_3_9_mapping_as_the_thesis_gui_writes_it_is_analysed(snapshots, tmp_path, capsys):
    """Fig. 3.9: the 'drop node' also mapped to pickup, written as a second 'pickup:' block."""
    args = clean_and_patrol_args(snapshots)
    shared = Path(args[3]).read_text()
    second = ("  pickup:\n    node : '/drop'\n    node_subscribe_topic : '/move_group_and_move_base/outputs/pickup'\n"
              "    pkg : 'controller_executor'\n    filename : 'plan_manipulator_path.py'\n\n")
    mapping = tmp_path / "fig_3_9.yaml"
    mapping.write_text(shared.replace("  drop:\n", second + "  drop:\n", 1))
    args[3] = str(mapping)
    assert main([*args, "--json"]) == Exit.OK
    data = json.loads(capsys.readouterr().out)
    e3 = {(f["output"], f["topic"]): f["nodes"] for f in data["E3"]}
    assert e3[("pickup", "/arm_1/gripper_controller/position_command")] == ["/pickup", "/drop"], e3
