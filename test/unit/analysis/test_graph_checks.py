"""The graph checks are one registry (``analysis.graph_checks``): each check is one module that
declares its code, title, severity, explanation, search, table and lines; the analysis, the three
reports and the analysis panel's model show every registered check and nothing else."""
from __future__ import annotations

import json
import sys
import textwrap

import pytest
from analysis_data import analyze_simple

from ltl_stack.analysis import graph_checks
from ltl_stack.analysis.graph_checks.base import ERROR, WARNING
from ltl_stack.analysis.report import to_dict, to_markdown, to_text
from ltl_stack.gui.analysis_model import AnalysisResult

PROBE = "x9_probe_check"
PROBE_MODULE = textwrap.dedent('''
    from dataclasses import dataclass

    from ltl_stack.analysis.graph_checks.base import WARNING, GraphCheck


    @dataclass(frozen=True)
    class Mapped:
        output: str
        node: str

        def to_dict(self):
            return {"output": self.output, "node": self.node}


    def find(a, context):
        return [Mapped(y, n) for y in a.outputs for n in a.nodes.get(y, [])]


    CHECK = GraphCheck(code="X9", title="Every mapped output node (a probe)", severity=WARNING,
                       explanation="only for the test", find=find, columns=("Output", "Node"),
                       rows=lambda f, markdown: [[f.output, f.node]], lines=lambda f: [f"{f.output} at {f.node}"],
                       order=15)
''')
NODES = {"/drive": {"sub": ["/t/outputs/go"], "pub": ["/cmd_vel"]},
         "/dock": {"sub": ["/t/outputs/dock"], "pub": ["/cmd_vel"]},
         "/sensor": {"pub": ["/t/inputs/seen"]}}


def test_the_registry_holds_the_thesis_checks_in_report_order():
    assert [c.code for c in graph_checks.CHECKS] == ["E1", "E2", "E3", "C1", "C2", "P1"]
    for check in graph_checks.CHECKS:
        assert "thesis 3.5" in check.title and check.explanation, check.code
        assert check.severity in (ERROR, WARNING) and check.columns, check.code
        assert graph_checks.BY_CODE[check.code] is check
    assert [c.code for c in graph_checks.CHECKS if c.needs_robots] == ["C1", "C2"]


def test_every_check_has_an_entry_and_the_panel_a_table_p1_included():
    a = analyze_simple(NODES, {"seen": "/sensor"}, {"go": "/drive", "dock": "/dock"})
    assert set(a.findings) == {c.code for c in graph_checks.CHECKS}
    assert [g.outputs for g in a.e2] == [("go", "dock")] and a.finding_count == 1
    result = AnalysisResult(None, a, [], [], None)
    assert set(result.tables()) >= {c.code for c in graph_checks.CHECKS} and "P1" in result.counts()
    assert result.tables()["E2"].rows == [["[/cmd_vel]", "go", "(/drive) -> [/cmd_vel]"],
                                         ["", "dock", "(/dock) -> [/cmd_vel]"]]


@pytest.fixture
def probe_registered(tmp_path, monkeypatch):
    """A check module that lives outside the package, found as if it were in it."""
    (tmp_path / f"{PROBE}.py").write_text(PROBE_MODULE)
    monkeypatch.setattr(graph_checks, "__path__", [*graph_checks.__path__, str(tmp_path)])
    checks = graph_checks._discover()
    monkeypatch.setattr(graph_checks, "CHECKS", checks)
    monkeypatch.setattr(graph_checks, "BY_CODE", {c.code: c for c in checks})
    yield
    sys.modules.pop(f"{graph_checks.__name__}.{PROBE}", None)


def test_a_new_check_module_reaches_the_analysis_the_reports_and_the_panel(probe_registered):
    assert [c.code for c in graph_checks.CHECKS] == ["E1", "X9", "E2", "E3", "C1", "C2", "P1"]
    a = analyze_simple(NODES, {"seen": "/sensor"}, {"go": "/drive", "dock": "/dock"})
    assert [(f.output, f.node) for f in a.x9] == [("go", "/drive"), ("dock", "/dock")]
    assert a.finding_count == 3
    text = to_text(a, [])
    assert "X9  Every mapped output node (a probe): 2\n  go at /drive\n  dock at /dock\n" in text, text
    assert text.index("E1  ") < text.index("X9  ") < text.index("E2  ")
    assert "## X9: Every mapped output node (a probe)\n\n| Output | Node |\n|---|---|\n| go | /drive |" in \
        to_markdown(a, [])
    report = json.loads(json.dumps(to_dict(a, [])))
    assert report["X9"] == [{"output": "go", "node": "/drive"}, {"output": "dock", "node": "/dock"}]
    assert {"code": "X9", "title": "Every mapped output node (a probe)", "severity": "warning",
            "explanation": "only for the test", "ran": True} in report["checks"]
    result = AnalysisResult(None, a, [], [], None)
    assert result.tables()["X9"].rows == [["go", "/drive"], ["dock", "/dock"]]
    assert result.counts()["X9"] == 2 and "X9 2" in result.summary()
