"""E1 (thesis §3.5.2.2, Fig. 3.6): an output proposition's nodes publish-reach an input proposition node.

One finding per (output, input) pair with every chain under it. Pairs that are the designed feedback
of the activation-completion paradigm ([75]: an action ``X`` and its completion ``X_ac``, a region
``R`` and its completion ``R_rc``), and the pairs the mapping declares under ``expected_feedback:``,
are kept apart as *expected feedback* (``Analysis.feedback``): shown, not counted as findings.
"""
from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from fnmatch import fnmatchcase

from ltl_stack.analysis.graph_checks.base import WARNING, Context, GraphCheck
from ltl_stack.analysis.result import Analysis, Witness, make_witness
from ltl_stack.spec.activation_completion import ACTION_COMPLETION, REGION_COMPLETION

#: kinds of expected feedback (``E1Finding.expected``) and what each means
ACTION_FEEDBACK = "action completion"
REGION_FEEDBACK = "region completion"
DECLARED_FEEDBACK = "declared in the mapping"


@dataclass(frozen=True)
class E1Finding:
    """Output ``output`` publish-reaches the node(s) of input ``input``: one chain per (output node,
    input node) pair, folded under the one (output, input) row. ``expected`` is the reason when the
    pair is designed feedback (activation-completion: its kind), else ''."""

    output: str
    input: str
    witnesses: tuple[Witness, ...]
    input_nodes: tuple[str, ...]  # the input node each witness ends at
    expected: str = ""  # a kind of expected feedback (``expected_feedback``) or ''

    @property
    def witness(self) -> Witness:
        return self.witnesses[0]

    @property
    def input_node(self) -> str:
        return self.input_nodes[0]

    def to_dict(self) -> dict:
        data = {"output": self.output, "input": self.input, "input_node": self.input_node,
                "output_node": self.witness.node, "chain": self.witness.text,
                "chains": [{"output_node": w.node, "input_node": n, "chain": w.text}
                           for w, n in zip(self.witnesses, self.input_nodes)]}
        if self.expected:
            data["expected"] = self.expected
            data["why"] = feedback_reason(self)
        return data


def all_pairs(a: Analysis) -> list[E1Finding]:
    """Output propositions whose nodes publish-reach an input proposition node, expected feedback
    included: one finding per (output, input) pair in spec order, with a chain for every (output node,
    input node) pair that reaches; each is marked with ``expected_feedback``'s reason, if any."""
    input_nodes = [(x, [(n, a.graph.node_index[n]) for n in a.nodes.get(x, [])]) for x in a.inputs]
    found = []
    for y in a.outputs:
        for x, nodes in input_nodes:
            witnesses, ends = [], []
            for x_node, v in nodes:
                for y_node in a.nodes.get(y, []):
                    r = a.pub[(y, y_node)]
                    if v in r:
                        witnesses.append(make_witness(a.graph, y, y_node, r.chain(v)))
                        ends.append(x_node)
            if witnesses:
                kind = expected_feedback(y, x, a.declared_feedback)
                found.append(E1Finding(y, x, tuple(witnesses), tuple(ends), kind))
    return found


def expected_pairs(a: Analysis, context: Context) -> list[E1Finding]:
    """The pairs that are expected feedback (``Analysis.feedback``)."""
    return [f for f in context.once("E1 pairs", lambda: all_pairs(a)) if f.expected]


def find(a: Analysis, context: Context) -> list[E1Finding]:
    return [f for f in context.once("E1 pairs", lambda: all_pairs(a)) if not f.expected]


def expected_feedback(output: str, input: str, declared: Iterable[tuple[str, str, int]] = ()) -> str:
    """The kind of designed feedback that ``output`` reaching ``input`` is, or '' when it is a finding.

    Exactly the activation-completion pairs of [75] (thesis 4.3), plus what the user declares:
    - ``ACTION_FEEDBACK``: ``X`` -> ``X_ac``, the action reports its own completion (thesis Fig. 3.6
      calls this connection desirable);
    - ``REGION_FEEDBACK``: ``R`` -> ``R_rc``, heading for region R, the robot's own location sensing
      reports its arrival;
    - ``DECLARED_FEEDBACK``: a pair the mapping's ``expected_feedback:`` matches (output pattern, input
      pattern), e.g. a robot whose every motion output reaches every region sensor through a simulator.
    Anything else — a motion output reaching another region's sensor included — is a finding.
    """
    if input == output + ACTION_COMPLETION:
        return ACTION_FEEDBACK
    if input == output + REGION_COMPLETION:
        return REGION_FEEDBACK
    if any(fnmatchcase(output, o) and fnmatchcase(input, i) for o, i, _ in declared):
        return DECLARED_FEEDBACK
    return ""


def feedback_reason(f: E1Finding) -> str:
    """One sentence saying why ``f`` is expected feedback."""
    if f.expected == ACTION_FEEDBACK:
        return f"{f.input} reports the completion of the action {f.output}"
    if f.expected == REGION_FEEDBACK:
        return f"{f.input} reports the robot's arrival in region {f.output}"
    if f.expected == DECLARED_FEEDBACK:
        return f"the mapping declares {f.output} -> {f.input} expected feedback"
    return ""


def rows(f: E1Finding, markdown: bool) -> list[list[str]]:
    """One row per chain, the (output, input) cells only on the pair's first row."""
    return [[f.output if k == 0 else "", f.input if k == 0 else "", f"`{w.text}`" if markdown else w.text]
            for k, w in enumerate(f.witnesses)]


def lines(f: E1Finding) -> list[str]:
    if len(f.witnesses) == 1:
        return [f"{f.output} -> {f.input}: {f.witness.text}"]
    return [f"{f.output} -> {f.input}: {len(f.witnesses)} chains", *(f"  {w.text}" for w in f.witnesses)]


def witnesses(f: E1Finding) -> tuple[list[Witness], set[str]]:
    return list(f.witnesses), set(f.input_nodes)


CHECK = GraphCheck(
    code="E1", title="Output propositions publishing to input proposition nodes (thesis 3.5.2.2)",
    severity=WARNING,
    explanation="What the robot does changes what it senses, outside the specification: the controller may "
                "see its own action as an environment change. Designed feedback (an action's completion, "
                "arrival in a region, the mapping's expected_feedback) is listed apart.",
    find=find, columns=("Output", "Input", "Output-to-input chain"), rows=rows, lines=lines, order=10,
    witnesses=witnesses)
