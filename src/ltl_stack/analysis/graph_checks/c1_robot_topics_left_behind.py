"""C1 (thesis §3.5.2.5, Fig. 3.14): for one output, a robot topic ``/<robot>/<suffix>`` is reached for
some robots of the user's list but not for all."""
from __future__ import annotations

from dataclasses import dataclass

from ltl_stack.analysis.graph_checks import c2_uncontrolled_robots
from ltl_stack.analysis.graph_checks.base import WARNING, Context, GraphCheck
from ltl_stack.analysis.graph_checks.robot_topics import robot_topics
from ltl_stack.analysis.result import Analysis, Witness


@dataclass(frozen=True)
class C1Finding:
    """For ``output``, the robot topic ``/<robot><suffix>`` is reached for ``present`` robots only."""

    output: str
    suffix: str
    present: tuple[tuple[str, Witness], ...]
    missing: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"output": self.output, "suffix": self.suffix, "missing": list(self.missing),
                "present": [{"robot": r, **w.to_dict()} for r, w in self.present]}


def find(a: Analysis, context: Context) -> list[C1Finding]:
    """Per output: robot topics reached for some robots of the list but not all. The robots C2 reports
    as not controlled at all are not repeated here."""
    skip = {f.robot for f in c2_uncontrolled_robots.find(a, context)}
    considered = [r for r in a.robots if r not in skip]
    found = []
    for y in a.outputs:
        for suffix, by_robot in sorted(robot_topics(a, y).items()):
            missing = tuple(r for r in considered if r not in by_robot)
            if not missing:
                continue
            present = tuple((r, a.witness(y, node, v)) for r in a.robots if r in by_robot
                            for node, v in [by_robot[r]])
            found.append(C1Finding(y, suffix, present, missing))
    return found


def rows(f: C1Finding, markdown: bool) -> list[list[str]]:
    cells = [(r, f"`{w.text}`" if markdown else w.text) for r, w in f.present]
    cells += [(r, "—" if markdown else "— (missing)") for r in f.missing]
    return [[f.output if i == 0 else "", f.suffix if i == 0 else "", robot, chain]
            for i, (robot, chain) in enumerate(cells)]


def lines(f: C1Finding) -> list[str]:
    return [f"{f.output} {f.suffix}: missing for {', '.join(f.missing)}",
            *(f"  {r}: {w.text}" for r, w in f.present), *(f"  {r}: -" for r in f.missing)]


def witnesses(f: C1Finding) -> tuple[list[Witness], set[str]]:
    return [w for _r, w in f.present], {w.path[-1][1] for _r, w in f.present}


CHECK = GraphCheck(
    code="C1", title="Robot topics left behind: reached for some robots but not all (thesis 3.5.2.5)",
    severity=WARNING,
    explanation="An output drives a topic of some robots of the list but not of the others: the others "
                "will not do what the specification says they do.",
    find=find, columns=("Output", "Topic", "Robot", "One existing chain"), rows=rows, lines=lines, order=40,
    witnesses=witnesses, needs_robots=True)
