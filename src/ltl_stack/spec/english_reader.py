"""Read tasks written in Structured English (LTLMoP's sentences, [46]) into the GR(1) ``Spec``.

A file has declarations (``Keyword: names``) and one sentence per line, as in the thesis::

    Sensors: person
    Actions: move, stop
    Always move.
    If you are sensing person then do stop.

Declarations: ``Sensors:`` (environment inputs), ``Actions:`` (robot outputs that act at once),
``Actions with completion:`` (the robot activates ``a``, the environment reports ``a_ac``),
``Memory:`` (robot propositions kept by ``is set on … and reset on …``), ``Regions:`` (names;
every region touches every other) or ``Map:`` (an LTLMoP ``.regions`` file, relative to the spec,
whose adjacency becomes the topology). Regions get ``R`` (head for R) and ``R_rc`` (in R).
``Other robots:`` is reserved for the negotiation of several robots.

Sentences compile with the activation–completion encoding of [75] (``activation_completion``);
each clause keeps the sentence's text, file and line. The full grammar and what each sentence
compiles to are in ``docs/spec_formats.md`` (section "Structured English").

Time is LTLMoP's (``parseEnglishToLTL``; ``_Sentence._primed``, docs/spec_formats.md "Timing"): in
a safety sentence the present tense is the *next* state — the robot reacts to what it is sensing
now — and the past tense (``you were in``, ``you sensed``) the current one; a name without a phrase
in a condition is the current state; a memory's events read sensors next and the robot's own
propositions now. In goals and initial conditions everything is the current state.

LTLMoP project files (``======== SETTINGS ========`` …) are read by ``ltlmop_project`` into the same
``Declarations`` and sentences.

The reader is iterative (an operator-precedence loop), so nesting depth costs no stack, and each
line is read once: time and memory are linear in the size of the file.
"""
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
    at_most_one,
    place_clauses,
    region_clauses,
)
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import FALSE, TRUE, And, Formula, Iff, Implies, Not, Or, Var, walk
from ltl_stack.spec.model import SECTIONS, Clause, Spec
from ltl_stack.spec.ops import Pending, settle
from ltl_stack.spec.region_map import RegionTopology, complete_topology, parse_region_map

ENGLISH_SUFFIXES = (".spec", ".english")
#: sentences ``all G`` / ``each G`` may make in one spec, one per member (100 sentences ``visit all G``
#: over a group of 2,000 regions made 200,000 goals: minutes before synthesis printed anything)
MAX_REPEATED = 10_000

# Words of the sentences; a proposition may not be called one of these.
KEYWORDS = frozenset("""
and or not if then only unless always never assume do visit go to infinitely often you the robot it
are is were was have has had did sensing sensed sense activating activated activate in finished finish
set reset on start starts with environment env true false mutually exclusive together
""".split())

_COMMENT = re.compile(r"(^|\s)#")
_DECLARATION = re.compile(r"^\s*(?P<key>[A-Za-z][A-Za-z' ]*?)\s*:(?P<rest>.*)$")
_TOKEN = re.compile(r"(?P<space>\s+)|(?P<word>[A-Za-z_][A-Za-z0-9_]*)|(?P<number>\d+(?:\.\d+)?)|(?P<punct>[(),.])")
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")

DECLARATION_KINDS = {
    "sensors": "sensors", "sensor": "sensors",
    "actions": "actions", "action": "actions",
    "actions with completion": "completion_actions", "action with completion": "completion_actions",
    "memory": "memory", "memories": "memory", "memory propositions": "memory",
    "regions": "regions", "region": "regions",
    "map": "map", "region map": "map",
    # Hook for the negotiation of several robots (issue 13): the names and meaning of other robots'
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


def has_section_headers(text: str) -> bool:
    """Does the first line that is not blank or a comment start with '[' (a slugs-format file)?"""
    for raw in text.splitlines():
        m = _COMMENT.search(raw)
        body = (raw[:m.start()] if m else raw).strip()
        if body:
            return body.startswith("[")
    return False


def read_sentences(text: str, file: str, base_dir: Path) -> EnglishSpec:
    """A plain Structured English file (declarations, then sentences): its spec, declarations and
    sentences. ``english_files.read_english`` is the entry that also takes LTLMoP project files."""
    lines = []
    for number, raw in enumerate(text.splitlines(), start=1):
        m = _COMMENT.search(raw)
        body = (raw[:m.start()] if m else raw).rstrip()
        if body.strip():
            lines.append((number, body))
    decl = Declarations()
    sentences: list[tuple[int, str]] = []
    for number, body in lines:
        m = _DECLARATION.match(body)
        if m:
            _declare(decl, m, number, body, file, Path(base_dir))
        else:
            sentences.append((number, body))
    return compile_sentences(decl, sentences, file)


def is_ltlmop_project(text: str) -> bool:
    """Is ``text`` an LTLMoP project file (its ``======== SETTINGS ========`` container)?"""
    return re.search(r"^=+ *(SETTINGS|SPECIFICATION) *=+\s*$", text, re.MULTILINE) is not None


def compile_sentences(decl: Declarations, sentences: list[tuple[int, str]], file: str,
                      clauses: dict[str, list[Clause]] | None = None) -> EnglishSpec:
    """The spec of ``sentences`` (line, text) over ``decl`` (after ``clauses`` already read, by
    section), with the generated conventions."""
    sections: dict[str, list[Clause]] = {name: list((clauses or {}).get(name, [])) for name in SECTIONS}
    for number, body in sentences:
        reader = _Sentence(body, number, file, decl)
        for section, formula in reader.compile():
            sections[section].append(Clause(formula, body.strip(), file, number))
    _add_conventions(decl, sections, file)
    spec = Spec(inputs=decl.inputs, outputs=decl.outputs, source=file, **sections)
    if decl.topology is not None:
        spec.warnings.extend(decl.topology.warnings)
    return EnglishSpec(spec, decl, dict(sentences))


# -- declarations ------------------------------------------------------------------------------

def _declare(decl: Declarations, m: re.Match, number: int, body: str, file: str, base_dir: Path) -> None:
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


def _article(word: str) -> str:
    return ("an " if word[:1] in "aeiou" else "a ") + word


_KIND_WORD = {"sensors": "sensor", "actions": "action", "completion_actions": "action with completion",
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
            raise SpecError(file, number, column, f"'{new}' is declared twice (first as {_KIND_WORD.get(first, first)})")
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


def _add_conventions(decl: Declarations, sections: dict[str, list[Clause]], file: str) -> None:
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


# -- sentences ---------------------------------------------------------------------------------

class _Token:
    __slots__ = ("kind", "text", "column", "low")

    def __init__(self, kind: str, text: str, column: int):
        self.kind = kind  # word ( ) , .
        self.text = text
        self.column = column
        self.low = text.lower()


@dataclass(frozen=True)
class _Phrase:
    """``you are sensing``, ``you were in``, ``finished``, ``do not`` …: how the names after it read."""

    completion: bool  # names read as their completion (R_rc, a_ac)
    past: bool
    negated: bool
    length: int
    text: str
    #: ``sensing`` / ``sensed``: the name right after it must be an input
    sensing: bool = False


def _phrase_table() -> dict[tuple[str, ...], tuple[bool, bool, bool]]:
    """word sequence -> (completion, past, negated)."""
    verbs: dict[str, tuple[bool, bool, bool]] = {}
    for be, past in (("are", False), ("is", False), ("were", True), ("was", True)):
        for neg in (False, True):
            n = " not" if neg else ""
            verbs[f"{be}{n} sensing"] = (False, past, neg)
            verbs[f"{be}{n} activating"] = (False, past, neg)
            verbs[f"{be}{n} in"] = (True, past, neg)
    for have, past in (("have", False), ("has", False), ("had", True)):
        verbs[f"{have} finished"] = (True, past, False)
        verbs[f"{have} not finished"] = (True, past, True)
    verbs.update({"sensed": (False, True, False), "did not sense": (False, True, True),
                  "activated": (False, True, False), "did not activate": (False, True, True)})
    table: dict[tuple[str, ...], tuple[bool, bool, bool]] = {}
    for subject in ("", "you ", "the robot ", "robot ", "it "):
        for verb, meaning in verbs.items():
            table[tuple((subject + verb).split())] = meaning
    table[("finished",)] = (True, False, False)
    table[("do",)] = (False, False, False)
    table[("do", "not")] = (False, False, True)
    return table


PHRASES = _phrase_table()
_SENSING = ("sensing", "sensed", "sense")
_LONGEST_PHRASE = max(len(k) for k in PHRASES)
_PHRASE_STARTS = frozenset(k[0] for k in PHRASES)
_BINARY = {"and": 2, "or": 1}

# Sentence forms for "did you mean …": names become <kind> placeholders.
TEMPLATES = [
    "always <p>", "never <p>", "do <action>",
    "if you are sensing <sensor> then do <action>", "if you are not sensing <sensor> then do <action>",
    "if you are activating <p> then do <action>", "if you are in <region> then do <action>",
    "if you were in <region> then do <action>", "if you have finished <action> then do <action>",
    "do <action> if and only if you are sensing <sensor>", "do <action> unless you are sensing <sensor>",
    "visit <region>", "go to <region>", "if you are sensing <sensor> then visit <region>",
    "infinitely often <p>", "<memory> is set on <sensor> and reset on finished <action>",
    "start in <region>", "robot starts with <action>", "environment starts with <sensor>",
    "assume always <p>", "<p> and <p> are mutually exclusive",
]
#: LTLMoP's forms that need its geometry or its internal memories, named when refused
UNSUPPORTED = (
    (("between",), "'between R1 and R2' (a region LTLMoP computes from the map's geometry)"),
    (("within",), "'within N of R' (a region LTLMoP computes from the map's geometry)"),
    (("near",), "'near R' (a region LTLMoP computes from the map's geometry)"),
    (("at", "least", "once"), "'at least once' (LTLMoP's generated memory propositions)"),
    (("after", "each", "time"), "'after each time' (LTLMoP's generated memory propositions)"),
)
#: words a hint may put in place of a misspelt one
VOCABULARY = sorted(KEYWORDS | {"stay", "there", "group", "toggled", "when", "of", "end", "beginning", "all", "any",
                                "each", "sense", "than"} - {"than"})
_PLACEHOLDER = {"sensors": "<sensor>", "actions": "<action>", "completion_actions": "<action>",
                "memory": "<memory>", "regions": "<region>", "completions": "<p>"}


class _Sentence:
    """One sentence line: tokens, the sentence forms, and the expression reader."""

    def __init__(self, body: str, line: int, file: str, decl: Declarations):
        self.body = body
        self.line = line
        self.file = file
        self.decl = decl
        self.tokens = self._tokenize()

    def error(self, column: int, message: str, form: bool = False) -> SpecError:
        """``form``: the sentence's shape is wrong, so the closest sentence form is suggested."""
        error = SpecError(self.file, self.line, column, message)
        error.form = form
        return error

    def _tokenize(self) -> list[_Token]:
        out = []
        position = 0
        text = self.body
        while position < len(text):
            m = _TOKEN.match(text, position)
            if not m:
                raise self.error(position + 1, f"unexpected character {text[position]!r} (a sentence has words, "
                                               "parentheses, commas and a final period)")
            if m.lastgroup != "space":
                kind = m.lastgroup if m.lastgroup in ("word", "number") else m.group()
                out.append(_Token(kind, m.group(), position + 1))
            position = m.end()
        while out and out[-1].kind == ".":
            out.pop()
        for t in out:
            if t.kind == ".":
                raise self.error(t.column, "a period ends a sentence; write one sentence per line")
        return out

    # -- sentence forms ---------------------------------------------------------------------

    def compile(self, hints: bool = True) -> list[tuple[str, Formula]]:
        try:
            return self._quantified()
        except SpecError as e:
            hint = self._closest_form(e) if hints and getattr(e, "form", False) else None
            if hint and "did you mean" not in e.message:
                raise SpecError(e.file, e.line, e.column, f"{e.message}; did you mean '{hint}'?") from None
            raise

    def _quantified(self) -> list[tuple[str, Formula]]:
        """``all X`` / ``each X`` / ``any X`` over a group (one per sentence, as in LTLMoP's
        ``parseEnglishToLTL``): in a condition, a memory or toggle event or a start, ``all`` is the
        members' conjunction and ``any`` their disjunction; elsewhere ``any`` is the disjunction
        and ``all``/``each`` repeat the sentence once per member (``visit all rooms``)."""
        toks = self.tokens
        self._refuse_unsupported(toks)
        at = next((i for i, t in enumerate(toks[:-1]) if t.low in ("all", "any", "each")
                   and toks[i + 1].text in self.decl.groups and t.text not in self.decl.kind_of), None)
        if at is None:
            loose = next((t for i, t in enumerate(toks[:-1]) if t.low in ("all", "any", "each")
                          and toks[i + 1].kind == "word" and toks[i + 1].text not in self.decl.kind_of
                          and toks[i + 1].low not in KEYWORDS and t.text not in self.decl.kind_of), None)
            if loose is not None:
                name = toks[toks.index(loose) + 1]
                groups = ", ".join(self.decl.groups) or "none defined"
                raise self.error(name.column, f"unknown group '{name.text}' after '{loose.text}' (define it first: "
                                              f"'group {name.text} is <region>, <region>'; groups: {groups})")
            return self._compile()
        members = self.decl.groups[toks[at + 1].text]
        column = toks[at].column
        if toks[at].low == "any" or self._in_condition(at):
            joiner = "or" if toks[at].low == "any" else "and"
            group: list[_Token] = [_Token("(", "(", column)]
            for k, member in enumerate(members):
                if k:
                    group.append(_Token("word", joiner, column))
                group.append(_Token("word", member, column))
            group = group + [_Token(")", ")", column)] if members else [_Token("word", "false", column)]
            self.tokens = toks[:at] + group + toks[at + 2:]
            try:
                return self._compile()
            finally:
                self.tokens = toks
        out: list[tuple[str, Formula]] = []
        self.decl.repeated += len(members)
        if self.decl.repeated > MAX_REPEATED:
            raise self.error(column, f"'{toks[at].text} {toks[at + 1].text}' repeats this sentence for each of "
                                     f"{len(members)} members: with the sentences before it, more than "
                                     f"{MAX_REPEATED:,} (the most a spec may make this way; a goal per member "
                                     "makes synthesis slow long before)")
        try:
            for member in members:
                self.tokens = toks[:at] + [_Token("word", member, column)] + toks[at + 2:]
                out.extend(self._compile())
        finally:
            self.tokens = toks
        return out

    def _in_condition(self, at: int) -> bool:
        """Is token ``at`` part of a condition (or an event, a start) rather than a requirement?"""
        words = [t.low for t in self.tokens]
        start = 1 if words[:1] in (["always"], ["assume"]) else 0
        if words[start:start + 1] == ["if"]:
            then = self._find(self.tokens, ("then",))
            return then is not None and at < then
        iff = self._find(self.tokens, ("if", "and", "only", "if"))
        if iff is not None:
            return at > iff
        unless = self._find(self.tokens, ("unless",))
        if unless is not None:
            return at > unless
        return "set" in words or "toggled" in words or "start" in words or "starts" in words

    def _compile(self) -> list[tuple[str, Formula]]:
        toks = self.tokens
        words = [t.low for t in toks]
        forced = None
        start = 0
        if words[:1] == ["assume"]:
            forced, start = "env", 1
            if len(toks) == 1:
                raise self.error(toks[0].column + 6, "expected a sentence after 'Assume'")
            if toks[1].kind == ",":
                start = 2
        rest = toks[start:]
        w = words[start:]
        if not rest:
            raise self.error(1, "expected a sentence")
        self._refuse_unsupported(rest)
        if w[0] == "group" and len(w) > 2 and w[2] in ("is", "are"):
            return self._group(rest)
        if len(w) >= 4 and w[1:3] == ["is", "toggled"] and w[3] in ("on", "when"):
            return self._toggle(rest, forced)
        if not forced and w[0] in ("visit", "go") and w[-3:] == ["and", "stay", "there"]:
            goals = self._visit(rest[:-3])
            return [*self._goals(goals, forced), *(("sys_safety", Implies(g, self._stay(rest[-2]))) for g in goals)]
        # initial conditions
        if w[:2] in (["environment", "starts"], ["env", "starts"], ["the", "environment"]):
            return self._environment_start(rest)
        subject = 1 if w[:1] in (["robot"], ["you"]) else 2 if w[:2] == ["the", "robot"] else 0
        if len(w) > subject and w[subject] in ("start", "starts"):
            return self._robot_start(rest, subject + 1, forced)
        # memory, mutual exclusion
        if len(w) >= 4 and w[1:4] == ["is", "set", "on"]:
            return self._memory(rest, forced)
        if w[-2:] == ["mutually", "exclusive"] or w[-3:] == ["never", "true", "together"]:
            return self._exclusive(rest, forced)
        # conditionals and the plain forms
        if w[0] == "always":
            skip = 2 if len(rest) > 1 and rest[1].kind == "," else 1
            if len(rest) == skip:
                raise self.error(rest[0].column + len(rest[0].text), "expected what is always true after 'always'")
            return self._statement(rest[skip:], forced, always=True)
        if w[0] == "never":
            if len(rest) == 1:
                raise self.error(rest[0].column + 5, "expected what never happens after 'never'")
            return [self._safety(Not(self._expr(rest[1:], "safety")), forced)]
        return self._statement(rest, forced, always=False)

    def _statement(self, toks: list[_Token], forced: str | None, always: bool) -> list[tuple[str, Formula]]:
        words = [t.low for t in toks]
        if words[0] == "if":
            then = self._find(toks, ("then",))
            if then is None:
                raise self.error(toks[-1].column + len(toks[-1].text), "expected 'then' after the condition of 'if'",
                                 form=True)
            condition = toks[1:then - 1] if toks[then - 1].kind == "," else toks[1:then]
            requirement = toks[then + 1:]
            if not condition:
                raise self.error(toks[then].column, "expected a condition between 'if' and 'then'")
            if not requirement:
                raise self.error(toks[then].column + 4, "expected what to do after 'then'")
            return self._conditional(condition, requirement, "if", forced, always)
        iff = self._find(toks, ("if", "and", "only", "if"))
        if iff is not None:
            return self._conditional(toks[iff + 4:], toks[:iff], "iff", forced, always, at=toks[iff])
        unless = self._find(toks, ("unless",))
        if unless is not None:
            return self._conditional(toks[unless + 1:], toks[:unless], "unless", forced, always, at=toks[unless])
        if not always and words[0] in ("visit", "go"):
            return self._goals(self._visit(toks), forced)
        if words in (["stay", "there"], ["stay"]):
            return [self._safety(self._stay(toks[0]), forced)]
        if not always and words[:2] == ["infinitely", "often"]:
            body = toks[2:]
            if not body:
                raise self.error(toks[1].column + 5, "expected what happens infinitely often")
            goal = self._expr(body, "goal")
            if forced is None and body[0].low != "do" and self._mentions_input(goal):
                forced = "env"  # LTLMoP / the thesis' toolchain: a goal over sensing is an assumption
            return self._goals([goal], forced)
        return [self._safety(self._expr(toks, "safety"), forced)]

    def _conditional(self, condition: list[_Token], requirement: list[_Token], how: str, forced: str | None,
                     always: bool, at: _Token | None = None) -> list[tuple[str, Formula]]:
        word = {"if": "then", "iff": "if and only if", "unless": "unless"}[how]
        if not condition:
            raise self.error(at.column if at else 1, f"expected a condition after '{word}'")
        if not requirement:
            raise self.error(at.column if at else 1, f"expected what to do before '{word}'")
        if requirement[0].low == "always" and len(requirement) > 1:  # "if C then always P" (LTLMoP)
            requirement = requirement[2:] if requirement[1].kind == "," else requirement[1:]
        first = [t.low for t in requirement[:2]]
        req_words = [t.low for t in requirement]
        if req_words in (["stay", "there"], ["stay"]):
            if how == "iff":
                raise self.error(requirement[0].column, "'stay there' cannot follow 'if and only if' (LTLMoP)")
            cond = self._expr(condition, "condition")
            return [self._safety(self._combine(how, cond, self._stay(requirement[0])), forced)]
        if first[:1] in (["visit"], ["go"]) and req_words[-3:] == ["and", "stay", "there"]:
            # LTLMoP: "if C then go to R and stay there" is G(C -> (R -> stay)), C and R now; no goal
            if how == "iff":
                raise self.error(requirement[0].column, "'stay there' cannot follow 'if and only if' (LTLMoP)")
            cond = self._expr(condition, "goal")
            stay = self._stay(requirement[-2])
            return [self._safety(self._combine(how, cond, Implies(g, stay)), forced)
                    for g in self._visit(requirement[:-3])]
        if not always and (first[:1] in (["visit"], ["go"]) or first == ["infinitely", "often"]):
            if first == ["infinitely", "often"]:
                if len(requirement) == 2:
                    raise self.error(requirement[1].column + 5, "expected what happens infinitely often")
                goals = [self._expr(requirement[2:], "goal")]
            else:
                goals = self._visit(requirement)
            cond = self._expr(condition, "goal")
            return self._goals([self._combine(how, cond, g) for g in goals], forced)
        req = self._expr(requirement, "safety")
        robot_next = any(isinstance(v, Var) and v.primed and v.name in self._outputs for v in walk(req))
        # LTLMoP's parseCond: a name without a phrase is read now; in an assumption (a requirement
        # about sensors) 'you are in R' / 'you are activating a' read the robot's current values
        cond = self._expr(condition, "condition" if robot_next else "env_condition")
        return [self._safety(self._combine(how, cond, req), forced)]

    @staticmethod
    def _combine(how: str, cond: Formula, req: Formula) -> Formula:
        if how == "if":
            return Implies(cond, req)
        if how == "iff":
            return Iff(req, cond)
        return Or((req, cond))

    def _find(self, toks: list[_Token], words: tuple[str, ...]) -> int | None:
        """Index of the first occurrence of ``words`` outside parentheses."""
        depth = 0
        n = len(words)
        for i, t in enumerate(toks):
            if t.kind == "(":
                depth += 1
            elif t.kind == ")":
                depth -= 1
            elif depth == 0 and t.low == words[0] and tuple(x.low for x in toks[i:i + n]) == words:
                return i
        return None

    def _visit(self, toks: list[_Token]) -> list[Formula]:
        """``visit a, b and c`` / ``go to a or b``: one goal per item of an 'and' list."""
        skip = 2 if toks[0].low == "go" else 1
        if toks[0].low == "go" and (len(toks) < 2 or toks[1].low != "to"):
            raise self.error(toks[0].column + 3, "expected 'to' after 'go' (go to <region>)", form=True)
        items = [t for t in toks[skip:] if t.kind not in ("(", ")")]
        if not items:
            raise self.error(toks[skip - 1].column + len(toks[skip - 1].text), "expected a region to visit")
        names, connective = [], None
        expect_name = True
        for t in items:
            if expect_name:
                if t.kind != "word" or t.low in KEYWORDS:
                    raise self.error(t.column, f"expected a region name, got '{t.text}'", form=True)
                names.append(t)
                expect_name = False
            elif t.kind == "," or t.low in ("and", "or"):
                if t.kind != ",":
                    if connective and connective != t.low:
                        raise self.error(t.column, "a list of regions is joined either by 'and' or by 'or'")
                    connective = t.low
                expect_name = True
            else:
                raise self.error(t.column, f"expected ',', 'and' or 'or' between regions, got '{t.text}'", form=True)
        if expect_name:
            raise self.error(items[-1].column + len(items[-1].text), "expected a region after the list's last "
                                                                    "separator")
        arrivals = []
        for t in names:
            if not self.decl.is_region(t.text):
                raise self.error(t.column, self._unknown(t.text, "region", self.decl.regions))
            pieces = [Var(p) if self.decl.regions_are_places else And((Var(p), Var(p + REGION_COMPLETION)))
                      for p in self.decl.areas.get(t.text, [t.text])]
            arrivals.append(pieces[0] if len(pieces) == 1 else Or(tuple(pieces)) if pieces else FALSE)
        if connective == "or":
            return [Or(tuple(arrivals))]
        return arrivals

    def _goals(self, goals: list[Formula], forced: str | None) -> list[tuple[str, Formula]]:
        section = "env_liveness" if forced == "env" else "sys_liveness"
        return [(section, g) for g in goals]

    def _safety(self, formula: Formula, forced: str | None) -> tuple[str, Formula]:
        robot_next = [v for v in walk(formula) if isinstance(v, Var) and v.primed and v.name in self._outputs]
        if forced == "env":
            if robot_next:
                raise self.error(1, f"an assumption cannot depend on what the robot does next ('{robot_next[0].name}'"
                                    f"); use the past tense, as in 'you were activating {robot_next[0].name}'")
            return "env_safety", formula
        return ("sys_safety" if robot_next else "env_safety"), formula

    @property
    def _outputs(self) -> set[str]:
        """The robot's propositions (computed once per set of declarations: every name read asks)."""
        cached = self.decl.__dict__.get("_robot_names")
        if cached is None or cached[0] != len(self.decl.kind_of):
            names = {n for n, k in self.decl.kind_of.items()
                     if k in ("actions", "completion_actions", "memory", "regions")}
            cached = self.decl.__dict__["_robot_names"] = (len(self.decl.kind_of), names)
        return cached[1]

    def _mentions_input(self, formula: Formula) -> bool:
        outputs = self._outputs
        return any(isinstance(v, Var) and v.name not in outputs for v in walk(formula))

    # -- initial conditions, memory, mutual exclusion -------------------------------------------

    def _robot_start(self, toks: list[_Token], i: int, forced: str | None) -> list[tuple[str, Formula]]:
        words = [t.low for t in toks]
        out: list[tuple[str, Formula]] = []
        if i >= len(toks) or words[i] not in ("in", "with"):
            where = toks[i].column if i < len(toks) else toks[-1].column + len(toks[-1].text)
            raise self.error(where, "expected 'in <region>' or 'with <propositions>' after 'start'", form=True)
        if words[i] == "in":
            with_at = self._find(toks[i + 1:], ("with",))
            region_toks = toks[i + 1:] if with_at is None else toks[i + 1:i + 1 + with_at]
            if not region_toks:
                raise self.error(toks[i].column + 2, "expected a region after 'in'")
            out.append(("sys_init", self._expr(region_toks, "init", only="regions")))
            if not self.decl.regions_are_places:
                out.append(("env_init", self._expr(region_toks, "init", only="regions", completion=True)))
            if with_at is None:
                return out
            i = i + 1 + with_at
        body = toks[i + 1:]
        if not body:
            raise self.error(toks[i].column + 4, "expected the propositions the robot starts with after 'with'")
        if [t.low for t in body] == ["false"]:
            robot = [*self.decl.actions, *self.decl.completion_actions, *self.decl.memory]
            out.append(("sys_init", And(tuple(Not(Var(n)) for n in robot)) if robot else TRUE))
        else:
            out.append(("sys_init", self._expr(body, "init")))
        return out

    def _environment_start(self, toks: list[_Token]) -> list[tuple[str, Formula]]:
        words = [t.low for t in toks]
        i = 1 if words[0] != "the" else 2
        if words[i:i + 2] != ["starts", "with"]:
            raise self.error(toks[min(i, len(toks) - 1)].column, "expected 'starts with' (Environment starts with …)")
        body = toks[i + 2:]
        if not body:
            raise self.error(toks[-1].column + 4, "expected what the environment starts with")
        if [t.low for t in body] == ["false"]:
            sensors = self.decl.sensors
            return [("env_init", And(tuple(Not(Var(n)) for n in sensors)) if sensors else TRUE)]
        return [("env_init", self._expr(body, "init"))]

    def _memory(self, toks: list[_Token], forced: str | None) -> list[tuple[str, Formula]]:
        """``P is set on E and reset on F``: LTLMoP's four clauses (``parseEvent``), with E and F read
        as LTLMoP reads them: what the environment reports (sensors, completions) at the next step,
        the robot's own propositions at the current one; ``reset on false`` never resets."""
        name = toks[0]
        if name.text not in self._outputs or name.text in self.decl.regions:
            if name.text in self.decl.kind_of:
                raise self.error(name.column, f"'{name.text}' is not a robot proposition; declare it under 'Memory:'")
            raise self.error(name.column, self._unknown(name.text, "memory proposition", self.decl.memory))
        reset = self._find(toks[4:], ("and", "reset", "on"))
        if reset is None:
            raise self.error(toks[-1].column + len(toks[-1].text),
                             f"expected 'and reset on <event>' ({name.text} is set on … and reset on …)", form=True)
        set_toks = toks[4:4 + reset]
        reset_toks = toks[4 + reset + 3:]
        if not set_toks:
            raise self.error(toks[3].column + 2, "expected the event that sets it after 'set on'")
        if not reset_toks:
            raise self.error(toks[-1].column + len(toks[-1].text), "expected the event that resets it after 'reset on'")
        if forced == "env":
            raise self.error(1, "a memory proposition belongs to the robot; 'Assume' cannot define it")
        e = self._expr(set_toks, "event")
        f = self._expr(reset_toks, "event")
        p, p_next = Var(name.text), Var(name.text, True)
        return [("sys_safety", Implies(And((e, Not(f))), p_next)),
                ("sys_safety", Implies(f, Not(p_next))),
                ("sys_safety", Implies(And((p, Not(f))), p_next)),
                ("sys_safety", Implies(And((Not(p), Not(e))), Not(p_next)))]

    def _exclusive(self, toks: list[_Token], forced: str | None) -> list[tuple[str, Formula]]:
        """``a, b and c are mutually exclusive``: at most one is true, initially and always."""
        end = len(toks) - (3 if toks[-1].low == "exclusive" else 4)  # before "are mutually exclusive"/"are never true together"
        if end < 1 or toks[end].low not in ("are", "is"):
            raise self.error(toks[max(end, 0)].column, "expected '<a>, <b> and <c> are mutually exclusive'", form=True)
        names = []
        commas = [t for t in toks[:end] if t.kind == ","]
        if commas and not any(t.low == "and" for t in toks[:end]):
            raise self.error(commas[0].column, "a list 'a, b and c' needs 'and' before its last item")
        for t in toks[:end]:
            if t.kind == "," or t.low == "and":
                continue
            if t.kind != "word":
                raise self.error(t.column, f"expected a proposition name, got '{t.text}'")
            if t.text not in self.decl.kind_of:
                raise self.error(t.column, self._unknown(t.text, "proposition", list(self.decl.kind_of)))
            names.append(t.text)
        if len(set(names)) < 2:
            raise self.error(toks[0].column, "mutual exclusion needs at least two different propositions")
        outputs = self._outputs
        robot = [n in outputs for n in names]
        if any(robot) and not all(robot):
            raise self.error(toks[0].column, "mix of robot and environment propositions; "
                                             "exclude robot propositions and sensed ones in separate sentences")
        if all(robot) and forced != "env":
            return [("sys_safety", at_most_one(names, True)), ("sys_init", at_most_one(names, False))]
        if all(robot):
            raise self.error(1, "an assumption cannot constrain the robot's propositions")
        return [("env_safety", at_most_one(names, True)), ("env_init", at_most_one(names, False))]

    # -- expressions --------------------------------------------------------------------------

    def _expr(self, toks: list[_Token], mode: str, only: str | None = None, completion: bool = False) -> Formula:
        """A condition: names, true/false, not/and/or, parentheses, phrases, comma lists.

        ``mode`` is ``safety`` (present = next state), ``goal`` or ``init`` (present = current state).
        A phrase (``you are sensing``) applies to the names after it joined by and/or, or to the
        parenthesized group right after it; ``not`` in it negates that whole group. A connective
        followed by anything but a name (another phrase, ``not``, ``(``, true, false) ends it, as
        do the end and a ')' closing a '(' opened before it.
        """
        toks = self._lists(toks)
        values: list = []
        ops: list = []  # ("(", token) | ("phrase", _Phrase, token) | ("not", token) | ("and"/"or", token)
        phrases: list[_Phrase] = []
        expect = True
        previous: _Token | None = None
        i = 0

        def apply(op) -> None:
            kind = op[0]
            if kind == "not":
                values.append(Not(settle(values.pop())))
            elif kind == "phrase":
                phrases.pop()
                if op[1].negated:
                    values.append(Not(settle(values.pop())))
            else:
                right, left = values.pop(), values.pop()
                values.append(Pending(And if kind == "and" else Or, left, right))

        def close_group() -> None:
            """End everything opened since the innermost '(' (at a ')' and at the end)."""
            while ops and ops[-1][0] != "(":
                apply(ops.pop())

        def close_phrase() -> None:
            """End the group of the innermost phrase, if it was opened after the innermost '('."""
            k = len(ops) - 1
            while k >= 0 and ops[k][0] not in ("(", "phrase"):
                k -= 1
            if k >= 0 and ops[k][0] == "phrase":
                while len(ops) > k:
                    apply(ops.pop())

        while i < len(toks):
            t = toks[i]
            if expect:
                phrase = self._phrase(toks, i)
                if phrase is not None:
                    ops.append(("phrase", phrase, t))
                    phrases.append(phrase)
                    previous = toks[i + phrase.length - 1]
                    i += phrase.length
                    continue
                edge = self._edge(toks, i, phrases[-1] if phrases else None, mode)
                if edge is not None:
                    values.append(edge)
                    expect = False
                    previous = toks[i + 2]
                    i += 3
                    continue
                if t.low == "not":
                    ops.append(("not", t))
                elif t.kind == "(":
                    ops.append(("(", t))
                elif t.kind == "word" and t.low not in KEYWORDS - {"true", "false"}:
                    if ops and ops[-1][0] == "phrase" and previous is toks[i - 1] and ops[-1][2] is not t:
                        self._check_kind(t, ops[-1][1])
                    values.append(self._atom(t, phrases[-1] if phrases else None, mode, only, completion))
                    expect = False
                elif t.low in ("you", "the", "robot", "it"):
                    words = " ".join(x.text for x in toks[i:i + 3])
                    raise self.error(t.column, f"'{words}' is not a phrase; expected one such as 'you are sensing', "
                                               "'you are activating', 'you are in' or 'you have finished'", form=True)
                else:
                    after = f" after '{previous.text}'" if previous else ""
                    raise self.error(t.column, f"expected a proposition or a phrase such as 'you are sensing'{after}, "
                                               f"got '{t.text}'", form=t.kind == "word")
                previous = t
                i += 1
                continue
            if t.low in _BINARY:
                # A phrase covers the names after it joined by and/or; anything else after a
                # connective (a phrase, 'not', '(', true, false) ends it.
                following = toks[i + 1] if i + 1 < len(toks) else None
                if following is None or following.kind != "word" or following.low in KEYWORDS \
                        or self._edge_starts(toks, i + 1):
                    close_phrase()
                precedence = _BINARY[t.low]
                while ops and (ops[-1][0] == "not" or (ops[-1][0] in _BINARY and _BINARY[ops[-1][0]] >= precedence)):
                    apply(ops.pop())
                ops.append((t.low, t))
                expect = True
            elif t.kind == ")":
                close_group()
                if not ops:
                    raise self.error(t.column, "unexpected ')' without a matching '('")
                ops.pop()
            else:
                raise self.error(t.column, f"expected 'and', 'or' or the end of the condition before '{t.text}'",
                                 form=True)
            previous = t
            i += 1
        if expect:
            end = (previous.column + len(previous.text)) if previous else 1
            after = f" after '{previous.text}'" if previous else ""
            raise self.error(end, f"expected a proposition{after}")
        while ops:
            if ops[-1][0] == "(":
                raise self.error(ops[-1][1].column, "this '(' is never closed")
            apply(ops.pop())
        return settle(values[0])

    @staticmethod
    def _edge_starts(toks: list[_Token], i: int) -> bool:
        return (toks[i].low in ("start", "beginning", "end") and i + 2 < len(toks) and toks[i + 1].low == "of"
                and toks[i + 2].kind == "word")

    def _edge(self, toks: list[_Token], i: int, phrase: _Phrase | None, mode: str) -> Formula | None:
        """``start of x`` / ``beginning of x`` (x rises: ``!x & x'``) and ``end of x`` (x falls:
        ``x & !x'``), LTLMoP's edge conditions; None when ``toks[i]`` does not start one."""
        if not self._edge_starts(toks, i):
            return None
        name_token = toks[i + 2]
        if mode in ("goal", "init"):
            raise self.error(toks[i].column, f"'{toks[i].text} of' compares two steps, which "
                                             f"{'a goal' if mode == 'goal' else 'an initial condition'} does not have")
        atom = self._atom(name_token, phrase, "event", None, False)  # checks the name
        if not isinstance(atom, Var):
            raise self.error(name_token.column, f"'{toks[i].text} of' needs a proposition")
        now, nxt = Var(atom.name), Var(atom.name, True)
        return And((Not(now), nxt)) if toks[i].low != "end" else And((now, Not(nxt)))

    def _refuse_unsupported(self, toks: list[_Token]) -> None:
        """Name LTLMoP's sentence forms this reader does not implement (rather than 'unknown word')."""
        words = [t.low for t in toks]
        for k, t in enumerate(toks):
            if t.text in self.decl.kind_of:
                continue
            for form, what in UNSUPPORTED:
                if tuple(words[k:k + len(form)]) == form:
                    raise self.error(t.column, f"{what} is not supported by ltl_stack's reader "
                                               "(see docs/spec_formats.md)")

    def _group(self, toks: list[_Token]) -> list[tuple[str, Formula]]:
        """``group X is a, b, c``: a named set of regions for ``all X``/``any X``/``each X``."""
        name = toks[1]
        if name.kind != "word" or name.low in KEYWORDS:
            raise self.error(name.column, "expected a group name after 'group'")
        if name.text in self.decl.kind_of:
            raise self.error(name.column, f"'{name.text}' is already a {_KIND_WORD.get(self.decl.kind_of[name.text], 'proposition')}")
        members: list[str] = []
        for t in toks[3:]:
            if t.kind == "," or t.low == "and":
                continue
            if t.kind != "word":
                raise self.error(t.column, f"expected a region name, got '{t.text}'")
            if t.low == "empty":  # LTLMoP: 'empty' adds nothing
                continue
            if t.text not in self.decl.kind_of:
                raise self.error(t.column, self._unknown(t.text, "region", self.decl.regions))
            members.append(t.text)
        self.decl.groups[name.text] = members
        if name.text.endswith("s") and name.text[:-1] and name.text[:-1] not in self.decl.kind_of:
            self.decl.groups.setdefault(name.text[:-1], members)  # 'any Corner' for group Corners (LTLMoP)
        return []

    def _toggle(self, toks: list[_Token], forced: str | None) -> list[tuple[str, Formula]]:
        """``M is toggled on E``: M flips whenever E holds and keeps its value otherwise (LTLMoP's
        ``parseToggle``; E is read as a condition)."""
        name = toks[0]
        if name.text not in self._outputs or name.text in self.decl.regions:
            if name.text in self.decl.kind_of:
                raise self.error(name.column, f"'{name.text}' is not a robot proposition; declare it under 'Memory:'")
            raise self.error(name.column, self._unknown(name.text, "memory proposition", self.decl.memory))
        if forced == "env":
            raise self.error(1, "a memory proposition belongs to the robot; 'Assume' cannot define it")
        if len(toks) < 5:
            raise self.error(toks[-1].column + len(toks[-1].text), f"expected the event after '{toks[3].text}'")
        e = self._expr(toks[4:], "condition")
        m, m_next = Var(name.text), Var(name.text, True)
        return [("sys_safety", Implies(And((m, e)), Not(m_next))), ("sys_safety", Implies(And((Not(m), e)), m_next)),
                ("sys_safety", Implies(And((m, Not(e))), m_next)),
                ("sys_safety", Implies(And((Not(m), Not(e))), Not(m_next)))]

    def _stay(self, at: _Token) -> Formula:
        """``stay there``: the robot's region does not change. In LTLMoP's region model every region
        proposition keeps its value; with activation–completion the robot heads for no region but
        the one it is in (so the environment keeps it there)."""
        regions = self.decl.regions
        if not regions:
            raise self.error(at.column, "'stay there' needs regions (declare 'Regions:' or 'Map:')")
        if self.decl.regions_are_places:
            parts = tuple(Iff(Var(r), Var(r, True)) for r in regions)
        else:
            parts = tuple(Implies(Var(r, True), Var(r + REGION_COMPLETION)) for r in regions)
        return parts[0] if len(parts) == 1 else And(parts)

    def _lists(self, toks: list[_Token]) -> list[_Token]:
        """``a, b or c`` -> ``a or b or c``: each comma takes the connective that ends its list."""
        if not any(t.kind == "," for t in toks):
            return toks
        out = list(toks)
        depth_of, depth = [], 0
        for t in out:
            if t.kind == "(":
                depth += 1
            depth_of.append(depth)
            if t.kind == ")":
                depth -= 1
        pending: dict[int, list[int]] = {}  # depth -> comma positions waiting for their connective
        for k, t in enumerate(out):
            d = depth_of[k]
            if t.kind == ",":
                pending.setdefault(d, []).append(k)
            elif t.low in _BINARY and pending.get(d):
                for c in pending.pop(d):
                    out[c] = _Token("word", t.text, out[c].column)
            elif t.kind == ")" and pending.get(d):
                break
        for commas in pending.values():
            if commas:
                raise self.error(out[commas[0]].column, "a list 'a, b and c' needs 'and' or 'or' before its last item")
        return out

    def _phrase(self, toks: list[_Token], i: int) -> _Phrase | None:
        if i >= len(toks) or toks[i].low not in _PHRASE_STARTS:
            return None
        for length in range(min(_LONGEST_PHRASE, len(toks) - i), 0, -1):
            key = tuple(t.low for t in toks[i:i + length])
            meaning = PHRASES.get(key)
            if meaning is not None:
                return _Phrase(*meaning, length, " ".join(t.text for t in toks[i:i + length]),
                               any(w in _SENSING for w in key))
        return None

    def _atom(self, t: _Token, phrase: _Phrase | None, mode: str, only: str | None, completion: bool) -> Formula:
        if t.low == "true":
            return TRUE
        if t.low == "false":
            return FALSE
        name = t.text
        if name not in self.decl.kind_of:
            pool = self.decl.regions if only == "regions" else list(self.decl.kind_of)
            raise self.error(t.column, self._unknown(name, "region" if only == "regions" else "proposition", pool))
        if only == "regions" and not self.decl.is_region(name):
            raise self.error(t.column, self._unknown(name, "region", self.decl.regions))
        if name in self.decl.areas:  # a region made of pieces: in any of them
            pieces = [_Token("word", piece, t.column) for piece in self.decl.areas[name]]
            parts = tuple(self._atom(piece, phrase, mode, only, completion) for piece in pieces)
            return parts[0] if len(parts) == 1 else Or(parts) if parts else FALSE
        past = phrase is not None and phrase.past
        if past and mode in ("goal", "init") and not (mode == "goal" and self.decl.regions_are_places):
            what = "a goal" if mode == "goal" else "an initial condition"
            raise self.error(t.column, f"'{phrase.text}' speaks of the previous state, which {what} does not have; "
                                       "use the present tense")
        if completion or (phrase is not None and phrase.completion):
            done = self.decl.completion(name)
            if done is None:
                raise self.error(t.column, f"'{name}' has no completion: '{phrase.text if phrase else 'in'}' needs a "
                                           "region or an action declared under 'Actions with completion:'")
            name = done
        return Var(name, self._primed(name, phrase, mode))

    def _check_kind(self, t: _Token, phrase: _Phrase) -> None:
        """The name right after ``you are sensing`` / ``you sensed`` must be an input (a sensor or a
        completion): the robot senses only those. Names joined after it by and/or are read as the
        thesis' own sentences write them (``you are sensing object or sawObject``, a memory
        proposition) and not checked. ``do <sensor>`` stays LTLMoP's form of an assumption
        (``if you are in r1 then do not person``)."""
        kind = self.decl.kind_of.get(t.text)
        if kind is None or t.low in ("true", "false"):
            return
        sensor = t.text in self.decl.inputs
        if phrase.sensing and not sensor:
            raise self.error(t.column, f"'{t.text}' is {_article(_KIND_WORD.get(kind, kind))}, not a sensor: "
                                       f"'{phrase.text}' needs a sensor ({', '.join(self.decl.sensors) or 'none declared'})")

    def _primed(self, name: str, phrase: _Phrase | None, mode: str) -> bool:
        """When a name is read (LTLMoP's ``parseEnglishToLTL``, see docs/spec_formats.md):

        - ``safety`` (what must always hold, ``parseSafety``): the next step;
        - ``condition`` (``if C then …``, ``… if and only if C``, ``parseCond``): with a present-tense
          phrase the next step, with a past one or none (``if stopEverything then …``) the current;
        - ``env_condition``: as ``condition``, but the robot's propositions at the current step (an
          assumption cannot depend on what the robot does next);
        - ``event`` (set/reset/toggle, ``parseEvent``): sensors and completions the next step, the
          robot's propositions the current one; a past phrase the current one;
        - ``goal`` and ``init``: the current (only) step.
        """
        past = phrase is not None and phrase.past
        if past or mode in ("goal", "init"):
            return False
        if mode == "safety":
            return True
        robot = name in self._outputs
        if mode == "event":
            return not robot
        if phrase is None:
            return False
        return not (mode == "env_condition" and robot)

    def _unknown(self, name: str, what: str, pool: list[str]) -> str:
        if name in self.decl.disabled:
            word = self.decl.disabled[name]
            return (f"'{name}' is a {word} the project disables ('{name}, 0' under "
                    f"{'Sensors' if word == 'sensor' else 'Actions'}:); enable it with '{name}, 1'")
        kind = self.decl.kind_of.get(name)
        if kind is not None:
            listed = ", ".join(pool[:8]) + (", …" if len(pool) > 8 else "") if pool else "none declared"
            return f"'{name}' is a {_KIND_WORD.get(kind, 'completion')}, not a {what} ({what}s: {listed})"
        close = difflib.get_close_matches(name, pool, n=1, cutoff=0.6)
        if not close:
            close = [p for p in pool if p.lower() == name.lower()][:1]
        if close:
            return f"unknown {what} '{name}'; did you mean '{close[0]}'?"
        if not pool:
            return f"unknown {what} '{name}' (no {what} is declared)"
        listed = ", ".join(pool[:8]) + (", …" if len(pool) > 8 else "")
        return f"unknown {what} '{name}' (declared: {listed})"

    def _closest_form(self, error: SpecError) -> str | None:
        """The user's sentence with one word changed (a misspelt keyword or name) or one sentence word
        inserted next to where the error is, if that reads; None otherwise. A hint never rewrites the
        sentence into another form, so it cannot change what the user said (issue 24)."""
        toks = self.tokens
        if not toks or len(toks) > 60:
            return None
        known = [*VOCABULARY, *self.decl.kind_of, *self.decl.groups]
        body = self.body
        tries: list[str] = []
        for t in toks:
            if t.kind == "word" and t.low not in VOCABULARY and t.text not in self.decl.kind_of \
                    and t.text not in self.decl.groups:
                for word in difflib.get_close_matches(t.low if t.low in known else t.text, known, n=3, cutoff=0.75):
                    tries.append(body[:t.column - 1] + word + body[t.column - 1 + len(t.text):])
        at = max((k for k, t in enumerate(toks) if t.column <= error.column), default=0)
        for k in sorted(range(len(toks) + 1), key=lambda k: abs(k - at)):
            column = toks[k].column if k < len(toks) else len(body.rstrip()) + 2
            for word in ("are", "then", "to", "is", "on", "of"):  # words that only complete a form
                tries.append((body[:column - 1] + word + " " + body[column - 1:]).rstrip())
        for text in tries:
            try:
                _Sentence(text, self.line, self.file, self.decl).compile(hints=False)
            except SpecError:
                continue
            return text.strip()
        return None
