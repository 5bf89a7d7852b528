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
reads OUT back as English; any other combination writes ``.slugsin`` (a user of English specs keeps reading English).

The live snapshot comes from the ``take_live`` callable given to ``main`` (``scripts/analyze_graph``
passes ``ltl_stack.ros.graph_snapshot.take_snapshot``), so this module stays free of ROS.
"""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence

from ltl_stack import cli
from ltl_stack.analysis import report
from ltl_stack.analysis.checks import Analysis
from ltl_stack.analysis.graph import DEFAULT_IGNORED_TOPICS, DEFAULT_MERGERS
from ltl_stack.analysis.snapshot import Snapshot, is_json_path
from ltl_stack.analysis.workflow import (
    MISSING_NODE,
    UNMAPPED,
    Problem,
    apply_suggestions,
    apply_text,
    english_text,
    load_inputs,
    problems,
    run_checks,
)
from ltl_stack.errors import Exit, UserError

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
    spec, mapping, issues = load_inputs(args.spec, args.mapping)
    snapshot = _snapshot(args, take_live)
    generic = None if args.generic_topics is None else args.generic_topics
    analysis, suggestions = run_checks(
        spec, mapping, snapshot, robots=args.robots, ignore_topics=args.ignore_topics,
        generic_topics=[*(DEFAULT_IGNORED_TOPICS if generic is None else generic), *args.add_generic_topics],
        mergers=(*DEFAULT_MERGERS, *args.add_mergers), progress=progress)
    applied = None
    outputs = []
    if args.apply:
        english = english_text(args.spec, args.apply)
        applied, text = apply_suggestions(spec, suggestions, args.apply, args.suggestions, english, progress)
        outputs.append((args.apply, text, "spec"))
    if args.save_snapshot:
        outputs.append((args.save_snapshot, snapshot.to_text(is_json_path(args.save_snapshot)), "snapshot"))
    cli.write_outputs(outputs)  # only now, all or none: an error above leaves no output behind
    for path, _, what in outputs:
        progress(f"{what} written to {path}")
    _print_report(args, analysis, suggestions, issues, problems(analysis, mapping, issues, snapshot), applied)
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


def _print_report(args, analysis: Analysis, suggestions, issues, found: list[Problem], applied: dict | None) -> None:
    if args.json:
        data = report.to_dict(analysis, suggestions, reach=args.reach,
                              extra={"mapping_warnings": [str(i) for i in issues], "apply": applied,
                                     "problems": [{"kind": p.kind, "severity": p.severity, "text": p.text}
                                                  for p in found]})
        print(json.dumps(data, indent=1))
        return
    text = (report.to_markdown(analysis, suggestions) if args.markdown
            else report.to_text(analysis, suggestions, reach=args.reach))
    listed = [p for p in found if p.kind not in (MISSING_NODE, UNMAPPED)]  # the report's Warnings has these
    if listed:  # the analysis panel lists every one of ``found`` (workflow.problems)
        text = "Problems:\n" + "".join(f"  {p}\n" for p in listed) + "\n" + text
    if applied is not None:
        text += "\n" + apply_text(applied)
    sys.stdout.write(text)
