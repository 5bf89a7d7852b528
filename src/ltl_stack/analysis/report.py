"""Reports of a graph analysis: readable text, Markdown tables like the thesis figures, and JSON."""
from __future__ import annotations

from ltl_stack.analysis.checks import DECLARED_FEEDBACK, Analysis, E1Finding, feedback_reason, reach_listing
from ltl_stack.analysis.graph import ACTION
from ltl_stack.analysis.reach import PUBLISH, SUBSCRIBE
from ltl_stack.analysis.suggest import MutualExclusion
from ltl_stack.spec.model import SLUGSIN_SECTIONS

CHECKS = {
    "E1": "Output propositions publishing to input proposition nodes (thesis 3.5.2.2)",
    "E2": "Output propositions publishing to the same topic or action (thesis 3.5.2.3)",
    "E3": "One output proposition reaching a topic through several of its nodes (thesis 3.5.2.4)",
    "C1": "Robot topics left behind: reached for some robots but not all (thesis 3.5.2.5)",
    "C2": "Robots that no output proposition controls (thesis 3.5.2.6)",
    "P1": "Input proposition topics with other publishers than the input's node (thesis 3.5.1)",
}
IN_SPEC_NOTE = "[already guaranteed by the spec: adding it changes nothing]"
FEEDBACK_TITLE = ("Expected feedback, not findings: activation-completion pairs [75] and what the mapping "
                  "declares")


def suggestion_forms(s: MutualExclusion) -> dict:
    """The renderings of a suggestion: its Structured English sentence, the formula in words, LTL, and
    .slugsin lines per section.

    The LTL form ``G(...)`` holds in every state, the first included; in GR(1) that is the
    unprimed formula in the init section plus the primed one in the safety section.
    """
    from ltl_stack.spec.formula_text import clause_to_english, formula_to_infix, formula_to_slugsin

    safety, init = s.sections
    return {
        "english": s.sentence(),
        "english_expanded": clause_to_english(s.formula(False), safety),
        "ltl": f"G({formula_to_infix(s.formula(False))})",
        "slugsin": {
            SLUGSIN_SECTIONS[safety]: formula_to_slugsin(s.formula(True)),
            SLUGSIN_SECTIONS[init]: formula_to_slugsin(s.formula(False)),
        },
    }


def to_dict(a: Analysis, suggestions: list[MutualExclusion], *, reach: bool = False,
            extra: dict | None = None) -> dict:
    g = a.graph
    data = {
        "graph": {"nodes": len(g.nodes), "topics": sum(c.kind != ACTION for c in g.channels),
                  "actions": sorted(c.name for c in g.channels if c.kind == ACTION),
                  "services": {name: providers for name, providers in sorted(g.services.items())},
                  "edges": g.edge_count,
                  "ignored_topics": sorted(g.ignored), "ignore_patterns": list(g.ignore_patterns)},
        "proposition_topics_not_crossed": a.boundary,
        "proposition_nodes": a.nodes,
        "missing_nodes": [{"proposition": m.proposition, "kind": m.kind, "node": m.node, "line": m.line}
                          for m in a.missing],
        "unmapped": a.unmapped,
        "robots": a.robots,
        "robot_topics_ignored": a.robot_topics_ignored,
        "E1": [f.to_dict() for f in a.e1],
        "expected_feedback": [f.to_dict() for f in a.feedback],
        "E2": [f.to_dict() for f in a.e2],
        "E3": [f.to_dict() for f in a.e3],
        "C1": [f.to_dict() for f in a.c1],
        "C2": [f.to_dict() for f in a.c2],
        "P1": [f.to_dict() for f in a.p1],
        "relays_followed": a.relays,
        "finding_count": a.finding_count,
        "suggestions": [{"id": i, **s.to_dict(), **_forms_or_error(s)} for i, s in enumerate(suggestions, 1)],
    }
    if reach:
        data["reach"] = {p: {"publish": reach_listing(a, p, PUBLISH), "subscribe": reach_listing(a, p, SUBSCRIBE)}
                         for p in (*a.inputs, *a.outputs) if p in a.nodes}
    if extra:
        data.update(extra)
    return data


def _forms_or_error(s: MutualExclusion) -> dict:
    try:
        return suggestion_forms(s)
    except ImportError as e:  # the spec layer's printers are not installed
        return {"english": s.sentence(), "render_error": str(e)}


def to_text(a: Analysis, suggestions: list[MutualExclusion], *, reach: bool = False) -> str:
    g = a.graph
    out: list[str] = []
    add = out.append
    actions = sum(c.kind == ACTION for c in g.channels)
    add(f"ROS computation graph: {len(g.nodes)} nodes, {len(g.channels) - actions} topics, {actions} actions, "
        f"{len(g.services)} services (not analysed), {g.edge_count} edges")
    if g.ignored:
        add(f"Ignored generic topics ({len(g.ignored)}): {_short_list(sorted(g.ignored))}")
    add(f"Proposition topics not crossed: {_short_list(a.boundary)}")
    if a.missing or a.unmapped:
        add("")
        add("Warnings:")
        for m in a.missing:
            add(f"  {m.kind} {m.proposition}: node {m.node} (mapping line {m.line}) is not in the graph; "
                "launch the proposition nodes before the analysis")
        if a.unmapped:
            add(f"  not mapped to any node (left out): {', '.join(a.unmapped)}")
    if a.relays:
        add(f"Relays followed for E2/E3 (not known mergers): {_short_list(a.relays)}")
    sections = [("P1", a.p1), ("E1", a.e1), ("E2", a.e2), ("E3", a.e3)]
    if a.robots:
        sections += [("C1", a.c1), ("C2", a.c2)]
    for key, findings in sections:
        add("")
        add(f"{key}  {CHECKS[key]}: {len(findings) or 'none'}")
        if key == "E2":
            out.extend(_e2_lines(findings))
            continue
        for f in findings:
            out.extend("  " + line for line in _finding_lines(key, f))
    if a.robots:
        add(f"  (robots: {', '.join(a.robots)}; robot topics ignored: {', '.join(a.robot_topics_ignored) or 'none'})")
    if a.feedback:
        add("")
        add(f"{FEEDBACK_TITLE}: {len(a.feedback)} pair(s)")
        out.extend("  " + line for line in feedback_lines(a.feedback))
    add("")
    add(f"Suggested additions to the specification: {len(suggestions) or 'none'}")
    for i, s in enumerate(suggestions, 1):
        out.extend("  " + line for line in suggestion_lines(i, s))
    if reach:
        add("")
        add("Reachability per proposition node (thesis 3.5.2.1)")
        for p in (*a.inputs, *a.outputs):
            for direction, label in ((PUBLISH, "publish"), (SUBSCRIBE, "subscribe")):
                for row in reach_listing(a, p, direction) if p in a.nodes else []:
                    add(f"  {p} {row['node']} {label}-reachable: {len(row['topics'])} topics, "
                        f"{len(row['nodes'])} nodes")
                    for name, chain in row["topics"].items():
                        add(f"    {name}: {chain}")
                    for name, chain in row["nodes"].items():
                        add(f"    {name}: {chain}")
    add("")
    add(f"{a.finding_count} finding(s)." + (f" {len(a.feedback)} expected feedback pair(s), not counted."
                                           if a.feedback else ""))
    return "\n".join(out) + "\n"


def suggestion_lines(i: int, s: MutualExclusion) -> list[str]:
    why = f"   (shared: {_short_list(list(s.topics), 4)})" if s.topics else ""
    lines = [f"{i}. {s.sentence()}{why}" + (f"   {IN_SPEC_NOTE}" if s.in_spec else "")]
    forms = _forms_or_error(s)
    if "render_error" in forms:
        lines.append(f"   (cannot render the formula: {forms['render_error']})")
        return lines
    lines.append(f"   In words: {forms['english_expanded']}")
    lines.append(f"   LTL: {forms['ltl']}")
    for section, line in forms["slugsin"].items():
        lines.append(f"   .slugsin [{section}]: {line}")
    return lines


def _e2_lines(groups) -> list[str]:
    """E2 groups; channels where the same pairs compete are named under the first one, not repeated."""
    alike: dict[tuple, list] = {}
    for g in groups:
        alike.setdefault((g.outputs, g.pairs), []).append(g)
    lines = []
    for first, *others in alike.values():
        lines.append(f"  {_channel_text(first)}: {', '.join(first.outputs)}")
        if not first.complete:
            lines.append(f"    competing pairs: {', '.join(a + '/' + b for a, b in first.pairs)}")
        lines.extend(f"    {w.proposition}: {w.text}" for w in first.witnesses)
        if others:
            lines.append("    the same outputs also compete on: "
                         + _short_list([_channel_text(g) for g in others], 6))
    return lines


def _channel_text(f) -> str:
    return f"({f.channel})" if f.kind == ACTION else f"[{f.channel}]"


def feedback_lines(pairs: list[E1Finding]) -> list[str]:
    """Expected feedback: completion pairs one by one with their chain; the pairs the mapping declares
    folded per output, one chain each."""
    lines = []
    for f in pairs:
        if f.expected != DECLARED_FEEDBACK:
            lines += [f"{f.output} -> {f.input}: {feedback_reason(f)}", f"  {f.witness.text}"]
    declared: dict[str, list[E1Finding]] = {}
    for f in pairs:
        if f.expected == DECLARED_FEEDBACK:
            declared.setdefault(f.output, []).append(f)
    if declared:
        lines.append("declared in the mapping (expected_feedback):")
        for output, fs in declared.items():
            lines += [f"  {output} -> {', '.join(f.input for f in fs)}", f"    {fs[0].witness.text}"]
    return lines


def _e1_lines(f: E1Finding) -> list[str]:
    if len(f.witnesses) == 1:
        return [f"{f.output} -> {f.input}: {f.witness.text}"]
    return [f"{f.output} -> {f.input}: {len(f.witnesses)} chains", *(f"  {w.text}" for w in f.witnesses)]


def _finding_lines(key: str, f) -> list[str]:
    if key == "E1":
        return _e1_lines(f)
    if key == "E2":
        name = f"({f.channel})" if f.kind == ACTION else f"[{f.channel}]"
        return [f"{name}: {', '.join(f.outputs)}", *(f"  {w.proposition}: {w.text}" for w in f.witnesses)]
    if key == "E3":
        name = f"({f.channel})" if f.kind == ACTION else f"[{f.channel}]"
        return [f"{f.output} reaches {name} through {len(f.witnesses)} nodes:",
                *(f"  {w.node}: {w.text}" for w in f.witnesses)]
    if key == "P1":
        return [f"{f.input} [{f.topic}]: also published by {', '.join(f.others)} (the input's node: "
                f"{', '.join(f.nodes)})"]
    if key == "C1":
        return [f"{f.output} {f.suffix}: missing for {', '.join(f.missing)}",
                *(f"  {r}: {w.text}" for r, w in f.present), *(f"  {r}: -" for r in f.missing)]
    return [f"{f.robot}: no output reaches any of its topics"
            + (f" (the other robots get {', '.join(f.suffixes)})" if f.suffixes else "")]


def _short_list(items: list[str], limit: int = 8) -> str:
    if not items:
        return "none"
    shown = ", ".join(items[:limit])
    return shown + (f", ... ({len(items) - limit} more)" if len(items) > limit else "")


def to_markdown(a: Analysis, suggestions: list[MutualExclusion]) -> str:
    """Tables laid out like thesis Figs. 3.6-3.9, 3.14, 3.15."""
    out: list[str] = ["# ROS computation graph analysis", ""]
    g = a.graph
    out.append(f"{len(g.nodes)} nodes, {len(g.channels)} topics and actions, {g.edge_count} edges. "
               f"Ignored generic topics: {_short_list(sorted(g.ignored))}.")
    if a.missing:
        out += ["", "**Mapped nodes not in the graph:** "
                + ", ".join(f"`{m.node}` ({m.proposition})" for m in a.missing)]
    out += ["", f"## E1: {CHECKS['E1']}", ""]
    out += _table(["Output", "Input", "Output-to-input chain"], _e1_rows(a.e1))
    if a.feedback:
        out += ["", f"## {FEEDBACK_TITLE}", ""]
        out += _table(["Output", "Input", "Why", "Output-to-input chain"],
                      [[*row[:2], feedback_reason(f) if row[0] else "", row[2]]
                       for f in a.feedback for row in _e1_rows([f])])
    out += ["", f"## P1: {CHECKS['P1']}", ""]
    out += _table(["Input", "Topic", "Other publishers", "Mapped node"],
                  [[f.input, f.topic, ", ".join(f.others), ", ".join(f.nodes)] for f in a.p1])
    out += ["", f"## E2: {CHECKS['E2']}", ""]
    out += _table(["Topic", "Output", "Output-to-topic chain"],
                  [[f.channel if i == 0 else "", w.proposition, f"`{w.text}`"]
                   for f in a.e2 for i, w in enumerate(f.witnesses)])
    out += ["", f"## E3: {CHECKS['E3']}", ""]
    out += _table(["Output", "Topic", "Node", "One existing chain"],
                  [[f.output if i == 0 else "", f.channel if i == 0 else "", w.node, f"`{w.text}`"]
                   for f in a.e3 for i, w in enumerate(f.witnesses)])
    if a.robots:
        out += ["", f"Robots: {', '.join(a.robots)}. Robot topics to ignore: "
                f"{', '.join(a.robot_topics_ignored) or 'none'}."]
        out += ["", f"## C1: {CHECKS['C1']}", ""]
        rows = []
        for f in a.c1:
            cells = [(r, f"`{w.text}`") for r, w in f.present] + [(r, "—") for r in f.missing]
            for i, (robot, chain) in enumerate(cells):
                rows.append([f.output if i == 0 else "", f.suffix if i == 0 else "", robot, chain])
        out += _table(["Output", "Topic", "Robot", "One existing chain"], rows)
        out += ["", f"## C2: {CHECKS['C2']}", ""]
        out += _table(["Robot", "Topics the other robots get"], [[f.robot, ", ".join(f.suffixes)] for f in a.c2])
    out += ["", "## Suggested additions to the specification", ""]
    if not suggestions:
        out.append("None.")
    for i, s in enumerate(suggestions, 1):
        forms = _forms_or_error(s)
        out.append(f"{i}. **{s.sentence()}** (shared: {', '.join(s.topics) or '-'})"
                   + (f" {IN_SPEC_NOTE}" if s.in_spec else ""))
        if "render_error" not in forms:
            out.append(f"   - In words: `{forms['english_expanded']}`")
            out.append(f"   - LTL: `{forms['ltl']}`")
            for section, line in forms["slugsin"].items():
                out.append(f"   - `[{section}]`: `{line}`")
    out += ["", f"{a.finding_count} finding(s)." + (f" {len(a.feedback)} expected feedback pair(s), not counted."
                                                   if a.feedback else "")]
    return "\n".join(out) + "\n"


def _e1_rows(findings: list[E1Finding]) -> list[list[str]]:
    """One row per chain, the (output, input) cells only on a pair's first row."""
    return [[f.output if k == 0 else "", f.input if k == 0 else "", f"`{w.text}`"]
            for f in findings for k, w in enumerate(f.witnesses)]


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    if not rows:
        return ["None."]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(c.replace("|", "\\|") for c in row) + " |" for row in rows]
    return lines
