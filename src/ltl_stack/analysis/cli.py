"""``analyze_graph``: conflicts between proposition nodes in a ROS graph, and the spec edits that avoid them.

    rosrun ltl_stack analyze_graph --spec SPEC --mapping MAPPING (--snapshot FILE | --live [--master-uri URI])
        [--save-snapshot FILE] [--robots r1,r2] [--ignore-topics /odom,/imu] [--apply OUT] [--json|--markdown]

Exit codes (``ltl_stack.errors.Exit``): 0 analysis done (findings or not, unless
--fail-on-findings); 1 --fail-on-findings and there are findings; 2 bad input (spec, mapping,
snapshot, option, malformed master URI, an output that is an input); 3 no ROS master for --live;
4 an output could not be written; 10 --apply: the spec with the suggestions added is unrealizable
(the explanation is in the report). Outputs (--apply, --save-snapshot) are checked against the
inputs before any work and written only when everything else has succeeded.

--apply on a Structured English spec (``.spec``/``.english``) with an English OUT appends the
suggestions to the spec's text as English sentences (``a, b and c are mutually exclusive``) and
reads OUT back as English; any other combination writes ``.slugsin`` (issue 15).

The live snapshot comes from the ``take_live`` callable given to ``main`` (``scripts/analyze_graph``
passes ``ltl_stack.ros.graph_snapshot.take_snapshot``), so this module stays free of ROS.
"""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence
from dataclasses import replace

from ltl_stack import cli
from ltl_stack.analysis import report
from ltl_stack.analysis.checks import Analysis, analyze, e2_groups
from ltl_stack.analysis.graph import DEFAULT_IGNORED_TOPICS, DEFAULT_MERGERS, ComputationGraph
from ltl_stack.analysis.snapshot import Snapshot, is_json_path
from ltl_stack.analysis.suggest import (
    MutualExclusion,
    add_to_spec,
    input_exclusion_for,
    mark_guaranteed,
    mutual_exclusions,
)
from ltl_stack.errors import Exit, UserError
from ltl_stack.inputs import read_text
from ltl_stack.runtime.mapping import check_mapping, load_mapping, misfit
from ltl_stack.spec import formula_to_slugsin, load_spec, write_slugsin
from ltl_stack.spec.english_reader import ENGLISH_SUFFIXES, has_section_headers, parse_english
from ltl_stack.spec.english_writer import sentences_for
from ltl_stack.spec.model import SLUGSIN_SECTIONS, Spec
from ltl_stack.synthesis import is_realizable
from ltl_stack.synthesis.explain import explain
from ltl_stack.synthesis.explain_render import explanation_dict, explanation_text

PROG = "analyze_graph"
EXIT_CODES = (Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT, Exit.NO_ROS, Exit.WRITE_FAILED, Exit.UNREALIZABLE)


def _names(text: str) -> list[str]:
    return [t.strip() for t in text.split(",") if t.strip()]


def build_parser() -> cli.ToolParser:
    p = cli.ToolParser(
        PROG,
        "Analyse the ROS computation graph of launched proposition nodes (thesis 3.5.2): "
        "E1 outputs reaching input nodes, E2 outputs reaching the same topic/action, E3 one "
        "output's nodes reaching the same topic, C1/C2 robots left behind; suggest "
        "mutual-exclusion clauses for the spec.",
        exit_codes=EXIT_CODES,
        epilog="1: findings with --fail-on-findings; 10: --apply gave an unrealizable spec. An output "
               "(--apply, --save-snapshot) that names an input is refused before any work.")
    p.add_argument("--spec", required=True, help="the spec (.slugsin or structured)")
    p.add_argument("--mapping", required=True, help="the proposition mapping YAML")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--snapshot", metavar="FILE", help="analyse a saved graph snapshot (YAML or JSON)")
    src.add_argument("--live", action="store_true", help="take a snapshot of the running ROS master")
    p.add_argument("--master-uri", metavar="URI",
                   help="master for --live (default: __master:= or $ROS_MASTER_URI)")
    p.add_argument("--save-snapshot", metavar="FILE", help="also save the snapshot (.json: JSON, else YAML)")
    p.add_argument("--robots", type=_names, default=[], metavar="R1,R2,...",
                   help="homogeneous robots (topic namespaces) for checks C1 and C2")
    p.add_argument("--ignore-topics", type=_names, default=[], metavar="T1,T2,...",
                   help="robot topics to ignore in C1/C2, as suffixes (e.g. /odom,/imu; globs allowed)")
    p.add_argument("--generic-topics", type=_names, default=None, metavar="P1,P2,...",
                   help="replace the generic topics left out of the graph (globs; default: "
                        f"{','.join(DEFAULT_IGNORED_TOPICS)}); give '' for none")
    p.add_argument("--add-generic-topics", type=_names, default=[], metavar="P1,P2,...",
                   help="more generic topics to leave out (e.g. /odom,/joint_states to cut feedback loops)")
    p.add_argument("--add-mergers", type=_names, default=[], metavar="P1,P2,...",
                   help="more nodes that merge commands by design (globs on node names; default: "
                        f"{','.join(DEFAULT_MERGERS)}); E2/E3 follow other relays")
    p.add_argument("--reach", action="store_true",
                   help="also list every proposition node's publish/subscribe-reachable topics and nodes")
    p.add_argument("--apply", metavar="OUT",
                   help="write the spec with the suggestions added to OUT (.slugsin), synthesize it and report")
    p.add_argument("--suggestions", type=_names, default=None, metavar="N1,N2,...",
                   help="with --apply: the numbers of the suggestions to add (default: all)")
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="print the report as JSON on stdout")
    fmt.add_argument("--markdown", action="store_true", help="Markdown report (tables like the thesis figures)")
    p.add_argument("--fail-on-findings", action="store_true", help="exit 1 when there are findings")
    return p


def main(argv: Sequence[str] | None = None, take_live: Callable[..., Snapshot] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.master_uri is not None and not args.live:
        parser.error("--master-uri needs --live")
    if args.suggestions is not None and not args.apply:
        parser.error("--suggestions needs --apply")
    return cli.run(PROG, lambda: run(args, take_live))


def progress(message: str) -> None:
    cli.say(PROG, message)


def run(args: argparse.Namespace, take_live: Callable[..., Snapshot] | None) -> int:
    """The analysis; every user mistake is a ``UserError`` (``cli.run`` prints it and exits with its code)."""
    cli.check_outputs([args.spec, args.mapping, args.snapshot], [args.apply, args.save_snapshot])
    spec = load_spec(args.spec)
    mapping = load_mapping(args.mapping)
    issues = check_mapping(mapping, spec.inputs, spec.outputs)
    error = misfit(issues)
    if error is not None:
        raise error
    snapshot = _snapshot(args, take_live)
    ignored = list(DEFAULT_IGNORED_TOPICS if args.generic_topics is None else args.generic_topics)
    graph = ComputationGraph(snapshot, [*ignored, *args.add_generic_topics])
    progress(f"graph: {len(graph.nodes)} nodes, {len(graph.channels)} topics/actions, {graph.edge_count} edges")
    analysis = analyze(graph, mapping, spec.inputs, spec.outputs, robots=args.robots,
                       robot_topics_to_ignore=args.ignore_topics, progress=progress,
                       mergers=(*DEFAULT_MERGERS, *args.add_mergers))
    suggestions = mark_guaranteed(spec, mutual_exclusions(e2_groups(analysis), spec.outputs))
    applied = None
    outputs = []
    if args.apply:
        english = english_text(args.spec, args.apply)
        applied, text = apply_suggestions(spec, suggestions, args.apply, args.suggestions, english)
        outputs.append((args.apply, text, "spec"))
    if args.save_snapshot:
        outputs.append((args.save_snapshot, snapshot.to_text(is_json_path(args.save_snapshot)), "snapshot"))
    cli.write_outputs(outputs)  # only now, all or none: an error above leaves no output behind
    for path, _, what in outputs:
        progress(f"{what} written to {path}")
    warnings = [str(i) for i in issues]
    _print_report(args, analysis, suggestions, warnings, applied)
    if applied is not None and not applied["realizable"]:
        return Exit.UNREALIZABLE
    if args.fail_on_findings and analysis.finding_count:
        return Exit.NEGATIVE
    return Exit.OK


def _snapshot(args: argparse.Namespace, take_live: Callable[..., Snapshot] | None) -> Snapshot:
    if args.snapshot:
        return Snapshot.load(args.snapshot)
    if take_live is None:
        raise UserError("--live needs ROS (ltl_stack.ros.graph_snapshot); run it through rosrun ltl_stack "
                        "analyze_graph", Exit.NO_ROS)
    progress("taking a snapshot of the ROS master")
    return take_live(args.master_uri)


def english_text(spec_path: str, out: str) -> str | None:
    """The text of ``spec_path`` when it is Structured English and ``out`` is an English file too
    (``--apply`` then appends sentences), else None (``--apply`` writes .slugsin)."""
    english = tuple(s.lower() for s in ENGLISH_SUFFIXES)
    if not (spec_path.lower().endswith(english) and out.lower().endswith(english)):
        return None
    text = read_text(spec_path, "spec file")
    return None if has_section_headers(text) else text


def apply_suggestions(spec: Spec, suggestions: list[MutualExclusion], out: str,
                      chosen: list[str] | None, english: str | None = None) -> tuple[dict, str]:
    """``spec`` plus the chosen suggestions, as the text to write to ``out``, synthesized; explained
    when unrealizable. Returns (the report's ``apply`` entry, the text); writes nothing.

    With ``english`` (the text of a Structured English spec) the suggestions are appended to it as
    English sentences and the result is read back as English (its clauses then point at OUT's
    lines); else the text is ``.slugsin``. When the result is unrealizable, also try the assumption
    that the inputs driving the excluded outputs are mutually exclusive (thesis Example 9) and say
    whether it helps.
    """
    picked = _pick(suggestions, chosen)
    chosen_suggestions = [suggestions[i - 1] for i in picked]
    result: dict = {"output": out, "added": picked, "robotics_semantics": True,
                    "format": "english" if english is not None else "slugsin"}
    if english is not None:
        sentences = [sentence for s in chosen_suggestions for sentence in english_sentences(spec, s)]
        text = english + ("" if not english or english.endswith("\n") else "\n")
        if sentences:
            text += "# added by analyze_graph (ROS graph analysis, thesis 3.5.2.3)\n" + "".join(
                s + "\n" for s in sentences)
        new_spec = parse_english(text, out)  # as loading OUT will read it
        result["sentences"] = sentences
    else:
        new_spec = add_to_spec(spec, chosen_suggestions, file=out)
        new_spec.source = out
        text = write_slugsin(new_spec)
        text += "" if text.endswith("\n") else "\n"
        new_spec = _with_written_lines(new_spec, text, out)
    progress(f"spec with suggestion(s) {', '.join(map(str, picked)) or 'none'} for {out}; synthesizing")
    result["realizable_before"] = is_realizable(spec, robotics_semantics=True)
    result["realizable"] = is_realizable(new_spec, robotics_semantics=True)
    if result["realizable"]:
        return result, text
    progress("unrealizable: explaining")
    explanation = explain(new_spec, robotics_semantics=True)
    result["explanation"] = explanation_dict(explanation)
    result["explanation_text"] = explanation_text(explanation)
    outputs = [p for i in picked for p in suggestions[i - 1].propositions]
    assumption = input_exclusion_for(new_spec, outputs)
    if assumption is not None:
        fixed = add_to_spec(new_spec, [assumption], file=out)
        result["input_assumption"] = {**assumption.to_dict(), **report.suggestion_forms(assumption),
                                      "restores_realizability": is_realizable(fixed, robotics_semantics=True)}
        if english is not None:
            result["input_assumption"]["sentences"] = english_sentences(new_spec, assumption)
    return result, text


def english_sentences(spec: Spec, suggestion: MutualExclusion) -> list[str]:
    """A suggestion as Structured English sentences of ``spec``'s language (``english_writer``):
    ``a, b and c are mutually exclusive``, ``Assume x, y and z are mutually exclusive``."""
    return sentences_for(spec, list(suggestion.clauses().items()))


def _with_written_lines(spec: Spec, text: str, out: str) -> Spec:
    """The added clauses (``file == out``) get the line numbers they have in the written text."""
    lines = text.split("\n")
    for section, header in SLUGSIN_SECTIONS.items():
        if f"[{header}]" not in lines:
            continue
        first = lines.index(f"[{header}]") + 1  # 0-based index of the section's first clause
        clauses = []
        for k, clause in enumerate(spec.section(section)):
            at = first + k
            if clause.file == out and at < len(lines) and lines[at] == formula_to_slugsin(clause.formula):
                clause = replace(clause, line=at + 1)
            clauses.append(clause)
        spec = spec.with_section(section, clauses)
    return spec


def _pick(suggestions: list[MutualExclusion], chosen: list[str] | None) -> list[int]:
    if chosen is None:
        return list(range(1, len(suggestions) + 1))
    picked = []
    for token in chosen:
        if not token.isdigit() or not 1 <= int(token) <= len(suggestions):
            raise UserError(f"--suggestions: {token!r} is not a suggestion number (there are {len(suggestions)})")
        picked.append(int(token))
    return picked


def _print_report(args, analysis: Analysis, suggestions, warnings: list[str], applied: dict | None) -> None:
    if args.json:
        data = report.to_dict(analysis, suggestions, reach=args.reach,
                              extra={"mapping_warnings": warnings, "apply": applied})
        print(json.dumps(data, indent=1))
        return
    text = (report.to_markdown(analysis, suggestions) if args.markdown
            else report.to_text(analysis, suggestions, reach=args.reach))
    if warnings:
        text = "Mapping warnings:\n" + "".join(f"  {w}\n" for w in warnings) + "\n" + text
    if applied is not None:
        text += "\n" + apply_text(applied)
    sys.stdout.write(text)


def apply_text(applied: dict) -> str:
    out = [f"--apply: wrote {applied['output']} with suggestion(s) {', '.join(map(str, applied['added'])) or 'none'}."]
    if applied.get("sentences"):
        out.append("Sentences appended:")
        out += [f"  {s}" for s in applied["sentences"]]
    before = "realizable" if applied["realizable_before"] else "unrealizable"
    if applied["realizable"]:
        out.append(f"The new spec is realizable (robotics init semantics; the original was {before}).")
        return "\n".join(out) + "\n"
    out.append(f"The new spec is UNREALIZABLE (robotics init semantics; the original was {before}).")
    out.append("Explanation from the synthesis engine:")
    out += ["  " + line for line in applied["explanation_text"].rstrip("\n").split("\n")]
    hint = applied.get("input_assumption")
    if hint:
        names = ", ".join(hint["propositions"])
        if hint["restores_realizability"]:
            out.append(f"The excluded outputs are driven by the inputs {names}. Assuming the environment never "
                       "makes two of them true at once makes the spec realizable again (thesis Example 9):")
        else:
            out.append(f"The excluded outputs are driven by the inputs {names}; assuming they are mutually "
                       "exclusive is NOT enough on its own to make the spec realizable:")
        for sentence in hint.get("sentences", []):
            out.append(f"  Sentence to add: {sentence}")
        out.append(f"  Structured English: {hint['english_expanded']}")
        for section, line in hint["slugsin"].items():
            out.append(f"  .slugsin [{section}]: {line}")
    return "\n".join(out) + "\n"
