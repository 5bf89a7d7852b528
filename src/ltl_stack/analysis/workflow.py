"""One run of the graph analysis as ``analyze_graph`` and the analysis panel both do it (thesis §3.5.2).

``load_inputs`` reads the spec and the mapping and refuses a mapping that does not fit the spec;
``run_checks`` runs E1–E3/C1–C2 on a snapshot and makes the suggestions (§3.5.2.3); ``problems`` lists
what makes the analysis incomplete or the graph wrong for the spec (mapping warnings, mapped nodes
not in the graph, propositions without a node, input topics with several publishers, §3.5.1), the
same lines the CLI prints and the panel lists; ``apply_suggestions`` writes the spec with the chosen
suggestions, synthesizes it and explains an unrealizable result with the input-exclusion hint of
thesis Example 9 (``analyze_graph --apply`` and the panel's Apply and check). No ROS, no Qt.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from ltl_stack.analysis import report
from ltl_stack.analysis.checks import Analysis, analyze, e2_groups
from ltl_stack.analysis.graph import DEFAULT_IGNORED_TOPICS, DEFAULT_MERGERS, ComputationGraph
from ltl_stack.analysis.graph_checks.p1_input_publishers import CHECK as P1
from ltl_stack.analysis.snapshot import Snapshot
from ltl_stack.analysis.suggest import (
    MutualExclusion,
    add_to_spec,
    input_exclusion_for,
    mark_guaranteed,
    mutual_exclusions,
)
from ltl_stack.errors import UserError
from ltl_stack.inputs import read_text
from ltl_stack.runtime.config.mapping import (
    INPUT,
    OUTPUT,
    Mapping,
    MappingIssue,
    check_mapping,
    load_mapping,
    misfit,
    resolve_topics,
)
from ltl_stack.spec import formula_to_slugsin, load_spec, write_slugsin
from ltl_stack.spec.english_files import parse_english
from ltl_stack.spec.model import SLUGSIN_SECTIONS, Spec
from ltl_stack.spec.structured_english import ENGLISH_SUFFIXES, has_section_headers
from ltl_stack.spec.structured_english.writer import sentences_for
from ltl_stack.synthesis import is_realizable
from ltl_stack.synthesis.explain import explain
from ltl_stack.synthesis.explain_render import explanation_dict, explanation_text

MAPPING, MISSING_NODE, UNMAPPED, PUBLISHERS = "mapping", "missing node", "unmapped", "several publishers"
TOPIC_TYPE = "topic type"
#: the type of every proposition topic: the executor subscribes and publishes std_msgs/Bool
PROPOSITION_TYPE = "std_msgs/Bool"


@dataclass(frozen=True)
class Problem:
    """Something the user must know before trusting the findings; ``text`` is the line shown."""

    kind: str  # MAPPING, MISSING_NODE, UNMAPPED, PUBLISHERS or TOPIC_TYPE
    severity: str  # "error" or "warning"
    text: str
    proposition: str = ""

    def __str__(self) -> str:
        return self.text


def load_inputs(spec_path: str, mapping_path: str) -> tuple[Spec, Mapping, list[MappingIssue]]:
    """The spec, the mapping and ``check_mapping``'s warnings. A mapping error is a ``UserError``
    naming the first one (and how many more), so nothing is analysed on a wrong mapping."""
    spec = load_spec(spec_path)
    mapping = load_mapping(mapping_path)
    issues = check_mapping(mapping, spec.inputs, spec.outputs)
    error = misfit(issues)
    if error is not None:
        raise error
    return spec, mapping, issues


def run_checks(spec: Spec, mapping: Mapping, snapshot: Snapshot, *, robots: Sequence[str] = (),
               ignore_topics: Sequence[str] = (), generic_topics: Sequence[str] | None = None,
               mergers: Sequence[str] = DEFAULT_MERGERS,
               progress: Callable[[str], None] | None = None) -> tuple[Analysis, list[MutualExclusion]]:
    """The checks on ``snapshot``'s graph (generic topics left out: ``DEFAULT_IGNORED_TOPICS`` unless
    given; relays are followed unless their name matches ``mergers``) and the mutual exclusions they
    suggest, marked when the spec already guarantees them."""
    say = progress or (lambda _text: None)
    ignored = list(DEFAULT_IGNORED_TOPICS if generic_topics is None else generic_topics)
    graph = ComputationGraph(snapshot, ignored)
    say(f"graph: {len(graph.nodes)} nodes, {len(graph.channels)} topics/actions, {graph.edge_count} edges")
    analysis = analyze(graph, mapping, spec.inputs, spec.outputs, robots=list(robots),
                       robot_topics_to_ignore=list(ignore_topics), progress=say, mergers=tuple(mergers))
    return analysis, mark_guaranteed(spec, mutual_exclusions(e2_groups(analysis), spec.outputs))


def problems(analysis: Analysis, mapping: Mapping, issues: Sequence[MappingIssue],
             snapshot: Snapshot) -> list[Problem]:
    """Every reason the findings may be incomplete or the run wrong: ``check_mapping``'s warnings, mapped
    nodes not in the graph, propositions with no node, input topics that another node publishes
    too (an input topic has exactly one publisher, thesis §3.5.1), and proposition topics whose type
    on the graph is not ``std_msgs/Bool`` (the executor could not read or drive them)."""
    found = [Problem(MAPPING, i.severity, str(i), i.proposition) for i in issues]
    for m in analysis.missing:
        found.append(Problem(MISSING_NODE, "warning", f"{m.kind} {m.proposition}: node {m.node} (mapping line "
                             f"{m.line}) is not in the graph (not launched, or a typo in the mapping)",
                             m.proposition))
    if analysis.unmapped:
        found.append(Problem(UNMAPPED, "warning", f"not mapped to any node (left out): {', '.join(analysis.unmapped)}"))
    for f in analysis.p1:  # P1 (thesis 3.5.1): the same finding the report lists, as a problem to fix first
        found.append(Problem(PUBLISHERS, P1.severity, f"{INPUT} {f.input}: topic {f.topic} is also published by "
                             f"{', '.join(f.others)}; an input topic takes exactly one node (thesis 3.5.1)", f.input))
    found += wrong_types(analysis, mapping, snapshot)
    return found


def wrong_types(analysis: Analysis, mapping: Mapping, snapshot: Snapshot) -> list[Problem]:
    """Mapped proposition topics the graph carries with another type than ``PROPOSITION_TYPE``: the
    executor's subscriber (input) or publisher (output) would never connect to them."""
    in_topics, out_topics = resolve_topics(mapping, analysis.inputs, analysis.outputs, analysis.namespace)
    found = []
    for kind, topics in ((INPUT, {p: [t] for p, t in in_topics.items()}), (OUTPUT, out_topics)):
        for prop, names in topics.items():
            if prop in analysis.unmapped:
                continue
            for topic in names:
                known = snapshot.topics.get(topic)
                if known is not None and known.type and known.type != PROPOSITION_TYPE:
                    found.append(Problem(TOPIC_TYPE, "error", f"{kind} {prop}: topic {topic} has type {known.type} "
                                         f"on the graph; a proposition topic must be {PROPOSITION_TYPE}", prop))
    return found


def english_text(spec_path: str, out: str) -> str | None:
    """The text of ``spec_path`` when it is Structured English and ``out`` is an English file too
    (``--apply`` then appends sentences), else None (``--apply`` writes .slugsin)."""
    english = tuple(s.lower() for s in ENGLISH_SUFFIXES)
    if not (spec_path.lower().endswith(english) and out.lower().endswith(english)):
        return None
    text = read_text(spec_path, "spec file")
    return None if has_section_headers(text) else text


def apply_suggestions(spec: Spec, suggestions: list[MutualExclusion], out: str,
                      chosen: list[str] | None, english: str | None = None,
                      progress: Callable[[str], None] | None = None) -> tuple[dict, str]:
    """``spec`` plus the chosen suggestions, as the text to write to ``out``, synthesized; explained
    when unrealizable. Returns (the report's ``apply`` entry, the text); writes nothing.

    With ``english`` (the text of a Structured English spec) the suggestions are appended to it as
    English sentences and the result is read back as English (its clauses then point at OUT's
    lines); else the text is ``.slugsin``. When the result is unrealizable, also try the assumption
    that the inputs driving the excluded outputs are mutually exclusive (thesis Example 9) and say
    whether it helps.
    """
    say = progress or (lambda _text: None)
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
    say(f"spec with suggestion(s) {', '.join(map(str, picked)) or 'none'} for {out}; synthesizing")
    result["realizable_before"] = is_realizable(spec, robotics_semantics=True)
    result["realizable"] = is_realizable(new_spec, robotics_semantics=True)
    if result["realizable"]:
        return result, text
    say("unrealizable: explaining")
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
    """A suggestion as Structured English sentences of ``spec``'s language (``structured_english.writer``):
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
        out.append(f"  In words: {hint['english_expanded']}")
        for section, line in hint["slugsin"].items():
            out.append(f"  .slugsin [{section}]: {line}")
    return "\n".join(out) + "\n"
