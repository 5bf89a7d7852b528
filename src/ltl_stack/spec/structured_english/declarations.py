"""The declaration lines of a Structured English file (``Sensors:``, ``Actions:``, ``Actions with
completion:``, ``Memory:``, ``Regions:``, ``Map:``) and what they introduce: the ``Declarations``, and
the clauses the conventions of [75] generate from them (region topology, durative actions)."""
from __future__ import annotations

import difflib
import re
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.inputs import read_text
from ltl_stack.spec.activation_completion import (
    ACTION_COMPLETION,
    REGION_COMPLETION,
    action_clauses,
    place_clauses,
    region_clauses,
)
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.region_map import RegionTopology, complete_topology, parse_region_map
from ltl_stack.spec.structured_english.vocabulary import KEYWORDS

DECLARATION = re.compile(r"^\s*(?P<key>[A-Za-z][A-Za-z' ]*?)\s*:(?P<rest>.*)$")
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")

DECLARATION_KINDS = {
    "sensors": "sensors", "sensor": "sensors",
    "actions": "actions", "action": "actions",
    "actions with completion": "completion_actions", "action with completion": "completion_actions",
    "memory": "memory", "memories": "memory", "memory propositions": "memory",
    "regions": "regions", "region": "regions",
    "map": "map", "region map": "map",
    # Hook for the negotiation of several robots: the names and meaning of other robots'
    # propositions are defined there; until then the keyword is reserved and refused clearly.
    "other robots": "other_robots", "other robot": "other_robots",
}


@dataclass
class Declarations:
    """What the declarations of an English spec introduce, by kind, and where."""

    sensors: list[str] = field(default_factory=list)
    actions: list[str] = field(default_factory=list)
    completion_actions: list[str] = field(default_factory=list)
    memory: list[str] = field(default_factory=list)
    regions: list[str] = field(default_factory=list)
    topology: RegionTopology | None = None
    kind_of: dict[str, str] = field(default_factory=dict)  # name -> sensor/action/completion/memory/region
    line_of: dict[str, int] = field(default_factory=dict)  # declaration kind -> its (first) line
    #: LTLMoP's region model (a project file without ``fastslow``): a region is a robot proposition
    #: saying where the robot is, moved between neighbours in one step; no ``R_rc``
    regions_are_places: bool = False
    #: ``group X is a, b`` (and its singular, as LTLMoP allows): the members, by group name
    groups: dict[str, list[str]] = field(default_factory=dict)
    #: sentences made so far by repeating one per group member (``visit all rooms``)
    repeated: int = 0
    #: propositions a project lists but disables (``name, 0``), with their kind
    disabled: dict[str, str] = field(default_factory=dict)
    #: a region name that stands for several pieces of the map (LTLMoP's decomposition when regions
    #: overlap, ``between``/``near`` areas): the pieces, which are the ``regions``
    areas: dict[str, list[str]] = field(default_factory=dict)

    def is_region(self, name: str) -> bool:
        return name in self.areas or name in self.regions

    @property
    def inputs(self) -> list[str]:
        places = [] if self.regions_are_places else [r + REGION_COMPLETION for r in self.regions]
        return [*self.sensors, *(a + ACTION_COMPLETION for a in self.completion_actions), *places]

    @property
    def outputs(self) -> list[str]:
        return [*self.actions, *self.completion_actions, *self.memory, *self.regions]

    def completion(self, name: str) -> str | None:
        """``a_ac`` for a durative action, ``R_rc`` for a region (``R`` itself in LTLMoP's region
        model), else None."""
        if name in self.regions:
            return name if self.regions_are_places else name + REGION_COMPLETION
        if name in self.completion_actions:
            return name + ACTION_COMPLETION
        return None


@dataclass
class EnglishSpec:
    """A read English spec: the GR(1) ``spec``, the declarations, and the sentences by line."""

    spec: Spec
    declarations: Declarations
    sentences: dict[int, str]



def declare(decl: Declarations, m: re.Match, number: int, body: str, file: str, base_dir: Path) -> None:
    """The declaration line ``body`` (line ``number``, matched by ``DECLARATION`` as ``m``) into ``decl``."""
    key = " ".join(m["key"].lower().split())
    column = body.index(m["key"][0]) + 1
    kind = DECLARATION_KINDS.get(key)
    if kind is None:
        known = ["Sensors", "Actions", "Actions with completion", "Memory", "Regions", "Map", "Other robots"]
        close = difflib.get_close_matches(key, list(DECLARATION_KINDS), n=1, cutoff=0.6)
        hint = f"; did you mean '{close[0].capitalize()}:'?" if close else ""
        raise SpecError(file, number, column, f"unknown declaration '{m['key'].strip()}:'; expected one of "
                                              f"{', '.join(k + ':' for k in known)}{hint}")
    rest_column = m.start("rest") + 1
    rest = m["rest"]
    if kind == "other_robots":
        raise SpecError(file, number, column, "'Other robots:' is reserved for propositions shared by other "
                                              "robots (multi-robot negotiation), which are not defined yet")
    if (kind == "map" and "regions" in decl.line_of) or (kind == "regions" and "map" in decl.line_of):
        raise SpecError(file, number, column, "declare regions either with 'Regions:' or with 'Map:', not both")
    decl.line_of.setdefault(kind, number)
    if kind == "map":
        _declare_map(decl, rest.strip(), number, rest_column + len(rest) - len(rest.lstrip()), file, base_dir)
        return
    for name, col in _names(rest, rest_column):
        _add(decl, kind, name, number, col, file)


def _names(rest: str, column: int) -> list[tuple[str, int]]:
    """The names of a declaration line; ``and`` joins two of them (``a, b and c``), anywhere else it
    is kept as a name (and then refused as a word of the sentences: ``Sensors: and``)."""
    found = [(m.group(), column + m.start()) for m in re.finditer(r"[^\s,]+", rest)]
    out = []
    for i, (word, col) in enumerate(found):
        joins = 0 < i < len(found) - 1 and found[i - 1][0].lower() != "and" and found[i + 1][0].lower() != "and"
        if word.lower() == "and" and joins:
            continue
        out.append((word, col))
    return out


def article(word: str) -> str:
    """``a``/``an`` and ``word``."""
    return ("an " if word[:1] in "aeiou" else "a ") + word


KIND_WORD = {"sensors": "sensor", "actions": "action", "completion_actions": "action with completion",
              "memory": "memory proposition", "regions": "region"}


def _add(decl: Declarations, kind: str, name: str, number: int, column: int, file: str) -> None:
    if name.endswith("."):
        name = name[:-1]
    if not _NAME.match(name):
        raise SpecError(file, number, column, f"invalid name '{name}': a name is a letter or '_' followed by "
                                              "letters, digits or '_'")
    if name.lower() in KEYWORDS:
        raise SpecError(file, number, column, f"'{name}' is a word of the sentences and cannot name a proposition")
    generated = {}
    if kind == "completion_actions":
        generated[name + ACTION_COMPLETION] = f"the completion of action {name}"
    if kind == "regions":
        generated[name + REGION_COMPLETION] = f"the completion of region {name}"
    for new in (name, *generated):
        if new in decl.kind_of:
            first = decl.kind_of[new]
            raise SpecError(file, number, column, f"'{new}' is declared twice (first as {KIND_WORD.get(first, first)})")
    getattr(decl, kind).append(name)
    decl.kind_of[name] = kind
    for new in generated:
        decl.kind_of[new] = "completions"


def add_declaration(decl: Declarations, kind: str, name: str, line: int, column: int, file: str) -> None:
    """Declare ``name`` as a ``kind`` (sensors, actions, completion_actions, memory, regions), with the
    checks of a declaration line (for readers of other containers, such as LTLMoP project files)."""
    _add(decl, kind, name, line, column, file)


def _declare_map(decl: Declarations, path_text: str, number: int, column: int, file: str, base_dir: Path) -> None:
    if not path_text:
        raise SpecError(file, number, column, "expected the path of an LTLMoP .regions file after 'Map:'")
    if decl.topology is not None:
        raise SpecError(file, number, column, "only one 'Map:' per spec")
    path = base_dir / path_text
    try:
        text = read_text(path, "region map", max_bytes=16 * 1024 * 1024)
    except InputError as e:
        raise SpecError(file, number, column, f"cannot read the map: {e}") from None
    try:
        topology = parse_region_map(text, str(path))
    except SpecError as e:
        raise SpecError(file, number, column, f"in the map: {e}") from None
    if not topology.regions:
        raise SpecError(file, number, column, f"the map {path_text} has no regions")
    for region in topology.regions:
        _add(decl, "regions", region, number, column, file)
    decl.topology = topology


def add_conventions(decl: Declarations, sections: dict[str, list[Clause]], file: str) -> None:
    """The generated clauses of [75]: regions (with topology) and durative actions."""
    if decl.regions:
        if decl.topology is None:
            decl.topology = complete_topology(decl.regions)
        origin = "Map" if "map" in decl.line_of else "Regions"
        line = decl.line_of.get("map", decl.line_of.get("regions", 0))
        generate = place_clauses if decl.regions_are_places else region_clauses
        for section, clauses in generate(decl.topology, file, line, origin).items():
            sections[section].extend(clauses)
    if decl.completion_actions:
        line = decl.line_of["completion_actions"]
        for section, clauses in action_clauses(decl.completion_actions, file, line,
                                               "Actions with completion").items():
            sections[section].extend(clauses)

