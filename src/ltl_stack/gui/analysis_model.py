"""What the analysis panel shows (thesis §3.6.1.2, §3.6.2.2, Figs. 3.6–3.9, 3.13–3.15), without Qt.

``run_analysis`` does what ``analyze_graph`` does (snapshot, every check of ``analysis.graph_checks``,
suggestions) and
returns an ``AnalysisResult`` whose ``tables()`` are the rows of the panel's tables laid out like the
thesis figures, with for each row the finding it belongs to (E2 rows of one topic share a group, so
selecting a topic selects its rows); E1 pairs that are the designed feedback of the
activation-completion paradigm get their own table (``FEEDBACK_KEY``), not counted as findings. ``suggestion_text`` renders the suggestions as Structured
English, LTL or ``.slugsin``; ``conflict_graph`` is the subgraph of a finding's witness chains with
the conflicting channels highlighted; ``apply_and_check`` writes the amended spec, synthesizes it and
explains an unrealizable result. Loading, the checks, the problem list and apply-and-check are
``analysis.workflow``'s, the functions ``analyze_graph`` calls, so the panel shows what the CLI prints.
"""
from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field

from ltl_stack.analysis import graph_checks, report
from ltl_stack.analysis.checks import Analysis, Witness, feedback_reason
from ltl_stack.analysis.graph_checks.e1_output_to_input import witnesses as pair_witnesses
from ltl_stack.analysis.report import IN_SPEC_NOTE
from ltl_stack.analysis.snapshot import Snapshot
from ltl_stack.analysis.suggest import MutualExclusion
from ltl_stack.analysis.workflow import (
    Problem,
    apply_suggestions,
    apply_text,
    english_text,
    load_inputs,
    problems,
    run_checks,
)
from ltl_stack.cli import check_outputs, write_output
from ltl_stack.gui.dotgraph import DotGraph
from ltl_stack.spec.model import Spec

CHECK_KEYS = tuple(c.code for c in graph_checks.CHECKS)
FEEDBACK_KEY = "feedback"
TAB_KEYS = (*CHECK_KEYS, FEEDBACK_KEY)  # the panel's tabs: the checks, then the expected feedback
TAB_TITLES = {**{k: k for k in CHECK_KEYS}, FEEDBACK_KEY: "Expected feedback"}
FORMS = ("english", "ltl", "slugsin")
FORM_TITLES = {"english": "Formula in words", "ltl": "LTL", "slugsin": ".slugsin"}
CONFLICT_COLOR = "red"
PROPOSITION_COLOR = "blue"


def names(text: str) -> list[str]:
    """``a, b ,c`` -> ``['a', 'b', 'c']`` (the Robots and topics-to-ignore fields)."""
    return [t.strip() for t in text.replace(";", ",").split(",") if t.strip()]


@dataclass
class Table:
    """Rows of one check's table; ``finding[i]`` is the index of the finding row ``i`` shows."""

    key: str
    header: list[str]
    rows: list[list[str]] = field(default_factory=list)
    finding: list[int] = field(default_factory=list)

    def rows_of(self, index: int) -> list[int]:
        """The rows of finding ``index`` (an E2 topic's rows, an E3/C1 finding's rows)."""
        return [i for i, f in enumerate(self.finding) if f == index]


@dataclass
class AnalysisResult:
    spec: Spec
    analysis: Analysis
    suggestions: list[MutualExclusion]
    problems: list[Problem]  # what analyze_graph prints with its report: never hidden
    snapshot: Snapshot
    spec_path: str = ""
    mapping_path: str = ""
    snapshot_path: str | None = None
    _tables: dict[str, Table] | None = None
    _texts: dict[str, str] = field(default_factory=dict)

    def prepare(self) -> AnalysisResult:
        """Build the tables and the suggestion texts now (on the worker thread, not the GUI's)."""
        self.tables()
        for form in FORMS:
            self.suggestion_text(form)
        self.summary()  # counts every edge of the graph: not on the GUI thread
        return self

    def suggestion_text(self, form: str) -> str:
        if form not in self._texts:
            self._texts[form] = suggestion_text(self.suggestions, form)
        return self._texts[form]

    def tables(self) -> dict[str, Table]:
        """A table per check, laid out like thesis Figs. 3.6, 3.7/3.8, 3.9, 3.14 and 3.15, and the expected
        feedback's (built once)."""
        if self._tables is None:
            self._tables = self._build_tables()
        return self._tables

    def _build_tables(self) -> dict[str, Table]:
        a = self.analysis
        t = {c.code: Table(c.code, list(c.columns)) for c in graph_checks.CHECKS}
        t[FEEDBACK_KEY] = Table(FEEDBACK_KEY, ["Output", "Input", "Why (activation-completion)", "Output-to-input chain"])
        for check in graph_checks.CHECKS:
            for i, f in enumerate(a.findings[check.code]):
                for row in check.rows(f, False):
                    _add(t[check.code], i, row)
        for i, f in enumerate(a.feedback):
            for k, w in enumerate(f.witnesses):
                _add(t[FEEDBACK_KEY], i, [f.output if k == 0 else "", f.input if k == 0 else "",
                                          feedback_reason(f) if k == 0 else "", w.text])
        return t

    def counts(self) -> dict[str, int]:
        """Findings per check, and the expected feedback pairs (``FEEDBACK_KEY``, not findings)."""
        a = self.analysis
        return {**{c.code: len(a.findings[c.code]) for c in graph_checks.CHECKS}, FEEDBACK_KEY: len(a.feedback)}

    def witnesses(self, key: str, index: int) -> tuple[list[Witness], set[str]]:
        """The chains of finding ``index`` of check ``key`` and the channels/nodes in conflict there."""
        if key == FEEDBACK_KEY:
            return pair_witnesses(self.analysis.feedback[index])
        return graph_checks.BY_CODE[key].witnesses(self.analysis.findings[key][index])

    def summary(self) -> str:
        if "summary" not in self._texts:
            self._texts["summary"] = self._summary()
        return self._texts["summary"]

    def _summary(self) -> str:
        g = self.analysis.graph
        c = self.counts()
        found = ", ".join(f"{k.code} {c[k.code]}" for k in graph_checks.CHECKS if k.applies(self.analysis))
        feedback = f"; expected feedback: {c[FEEDBACK_KEY]} pair(s)" if c[FEEDBACK_KEY] else ""
        return (f"{len(g.nodes)} nodes, {len(g.channels)} topics/actions, {g.edge_count} edges; "
                f"findings: {found}{feedback}; {len(self.suggestions)} suggestion(s)")

    def parts(self, chunk: int = 500) -> Iterator[tuple]:
        """The result as ``AnalysisView.assemble`` takes it, in parts of at most ``chunk`` rows or findings:
        the analysis process sends them one by one, so that reading any one of them is short (reading a
        whole result holds the GIL 280 ms on the 10,000-node graph, and the panel's GUI thread waits)."""
        self.prepare()
        yield ("meta", {"spec": self.spec, "suggestions": self.suggestions, "problems": self.problems,
                        "spec_path": self.spec_path, "mapping_path": self.mapping_path,
                        "snapshot_path": self.snapshot_path, "counts": self.counts(), "texts": dict(self._texts)})
        for key, table in self.tables().items():
            yield ("table", key, table.header)
            for start in range(0, len(table.rows), chunk):
                yield ("rows", key, table.rows[start:start + chunk], table.finding[start:start + chunk])
        counts = self.counts()
        for key in self.tables():
            for start in range(0, counts[key], chunk):
                yield ("witnesses", key, [self.witnesses(key, i) for i in range(start, min(counts[key], start + chunk))])


@dataclass
class AnalysisView:
    """What the analysis panel shows of an ``AnalysisResult`` (tables, counts, problems, suggestions, each
    finding's chains) and what Apply needs (spec, suggestions, paths), without the graph: the analysis
    runs in its own process (``worker_process``) and sends this back in parts. ``snapshot`` is the live
    graph when the panel took it."""

    spec: Spec
    suggestions: list[MutualExclusion]
    problems: list[Problem]
    spec_path: str = ""
    mapping_path: str = ""
    snapshot_path: str | None = None
    snapshot: Snapshot | None = None
    _counts: dict[str, int] = field(default_factory=dict)
    _texts: dict[str, str] = field(default_factory=dict)
    _tables: dict[str, Table] = field(default_factory=dict)
    _witnesses: dict[str, list[tuple[list[Witness], set[str]]]] = field(default_factory=dict)

    @classmethod
    def assemble(cls, parts: Iterable[tuple]) -> AnalysisView:
        view = None
        for part in parts:
            kind = part[0]
            if kind == "meta":
                meta = dict(part[1])
                counts, texts = meta.pop("counts"), meta.pop("texts")
                view = cls(**meta, _counts=counts, _texts=texts)
            elif kind == "table":
                view._tables[part[1]] = Table(part[1], list(part[2]))
            elif kind == "rows":
                view._tables[part[1]].rows.extend(part[2])
                view._tables[part[1]].finding.extend(part[3])
            elif kind == "witnesses":
                view._witnesses.setdefault(part[1], []).extend(part[2])
        if view is None:
            raise ValueError("no analysis in the parts")
        return view

    def tables(self) -> dict[str, Table]:
        return self._tables

    def counts(self) -> dict[str, int]:
        return self._counts

    def summary(self) -> str:
        return self._texts["summary"]

    def suggestion_text(self, form: str) -> str:
        if form not in self._texts:
            self._texts[form] = suggestion_text(self.suggestions, form)
        return self._texts[form]

    def witnesses(self, key: str, index: int) -> tuple[list[Witness], set[str]]:
        found = self._witnesses.get(key, [])
        return found[index] if 0 <= index < len(found) else ([], set())


def _add(table: Table, finding: int, row: list[str]) -> None:
    table.rows.append(row)
    table.finding.append(finding)


def run_analysis(spec_path: str, mapping_path: str, *, snapshot: Snapshot | None = None,
                 snapshot_path: str | None = None, robots: Sequence[str] = (), ignore_topics: Sequence[str] = (),
                 progress: Callable[[str], None] | None = None) -> AnalysisResult:
    """Load spec and mapping, take ``snapshot`` (or load ``snapshot_path``), run every check.

    Raises the loaders' ``UserError``s; a mapping that does not fit the spec is one too (the first
    error of ``check_mapping``), as in ``analyze_graph`` (``analysis.workflow.load_inputs``).
    """
    say = progress or (lambda _text: None)
    spec, mapping, issues = load_inputs(spec_path, mapping_path)
    if snapshot is None:
        if not snapshot_path:
            raise ValueError("no snapshot: take one of the live graph or name a snapshot file")
        say(f"loading {snapshot_path}")
        snapshot = Snapshot.load(snapshot_path)
    say("building the graph")
    analysis, suggestions = run_checks(spec, mapping, snapshot, robots=robots, ignore_topics=ignore_topics,
                                       progress=say)
    say("laying out the tables")
    return AnalysisResult(spec, analysis, suggestions, problems(analysis, mapping, issues, snapshot), snapshot,
                          str(spec_path), str(mapping_path), snapshot_path).prepare()


def suggestion_text(suggestions: Sequence[MutualExclusion], form: str) -> str:
    """Every suggestion (its Structured English sentence) with its formula in one of ``FORMS``: in words,
    LTL ``G(...)`` or ``.slugsin`` lines."""
    if not suggestions:
        return "No suggestions: no two outputs compete on a topic or action."
    out = []
    for i, s in enumerate(suggestions, 1):
        forms = report.suggestion_forms(s)
        out.append(f"{i}. {s.sentence()}" + (f"   (shared: {', '.join(s.topics[:4])}"
                                               f"{', …' if len(s.topics) > 4 else ''})" if s.topics else "")
                   + (f"   {IN_SPEC_NOTE}" if s.in_spec else ""))
        if form == "english":
            out.append(f"   always {re.sub('^always ', '', forms['english_expanded'])}")
        elif form == "ltl":
            out.append(f"   {forms['ltl']}")
        else:
            out.extend(f"   [{section}] {line}" for section, line in forms["slugsin"].items())
        out.append("")
    return "\n".join(out).rstrip() + "\n"


def conflict_graph(result: AnalysisResult | AnalysisView, key: str, index: int) -> DotGraph:
    """The subgraph of the finding's witness chains (nodes round, topics and actions boxed, as
    rqt_graph draws them), the conflicting channels red, the proposition nodes blue."""
    chains, conflict = result.witnesses(key, index)
    g = DotGraph(name=f"{key}_{index + 1}")
    for w in chains:
        previous = None
        for k, (kind, name) in enumerate(w.path):
            shape = "ellipse" if kind == "node" else "box"  # qt_dotgraph's box3d fails on PyQt5 5.15
            color = CONFLICT_COLOR if name in conflict else PROPOSITION_COLOR if k == 0 else "black"
            g.add_node((kind, name), name, shape=shape, color=color,
                       tooltip=f"{kind} {name}" + (f" (node of {w.proposition})" if k == 0 else ""))
            if previous is not None and not any(
                    e.source == g.key[previous] and e.target == g.key[(kind, name)] for e in g.edges):
                g.add_edge(previous, (kind, name), w.proposition if k == 1 else "")
            previous = (kind, name)
    return g


def apply_and_check(result: AnalysisResult | AnalysisView, out: str, chosen: Sequence[int] | None = None,
                    progress: Callable[[str], None] | None = None) -> dict:
    """Write the spec plus the chosen suggestions (1-based; default all) to ``out``, synthesize it
    (robotics init semantics) and, when unrealizable, explain it and try the input-exclusion hint of
    thesis Example 9. The dict is ``analyze_graph --apply``'s; ``text`` is its report. ``out`` naming
    one of the inputs is refused (``UserError``) before anything is written. A Structured English
    spec and an English ``out`` (``.spec``) get the suggestions appended as sentences, as
    ``analyze_graph --apply`` does."""
    picked = None if chosen is None else [str(i) for i in chosen]
    check_outputs([result.spec_path, result.mapping_path, result.snapshot_path], [out])  # never over an input
    english = english_text(result.spec_path, out) if result.spec_path else None
    applied, text = apply_suggestions(result.spec, result.suggestions, out, picked, english, progress)
    write_output(out, text, "amended spec")
    applied["text"] = apply_text(applied)
    return applied
