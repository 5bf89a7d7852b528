"""The explicit strategy automaton (thesis Def. 4.3.2) and its file formats.

- our JSON (schema in ``docs/strategy_json.md``): ``to_json`` / ``from_json``;
- slugs' ``--explicitStrategy --jsonOutput`` layout (``version``, ``slugs``, ``variables``, ``nodes``
  keyed by state number with ``rank``, ``state`` bit list and ``trans``): ``to_slugs_json`` /
  ``from_slugs_json``;
- Graphviz DOT (``to_dot``) and PNG through the ``dot`` program (``to_png``).

Recovery transitions (thesis §4.6, ``explicit(recovery=True)``) are ordinary successors that are
also listed in ``AutomatonState.recovery``: key ``recovery`` of a state (our JSON) or node (slugs
layout; slugs' own tools ignore it), dashed edges in DOT.

``Automaton.load(path)`` reads either JSON layout (through ``ltl_stack.inputs.load_json``; a file
that is not such a strategy is a ``StrategyFileError`` naming it, exit 2);
``automaton_check.load_checked(path, spec)`` also checks it against a spec. Files are written atomically (``write_atomic``).
"""
from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.inputs import load_json
from ltl_stack.synthesis.errors import StrategyFileError

FORMAT = "ltl_stack-strategy"
DOT_LAYOUT_LIMIT = 100
VERSION = 1


def goal_text(goal: int, goals: int | None = None) -> str:
    """A system goal as every display numbers it: from 1, as the thesis numbers the system liveness goals
    (``k/n`` when the number of goals ``n`` is known; "-" for none, before the first state). Machine-readable
    outputs (``goal_index`` on ``~state``, JSON) keep the index from 0."""
    if goal < 0:
        return "-"
    return f"{goal + 1}/{goals}" if goals else str(goal + 1)


@dataclass
class AutomatonState:
    id: int
    inputs: dict[str, bool]
    outputs: dict[str, bool]
    goal: int
    successors: list[int] = field(default_factory=list)
    #: the successors reached by recovery transitions (a subset of ``successors``)
    recovery: list[int] = field(default_factory=list)


@dataclass
class Automaton:
    """States (ids ``0..n-1``), the initial ones, and what they were synthesized from."""

    inputs: list[str]
    outputs: list[str]
    states: list[AutomatonState]
    initial: list[int]
    goals: int = 1
    metadata: dict = field(default_factory=dict)
    #: the file it was loaded from ("" when made in memory); not part of the JSON
    path: str = field(default="", compare=False)

    def __len__(self) -> int:
        return len(self.states)

    def find(self, inputs: dict[str, bool], outputs: dict[str, bool], goal: int) -> AutomatonState | None:
        """The state with this valuation and goal, if any."""
        index = self.__dict__.get("_index")
        if index is None:
            index = {self._key(s.inputs, s.outputs, s.goal): s for s in self.states}
            self.__dict__["_index"] = index
        return index.get(self._key(inputs, outputs, goal))

    def _key(self, inputs, outputs, goal):
        return (tuple(bool(inputs[n]) for n in self.inputs),
                tuple(bool(outputs[n]) for n in self.outputs), goal)

    # --- our JSON ------------------------------------------------------------------------
    def to_json(self) -> dict:
        def state(s: AutomatonState) -> dict:
            data = {"id": s.id, "goal": s.goal,
                    "inputs": {n: bool(s.inputs[n]) for n in self.inputs},
                    "outputs": {n: bool(s.outputs[n]) for n in self.outputs},
                    "successors": list(s.successors)}
            if s.recovery:
                data["recovery"] = list(s.recovery)
            return data
        return {
            "format": FORMAT,
            "version": VERSION,
            "inputs": list(self.inputs),
            "outputs": list(self.outputs),
            "goals": self.goals,
            "initial": list(self.initial),
            "metadata": dict(self.metadata),
            "states": [state(s) for s in self.states],
        }

    @classmethod
    def from_json(cls, data: dict) -> Automaton:
        if data.get("format") != FORMAT:
            raise ValueError(f"not an {FORMAT} document (format={data.get('format')!r})")
        if data.get("version") != VERSION:
            raise ValueError(f"unsupported {FORMAT} version {data.get('version')!r}; expected {VERSION}")
        states = [AutomatonState(int(s["id"]), dict(s["inputs"]), dict(s["outputs"]), int(s["goal"]),
                                 [int(t) for t in s["successors"]], [int(t) for t in s.get("recovery", [])])
                  for s in data["states"]]
        return cls(list(data["inputs"]), list(data["outputs"]), states, [int(i) for i in data["initial"]],
                   int(data.get("goals", 1)), dict(data.get("metadata", {})))

    # --- slugs' JSON ---------------------------------------------------------------------
    def to_slugs_json(self) -> dict:
        names = [*self.inputs, *self.outputs]
        nodes = {}
        for s in self.states:
            bits = [int(bool(s.inputs[n])) for n in self.inputs] + \
                [int(bool(s.outputs[n])) for n in self.outputs]
            nodes[str(s.id)] = {"rank": s.goal, "state": bits, "trans": list(s.successors)}
            if s.recovery:
                nodes[str(s.id)]["recovery"] = list(s.recovery)
        return {"version": 0, "slugs": "0.0.1", "variables": names, "nodes": nodes}

    @classmethod
    def from_slugs_json(cls, data: dict, inputs: list[str] | None = None) -> Automaton:
        """Read slugs' layout. It does not say which variables are inputs (pass ``inputs``; default
        none) nor which states are initial: states that no transition enters are taken as initial
        (the first state when every state is entered)."""
        names = list(data["variables"])
        inputs = [n for n in names if n in set(inputs or [])]
        outputs = [n for n in names if n not in set(inputs)]
        states = []
        targets = set()
        for key, node in sorted(data["nodes"].items(), key=lambda kv: int(kv[0])):
            values = dict(zip(names, (bool(b) for b in node["state"])))
            succ = [int(t) for t in node["trans"]]
            targets.update(succ)
            states.append(AutomatonState(int(key), {n: values[n] for n in inputs},
                                         {n: values[n] for n in outputs}, int(node["rank"]), succ,
                                         [int(t) for t in node.get("recovery", [])]))
        initial = [s.id for s in states if s.id not in targets] or ([states[0].id] if states else [])
        goals = max((s.goal for s in states), default=0) + 1
        return cls(inputs, outputs, states, initial, goals, {"source_format": "slugs"})

    @classmethod
    def load(cls, path: str | Path, inputs: list[str] | None = None) -> Automaton:
        """Read our JSON or slugs' layout (``inputs`` names the inputs of the latter). Problems are
        ``StrategyFileError`` naming the file; ``automaton_check.load_checked`` also checks a spec."""
        file = str(path)
        try:
            data = load_json(path, "strategy file")
        except InputError as e:
            raise StrategyFileError(str(e)) from None
        try:
            if isinstance(data, dict) and data.get("format") == FORMAT:
                automaton = cls.from_json(data)
            elif isinstance(data, dict) and "nodes" in data and "variables" in data:
                automaton = cls.from_slugs_json(data, inputs)
            else:
                raise ValueError(f"neither an {FORMAT} nor a slugs strategy JSON file")
        except (KeyError, TypeError, ValueError, AttributeError) as e:
            detail = f"missing field {e}" if isinstance(e, KeyError) else str(e)
            raise StrategyFileError(f"{file}: not a usable strategy file: {detail}") from None
        automaton.path = file
        return automaton

    # --- Graphviz -------------------------------------------------------------------------
    def to_dot(self, name: str = "strategy") -> str:
        """States labelled with their id, goal and true outputs; edges with the true inputs that
        lead there (the thesis' Fig. 3.1 convention); recovery edges dashed."""
        lines = [f"digraph {_dot_id(name)} {{", "  rankdir=LR;", "  node [shape=box, fontname=Helvetica];",
                 "  edge [fontname=Helvetica, fontsize=10];"]
        initial = set(self.initial)
        for s in self.states:
            outs = ", ".join(n for n in self.outputs if s.outputs[n]) or "-"
            style = ", peripheries=2" if s.id in initial else ""
            lines.append(f'  s{s.id} [label="{s.id} (goal {goal_text(s.goal)})\\n{_esc(outs)}"{style}];')
        by_id = {s.id: s for s in self.states}
        for s in self.states:
            recovery = set(s.recovery)
            for t in s.successors:
                ins = ", ".join(n for n in self.inputs if by_id[t].inputs[n]) or "-"
                style = ", style=dashed" if t in recovery else ""
                lines.append(f'  s{s.id} -> s{t} [label="{_esc(ins)}"{style}];')
        lines.append("}")
        return "\n".join(lines) + "\n"

    def to_png(self, timeout: float = 120.0) -> bytes:
        """Render with Graphviz (raises ``RuntimeError`` when it is missing, fails or times out).

        ``dot`` lays out small automata; beyond ``DOT_LAYOUT_LIMIT`` states it takes minutes, so
        ``sfdp`` (force-directed) is used instead.
        """
        program = "dot" if len(self.states) <= DOT_LAYOUT_LIMIT else "sfdp"
        exe = shutil.which(program)
        if exe is None:
            raise RuntimeError(f"Graphviz '{program}' is not installed; cannot write a PNG (write --dot instead)")
        try:
            data = subprocess.run([exe, "-Tpng", "-Goverlap=prism"], input=self.to_dot().encode(),
                                  capture_output=True, check=False, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise RuntimeError(f"{program} did not finish in {timeout:.0f} s ({len(self.states)} states); "
                               "write --dot and render a part of it") from None
        if data.returncode != 0:
            raise RuntimeError(f"{program} failed: {data.stderr.decode(errors='replace').strip()}")
        return data.stdout


def _esc(text: str) -> str:
    return text.replace("\\", "\\\\").replace('"', '\\"')


def _dot_id(name: str) -> str:
    return '"' + _esc(name) + '"'
