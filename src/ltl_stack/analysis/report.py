"""Reports of a graph analysis: readable text, Markdown tables like the thesis figures, and JSON.

Each check's section comes from its ``graph_checks`` module (title, table, lines), in registry order."""
from __future__ import annotations

from ltl_stack.analysis import graph_checks
from ltl_stack.analysis.checks import DECLARED_FEEDBACK, Analysis, E1Finding, feedback_reason, reach_listing
from ltl_stack.analysis.graph import ACTION
from ltl_stack.analysis.graph_checks.e1_output_to_input import rows as pair_rows
from ltl_stack.analysis.reach import PUBLISH, SUBSCRIBE
from ltl_stack.analysis.suggest import MutualExclusion
from ltl_stack.spec.model import SLUGSIN_SECTIONS

IN_SPEC_NOTE = "[already guaranteed by the spec: adding it changes nothing]"
FEEDBACK_TITLE = ("Expected feedback, not findings: activation-completion pairs [75] and what the mapping "
                  "declares")


def suggestion_forms(s: MutualExclusion) -> dict:
    """The renderings of a suggestion: its Structured English sentence, the formula in words, LTL, and
    .slugsin lines per section.

    The LTL form ``G(...)`` holds in every state, the first included; in GR(1) that is the
    unprimed formula in the init section plus the primed one in the safety section.
    """
    from ltl_stack.spec.formula_text import clause_in_words, formula_to_infix, formula_to_slugsin

    safety, init = s.sections
    return {
        "english": s.sentence(),
        "english_expanded": clause_in_words(s.formula(False), safety),
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
        "checks": [{"code": c.code, "title": c.title, "severity": c.severity, "explanation": c.explanation,
                    "ran": c.applies(a)} for c in graph_checks.CHECKS],
        **{c.code: [f.to_dict() for f in a.findings[c.code]] for c in graph_checks.CHECKS},
        "expected_feedback": [f.to_dict() for f in a.feedback],
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
    for check in (c for c in graph_checks.CHECKS if c.applies(a)):
        findings = a.findings[check.code]
        add("")
        add(f"{check.code}  {check.title}: {len(findings) or 'none'}")
        out.extend(check.text_lines(findings))
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
    robots_named = False
    for check in (c for c in graph_checks.CHECKS if c.applies(a)):
        if check.needs_robots and not robots_named:
            out += ["", f"Robots: {', '.join(a.robots)}. Robot topics to ignore: "
                    f"{', '.join(a.robot_topics_ignored) or 'none'}."]
            robots_named = True
        out += ["", f"## {check.code}: {check.title}", ""]
        out += _table(list(check.columns), [row for f in a.findings[check.code] for row in check.rows(f, True)])
    if a.feedback:
        out += ["", f"## {FEEDBACK_TITLE}", ""]
        out += _table(["Output", "Input", "Why", "Output-to-input chain"],
                      [[*row[:2], feedback_reason(f) if row[0] else "", row[2]]
                       for f in a.feedback for row in pair_rows(f, True)])
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


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    if not rows:
        return ["None."]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(c.replace("|", "\\|") for c in row) + " |" for row in rows]
    return lines
