"""E2 (thesis §3.5.2.3, Figs. 3.7, 3.8): two or more output propositions publish-reach the same topic
or action, refined in ``conflicts``: they must compete there, not merely both reach a driver's outputs."""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ltl_stack.analysis.graph_checks.base import WARNING, Context, GraphCheck
from ltl_stack.analysis.graph_checks.competition import competitions
from ltl_stack.analysis.result import Analysis, Witness, channel_text


@dataclass(frozen=True)
class E2Group:
    """Output propositions that compete on one channel (topic or action): one witness per output."""

    channel: str
    kind: str  # "topic" or "action"
    witnesses: tuple[Witness, ...]
    pairs: tuple[tuple[str, str], ...] = ()  # the competing pairs (all pairs unless a mux merges some)

    @property
    def outputs(self) -> tuple[str, ...]:
        return tuple(w.proposition for w in self.witnesses)

    @property
    def complete(self) -> bool:
        """True when every two of the outputs compete on the channel."""
        k = len(self.witnesses)
        return len(self.pairs) == k * (k - 1) // 2

    def to_dict(self) -> dict:
        return {"topic": self.channel, "kind": self.kind, "outputs": list(self.outputs),
                "pairs": [list(p) for p in self.pairs], "chains": [w.to_dict() for w in self.witnesses]}


def find(a: Analysis, context: Context) -> list[E2Group]:
    rank = {y: i for i, y in enumerate(a.outputs)}
    groups = []
    for c in competitions(a, context):
        if not c.pairs:
            continue
        ch = a.graph.channel_of_vertex(c.vertex)
        outputs = sorted(c.first, key=rank.__getitem__)
        groups.append(E2Group(ch.name, ch.kind, tuple(a.witness(y, c.first[y], c.vertex) for y in outputs),
                              tuple(sorted(c.pairs, key=lambda p: (rank[p[0]], rank[p[1]])))))
    groups.sort(key=lambda g: (-len(g.witnesses), g.channel))
    return groups


def e2_groups(a: Analysis) -> list[tuple[str, tuple[tuple[str, str], ...]]]:
    """(channel, competing output pairs) of every E2 group: the input of ``suggest.mutual_exclusions``."""
    return [(g.channel, g.pairs) for g in a.findings[CHECK.code]]


def rows(g: E2Group, markdown: bool) -> list[list[str]]:
    """One row per output, the channel named on the first."""
    if markdown:
        return [[g.channel if i == 0 else "", w.proposition, f"`{w.text}`"] for i, w in enumerate(g.witnesses)]
    return [[channel_text(g.channel, g.kind) if i == 0 else "", w.proposition, w.text]
            for i, w in enumerate(g.witnesses)]


def lines(g: E2Group) -> list[str]:
    return [f"{channel_text(g.channel, g.kind)}: {', '.join(g.outputs)}",
            *(f"  {w.proposition}: {w.text}" for w in g.witnesses)]


def text_block(groups: Sequence[E2Group]) -> list[str]:
    """E2 groups; channels where the same pairs compete are named under the first one, not repeated."""
    alike: dict[tuple, list] = {}
    for g in groups:
        alike.setdefault((g.outputs, g.pairs), []).append(g)
    out = []
    for first, *others in alike.values():
        out.append(f"  {channel_text(first.channel, first.kind)}: {', '.join(first.outputs)}")
        if not first.complete:
            out.append(f"    competing pairs: {', '.join(a + '/' + b for a, b in first.pairs)}")
        out.extend(f"    {w.proposition}: {w.text}" for w in first.witnesses)
        if others:
            names = [channel_text(g.channel, g.kind) for g in others]
            shown = ", ".join(names[:6]) + (f", ... ({len(names) - 6} more)" if len(names) > 6 else "")
            out.append("    the same outputs also compete on: " + shown)
    return out


def witnesses(g: E2Group) -> tuple[list[Witness], set[str]]:
    return list(g.witnesses), {g.channel}


CHECK = GraphCheck(
    code="E2", title="Output propositions publishing to the same topic or action (thesis 3.5.2.3)",
    severity=WARNING,
    explanation="Two outputs can command one topic or action at once and override each other; the "
                "suggested mutual exclusions keep them apart in the specification.",
    find=find, columns=("Topic", "Output", "Output-to-topic chain"), rows=rows, lines=lines, order=20,
    witnesses=witnesses, text_block=text_block)
