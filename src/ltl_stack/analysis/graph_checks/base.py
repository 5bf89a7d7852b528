"""What a graph check declares (``GraphCheck``) and what its search may share with the others
(``Context``). Each check is one module of ``graph_checks`` with a ``CHECK``; the package finds them."""
from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass, field
from typing import Any

from ltl_stack.analysis.result import Analysis, Witness
from ltl_stack.runtime.config.mapping import Mapping

#: How a finding is graded: an ERROR is a wiring mistake to fix first, a WARNING a place to look at.
ERROR, WARNING = "error", "warning"


@dataclass
class Context:
    """What ``checks.analyze`` knows besides the ``Analysis``: the mapping, the resolved input topics,
    the proposition topics not crossed (``blocked`` vertices), the relays followed, and a memo so
    that two checks that need one computation (E2 and E3, C1 and C2) make it once."""

    mapping: Mapping
    in_topics: dict[str, str]
    blocked: Collection[int] = ()
    relays: Collection[int] = ()
    _memo: dict[str, Any] = field(default_factory=dict)

    def once(self, key: str, compute: Callable[[], Any]) -> Any:
        if key not in self._memo:
            self._memo[key] = compute()
        return self._memo[key]


def no_witnesses(_finding: Any) -> tuple[list[Witness], set[str]]:
    return [], set()


@dataclass(frozen=True)
class GraphCheck:
    """One check of the ROS computation graph (thesis §3.5.2).

    ``code`` and ``title`` head its report section, panel tab and JSON key; ``severity`` grades its
    findings; ``explanation`` says what a finding means and what to do. ``find(analysis, context)``
    returns the findings. ``columns`` and ``rows(finding, markdown)`` make its table (the Markdown
    report quotes chains as code), ``lines(finding)`` its text lines, ``witnesses(finding)`` the chains
    and the channels or nodes in conflict that the panel draws. ``order`` places it in reports and the
    panel; ``needs_robots``: it runs only with a list of robots. ``text_block`` replaces the text lines
    of all findings at once (E2 folds channels where the same pairs compete)."""

    code: str
    title: str
    severity: str
    explanation: str
    find: Callable[[Analysis, Context], list[Any]]
    columns: tuple[str, ...]
    rows: Callable[[Any, bool], list[list[str]]]
    lines: Callable[[Any], list[str]]
    order: int
    witnesses: Callable[[Any], tuple[list[Witness], set[str]]] = no_witnesses
    needs_robots: bool = False
    text_block: Callable[[Sequence[Any]], list[str]] | None = None

    def applies(self, analysis: Analysis) -> bool:
        """Whether the check ran (and its section is shown) for ``analysis``."""
        return bool(analysis.robots) or not self.needs_robots

    def text_lines(self, findings: Sequence[Any]) -> list[str]:
        """The lines under the check's heading in the text report."""
        if self.text_block is not None:
            return self.text_block(findings)
        return ["  " + line for f in findings for line in self.lines(f)]


__all__ = ["ERROR", "WARNING", "Context", "GraphCheck", "no_witnesses"]
