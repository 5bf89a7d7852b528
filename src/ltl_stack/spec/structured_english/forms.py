"""The sentence forms of Structured English, one table entry each, tried in order.

A ``SentenceForm`` declares everything about one form in one place:

- ``recognize(r)``: does the sentence ``r`` (its tokens and lower-case words after ``Assume``) have
  this form? The first form of ``FORMS`` that recognizes a sentence reads it, so a form is listed
  before the forms whose recognizers also accept its sentences (``visit R and stay there`` before
  ``visit R``; every form before ``safety``, which reads anything left);
- ``build(r)``: the GR(1) clauses of the sentence, as (section, formula) pairs;
- ``templates``: the form with ``<kind>`` placeholders (``TEMPLATES``: documentation, the fuzz tests);
- ``words``: the words the form adds to the vocabulary of hints: a hint (``reader._closest_form``)
  puts one in place of a misspelt word, or inserts a word that completes a form, if the result reads;
- ``follows_always``: the form may follow ``Always`` (``Always if C then …``);
- ``write_clause(w, f, section, env)`` and ``write_group(group, w)``: the writer's counterpart (see
  ``writer``): one clause as a sentence of this form, or the clauses that one sentence of this form
  compiled to, written back as that sentence; None when the clause (group) is not of this form.
  A form without a writer is written back clause by clause in the forms that have one.

Adding a sentence form is one entry here (and its tests): its recognizer, its builder and, if the
writer should produce it, its writer. The pieces forms share (conditions, goals, ``visit`` lists) are
in ``sentence.Sentence`` (reading) and ``phrasing.Writer`` (writing).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import List, NamedTuple, Tuple

from ltl_stack.spec.activation_completion import REGION_COMPLETION, at_most_one
from ltl_stack.spec.formula import TRUE, And, Formula, Iff, Implies, Not, Or, Var, walk
from ltl_stack.spec.model import Clause
from ltl_stack.spec.structured_english.declarations import KIND_WORD
from ltl_stack.spec.structured_english.phrasing import Writer, split_condition
from ltl_stack.spec.structured_english.sentence import Sentence
from ltl_stack.spec.structured_english.vocabulary import CONDITION_WORDS, KEYWORDS, Token

#: what a sentence compiles to: (section, formula) pairs
Clauses = List[Tuple[str, Formula]]  # noqa: UP006 - a runtime alias: Python 3.8 has no list[...]
#: the clauses one sentence compiled to, with their sections
Group = List[Tuple[str, Clause]]  # noqa: UP006 - a runtime alias: Python 3.8 has no list[...]


class Reading(NamedTuple):
    """A sentence being read: its tokens and their lower-case words (after ``Assume`` and, for the
    forms that follow it, ``Always``); ``forced`` is ``env`` after ``Assume``."""

    sentence: Sentence
    toks: list[Token]
    words: list[str]
    forced: str | None
    always: bool


@dataclass(frozen=True)
class SentenceForm:
    """One sentence form: how it is recognized, read, shown and written back."""

    name: str
    recognize: Callable[[Reading], bool]
    build: Callable[[Reading], Clauses]
    templates: tuple[str, ...] = ()
    words: frozenset[str] = frozenset()
    follows_always: bool = False
    write_clause: Callable[[Writer, Formula, str, bool], str | None] | None = None
    write_group: Callable[[Group, Writer], str | None] | None = None


def read_form(r: Reading) -> Clauses:
    """The clauses of the sentence ``r``, read by the first form of ``FORMS`` that recognizes it."""
    for form in FORMS:
        if (form.follows_always or not r.always) and form.recognize(r):
            return form.build(r)
    raise AssertionError("the last form reads any sentence")  # pragma: no cover


def _safety_section(section: str) -> bool:
    return not section.endswith(("_init", "_liveness"))


# -- groups, memories ---------------------------------------------------------------------------

def _group(r: Reading) -> Clauses:
    """``group X is a, b, c``: a named set of regions for ``all X``/``any X``/``each X``."""
    s, toks = r.sentence, r.toks
    name = toks[1]
    if name.kind != "word" or name.low in KEYWORDS:
        raise s.error(name.column, "expected a group name after 'group'")
    if name.text in s.decl.kind_of:
        raise s.error(name.column, f"'{name.text}' is already a {KIND_WORD.get(s.decl.kind_of[name.text], 'proposition')}")
    members: list[str] = []
    for t in toks[3:]:
        if t.kind == "," or t.low == "and":
            continue
        if t.kind != "word":
            raise s.error(t.column, f"expected a region name, got '{t.text}'")
        if t.low == "empty":  # LTLMoP: 'empty' adds nothing
            continue
        if t.text not in s.decl.kind_of:
            raise s.error(t.column, s.unknown(t.text, "region", s.decl.regions))
        members.append(t.text)
    s.decl.groups[name.text] = members
    if name.text.endswith("s") and name.text[:-1] and name.text[:-1] not in s.decl.kind_of:
        s.decl.groups.setdefault(name.text[:-1], members)  # 'any Corner' for group Corners (LTLMoP)
    return []


def _memory_name(s: Sentence, name: Token) -> None:
    """``name`` must be a memory proposition (a robot proposition that is not a region)."""
    if name.text not in s.outputs or name.text in s.decl.regions:
        if name.text in s.decl.kind_of:
            raise s.error(name.column, f"'{name.text}' is not a robot proposition; declare it under 'Memory:'")
        raise s.error(name.column, s.unknown(name.text, "memory proposition", s.decl.memory))


def _toggle(r: Reading) -> Clauses:
    """``M is toggled on E``: M flips whenever E holds and keeps its value otherwise (LTLMoP's
    ``parseToggle``; E is read as a condition)."""
    s, toks = r.sentence, r.toks
    name = toks[0]
    _memory_name(s, name)
    if r.forced == "env":
        raise s.error(1, "a memory proposition belongs to the robot; 'Assume' cannot define it")
    if len(toks) < 5:
        raise s.error(toks[-1].column + len(toks[-1].text), f"expected the event after '{toks[3].text}'")
    e = s.expr(toks[4:], "condition")
    m, m_next = Var(name.text), Var(name.text, True)
    return [("sys_safety", Implies(And((m, e)), Not(m_next))), ("sys_safety", Implies(And((Not(m), e)), m_next)),
            ("sys_safety", Implies(And((m, Not(e))), m_next)),
            ("sys_safety", Implies(And((Not(m), Not(e))), Not(m_next)))]


def _memory(r: Reading) -> Clauses:
    """``P is set on E and reset on F``: LTLMoP's four clauses (``parseEvent``), with E and F read
    as LTLMoP reads them: what the environment reports (sensors, completions) at the next step,
    the robot's own propositions at the current one; ``reset on false`` never resets."""
    s, toks = r.sentence, r.toks
    name = toks[0]
    _memory_name(s, name)
    reset = s.find(toks[4:], ("and", "reset", "on"))
    if reset is None:
        raise s.error(toks[-1].column + len(toks[-1].text),
                      f"expected 'and reset on <event>' ({name.text} is set on … and reset on …)", form=True)
    set_toks = toks[4:4 + reset]
    reset_toks = toks[4 + reset + 3:]
    if not set_toks:
        raise s.error(toks[3].column + 2, "expected the event that sets it after 'set on'")
    if not reset_toks:
        raise s.error(toks[-1].column + len(toks[-1].text), "expected the event that resets it after 'reset on'")
    if r.forced == "env":
        raise s.error(1, "a memory proposition belongs to the robot; 'Assume' cannot define it")
    e = s.expr(set_toks, "event")
    f = s.expr(reset_toks, "event")
    p, p_next = Var(name.text), Var(name.text, True)
    return [("sys_safety", Implies(And((e, Not(f))), p_next)),
            ("sys_safety", Implies(f, Not(p_next))),
            ("sys_safety", Implies(And((p, Not(f))), p_next)),
            ("sys_safety", Implies(And((Not(p), Not(e))), Not(p_next)))]


def _write_memory(group: Group, w: Writer) -> str | None:
    """The four clauses ``_memory`` builds, as their sentence."""
    if len(group) != 4 or any(s != "sys_safety" for s, _ in group):
        return None
    first = group[0][1].formula
    if not (isinstance(first, Implies) and isinstance(first.right, Var) and isinstance(first.left, And)
            and len(first.left.args) == 2 and isinstance(first.left.args[1], Not)):
        return None
    name = first.right.name
    set_event, reset_event = first.left.args[0], first.left.args[1].arg
    return (f"{name} is set on {w.expression(set_event, 'safety', bare=True)} "
            f"and reset on {w.expression(reset_event, 'safety', bare=True)}")


# -- initial conditions, mutual exclusion -------------------------------------------------------

def _robot_subject(words: Sequence[str]) -> int:
    """How many words name the robot before ``start(s)``: ``robot``/``you`` 1, ``the robot`` 2."""
    return 1 if words[:1] in (["robot"], ["you"]) else 2 if words[:2] == ["the", "robot"] else 0


def _robot_start(r: Reading) -> Clauses:
    """``Start in R [with P]`` / ``Robot starts with P``: the robot's (and, for a region, the
    environment's completion) initial values."""
    s, toks, words = r.sentence, r.toks, r.words
    i = _robot_subject(words) + 1
    out: Clauses = []
    if i >= len(toks) or words[i] not in ("in", "with"):
        where = toks[i].column if i < len(toks) else toks[-1].column + len(toks[-1].text)
        raise s.error(where, "expected 'in <region>' or 'with <propositions>' after 'start'", form=True)
    if words[i] == "in":
        with_at = s.find(toks[i + 1:], ("with",))
        region_toks = toks[i + 1:] if with_at is None else toks[i + 1:i + 1 + with_at]
        if not region_toks:
            raise s.error(toks[i].column + 2, "expected a region after 'in'")
        out.append(("sys_init", s.expr(region_toks, "init", only="regions")))
        if not s.decl.regions_are_places:
            out.append(("env_init", s.expr(region_toks, "init", only="regions", completion=True)))
        if with_at is None:
            return out
        i = i + 1 + with_at
    body = toks[i + 1:]
    if not body:
        raise s.error(toks[i].column + 4, "expected the propositions the robot starts with after 'with'")
    if [t.low for t in body] == ["false"]:
        robot = [*s.decl.actions, *s.decl.completion_actions, *s.decl.memory]
        out.append(("sys_init", And(tuple(Not(Var(n)) for n in robot)) if robot else TRUE))
    else:
        out.append(("sys_init", s.expr(body, "init")))
    return out


def _write_start_in(group: Group, w: Writer) -> str | None:
    """``Start in R``: the pair ``R`` (robot) and ``R_rc`` (environment) ``_robot_start`` builds."""
    if len(group) != 2 or [s for s, _ in group] != ["env_init", "sys_init"]:
        return None
    env, sys = group[0][1].formula, group[1][1].formula
    if isinstance(sys, Var) and isinstance(env, Var) and sys.name in w.decl.regions \
            and env.name == sys.name + REGION_COMPLETION:
        return f"Start in {sys.name}"
    return None


def _write_robot_start(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    if not section.endswith("_init") or env:
        return None
    return f"robot starts with {w.expression(f, 'init', bare=True)}"


def _environment_start(r: Reading) -> Clauses:
    """``Environment starts with P``: the sensors' initial values (``false``: all off)."""
    s, toks, words = r.sentence, r.toks, r.words
    i = 1 if words[0] != "the" else 2
    if words[i:i + 2] != ["starts", "with"]:
        raise s.error(toks[min(i, len(toks) - 1)].column, "expected 'starts with' (Environment starts with …)")
    body = toks[i + 2:]
    if not body:
        raise s.error(toks[-1].column + 4, "expected what the environment starts with")
    if [t.low for t in body] == ["false"]:
        sensors = s.decl.sensors
        return [("env_init", And(tuple(Not(Var(n)) for n in sensors)) if sensors else TRUE)]
    return [("env_init", s.expr(body, "init"))]


def _write_environment_start(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    if not section.endswith("_init") or not env:
        return None
    return f"environment starts with {w.expression(f, 'init', bare=True)}"


def _exclusive(r: Reading) -> Clauses:
    """``a, b and c are mutually exclusive``: at most one is true, initially and always."""
    s, toks = r.sentence, r.toks
    end = len(toks) - (3 if toks[-1].low == "exclusive" else 4)  # before "are mutually exclusive"/"are never true together"
    if end < 1 or toks[end].low not in ("are", "is"):
        raise s.error(toks[max(end, 0)].column, "expected '<a>, <b> and <c> are mutually exclusive'", form=True)
    names = []
    commas = [t for t in toks[:end] if t.kind == ","]
    if commas and not any(t.low == "and" for t in toks[:end]):
        raise s.error(commas[0].column, "a list 'a, b and c' needs 'and' before its last item")
    for t in toks[:end]:
        if t.kind == "," or t.low == "and":
            continue
        if t.kind != "word":
            raise s.error(t.column, f"expected a proposition name, got '{t.text}'")
        if t.text not in s.decl.kind_of:
            raise s.error(t.column, s.unknown(t.text, "proposition", list(s.decl.kind_of)))
        names.append(t.text)
    if len(set(names)) < 2:
        raise s.error(toks[0].column, "mutual exclusion needs at least two different propositions")
    outputs = s.outputs
    robot = [n in outputs for n in names]
    if any(robot) and not all(robot):
        raise s.error(toks[0].column, "mix of robot and environment propositions; "
                                      "exclude robot propositions and sensed ones in separate sentences")
    if all(robot) and r.forced != "env":
        return [("sys_safety", at_most_one(names, True)), ("sys_init", at_most_one(names, False))]
    if all(robot):
        raise s.error(1, "an assumption cannot constrain the robot's propositions")
    return [("env_safety", at_most_one(names, True)), ("env_init", at_most_one(names, False))]


def _exclusive_names(f: Formula) -> list[str] | None:
    """Names of an at-most-one formula (the form ``activation_completion.at_most_one`` builds)."""
    if not isinstance(f, Or) or len(f.args) < 3 or not all(isinstance(t, And) for t in f.args):
        return None
    last = f.args[-1]
    if not all(isinstance(a, Not) and isinstance(a.arg, Var) for a in last.args):
        return None
    return [a.arg.name for a in last.args]


def _write_exclusive(group: Group, w: Writer) -> str | None:
    sections = [s for s, _ in group]
    if sorted(sections) not in (["sys_init", "sys_safety"], ["env_init", "env_safety"]):
        return None
    names = _exclusive_names(next(c.formula for s, c in group if s.endswith("safety")))
    if not names:
        return None
    listed = ", ".join(names[:-1]) + " and " + names[-1]
    return f"{'Assume ' if sections[0].startswith('env') else ''}{listed} are mutually exclusive"


# -- always, never, conditionals -----------------------------------------------------------------

def _always(r: Reading) -> Clauses:
    """``Always S``: the sentence ``S`` (a form that may follow ``Always``)."""
    s, rest = r.sentence, r.toks
    skip = 2 if len(rest) > 1 and rest[1].kind == "," else 1
    if len(rest) == skip:
        raise s.error(rest[0].column + len(rest[0].text), "expected what is always true after 'always'")
    toks = rest[skip:]
    return read_form(Reading(s, toks, [t.low for t in toks], r.forced, True))


def _write_always(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    if not _safety_section(section) or isinstance(f, Iff) or split_condition(f)[0] is not None:
        return None
    if w.robot_next_only(f):
        return f"always {w.expression(f, 'safety', bare=True)}"
    return f"always {w.expression(f, 'safety')}"


def _never(r: Reading) -> Clauses:
    s, rest = r.sentence, r.toks
    if len(rest) == 1:
        raise s.error(rest[0].column + 5, "expected what never happens after 'never'")
    return [s.safety(Not(s.expr(rest[1:], "safety")), r.forced)]


def _if(r: Reading) -> Clauses:
    """``If C then R``."""
    s, toks = r.sentence, r.toks
    then = s.find(toks, ("then",))
    if then is None:
        raise s.error(toks[-1].column + len(toks[-1].text), "expected 'then' after the condition of 'if'",
                      form=True)
    condition = toks[1:then - 1] if toks[then - 1].kind == "," else toks[1:then]
    requirement = toks[then + 1:]
    if not condition:
        raise s.error(toks[then].column, "expected a condition between 'if' and 'then'")
    if not requirement:
        raise s.error(toks[then].column + 4, "expected what to do after 'then'")
    return _conditional(r, condition, requirement, "if")


def _write_if(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    if section.endswith("_init") or isinstance(f, Iff):
        return None
    condition, then = split_condition(f)
    if condition is None:
        return None
    if section.endswith("_liveness"):
        g = w.visited(then)
        goal = f"visit {g}" if g else f"infinitely often {w.expression(then, 'goal', bare=True)}"
        return f"if {w.expression(condition, 'goal')} then {goal}"
    return f"if {w.expression(condition, 'safety')} then {w.requirement(then)}"


_IFF = ("if", "and", "only", "if")


def _iff(r: Reading) -> Clauses:
    """``R if and only if C``."""
    toks = r.toks
    iff = r.sentence.find(toks, _IFF)
    return _conditional(r, toks[iff + 4:], toks[:iff], "iff", at=toks[iff])


def _write_iff(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    if not _safety_section(section) or not isinstance(f, Iff):
        return None
    return f"{w.requirement(f.left)} if and only if {w.expression(f.right, 'safety')}"


def _unless(r: Reading) -> Clauses:
    """``R unless C``: R or C."""
    toks = r.toks
    unless = r.sentence.find(toks, ("unless",))
    return _conditional(r, toks[unless + 1:], toks[:unless], "unless", at=toks[unless])


def _conditional(r: Reading, condition: list[Token], requirement: list[Token], how: str,
                 at: Token | None = None) -> Clauses:
    """The requirement ``requirement`` under ``condition`` (``if``/``iff``/``unless``): a safety
    clause, or goals under a condition (``if C then visit R``)."""
    s, forced = r.sentence, r.forced
    word = {"if": "then", "iff": "if and only if", "unless": "unless"}[how]
    if not condition:
        raise s.error(at.column if at else 1, f"expected a condition after '{word}'")
    if not requirement:
        raise s.error(at.column if at else 1, f"expected what to do before '{word}'")
    if requirement[0].low == "always" and len(requirement) > 1:  # "if C then always P" (LTLMoP)
        requirement = requirement[2:] if requirement[1].kind == "," else requirement[1:]
    first = [t.low for t in requirement[:2]]
    req_words = [t.low for t in requirement]
    if req_words in (["stay", "there"], ["stay"]):
        if how == "iff":
            raise s.error(requirement[0].column, "'stay there' cannot follow 'if and only if' (LTLMoP)")
        cond = s.expr(condition, "condition")
        return [s.safety(s.combine(how, cond, s.stay(requirement[0])), forced)]
    if first[:1] in (["visit"], ["go"]) and req_words[-3:] == ["and", "stay", "there"]:
        # LTLMoP: "if C then go to R and stay there" is G(C -> (R -> stay)), C and R now; no goal
        if how == "iff":
            raise s.error(requirement[0].column, "'stay there' cannot follow 'if and only if' (LTLMoP)")
        cond = s.expr(condition, "goal")
        stay = s.stay(requirement[-2])
        return [s.safety(s.combine(how, cond, Implies(g, stay)), forced)
                for g in s.visit(requirement[:-3])]
    if not r.always and (first[:1] in (["visit"], ["go"]) or first == ["infinitely", "often"]):
        if first == ["infinitely", "often"]:
            if len(requirement) == 2:
                raise s.error(requirement[1].column + 5, "expected what happens infinitely often")
            goals = [s.expr(requirement[2:], "goal")]
        else:
            goals = s.visit(requirement)
        cond = s.expr(condition, "goal")
        return s.goals([s.combine(how, cond, g) for g in goals], forced)
    req = s.expr(requirement, "safety")
    robot_next = any(isinstance(v, Var) and v.primed and v.name in s.outputs for v in walk(req))
    # LTLMoP's parseCond: a name without a phrase is read now; in an assumption (a requirement
    # about sensors) 'you are in R' / 'you are activating a' read the robot's current values
    cond = s.expr(condition, "condition" if robot_next else "env_condition")
    return [s.safety(s.combine(how, cond, req), forced)]


# -- goals, staying, plain safety ----------------------------------------------------------------

def _visit_and_stay(r: Reading) -> Clauses:
    """``visit R and stay there``: the goal R, and once in R the robot stays."""
    s, rest = r.sentence, r.toks
    goals = s.visit(rest[:-3])
    return [*s.goals(goals, r.forced), *(("sys_safety", Implies(g, s.stay(rest[-2]))) for g in goals)]


def _visit(r: Reading) -> Clauses:
    """``visit a, b and c`` / ``go to a or b``: one goal per item of an 'and' list."""
    return r.sentence.goals(r.sentence.visit(r.toks), r.forced)


def _write_visit(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    if not section.endswith("_liveness") or split_condition(f)[0] is not None:
        return None
    region = w.visited(f)
    return None if region is None else f"visit {region}"


def _write_visits(group: Group, w: Writer) -> str | None:
    """Several goals of one sentence, each a visit under the same condition: ``visit a and b``."""
    sections = [s for s, _ in group]
    if len(group) < 2 or not all(s == sections[0] and s.endswith("liveness") for s in sections):
        return None
    visits = [split_condition(c.formula) for _, c in group]
    regions = [w.visited(g) for _, g in visits]
    conditions = {w.expression(c, "goal") if c is not None else "" for c, _ in visits}
    if not all(regions) or len(conditions) != 1:
        return None
    condition = conditions.pop()
    listed = ", ".join(regions[:-1]) + " and " + regions[-1]
    prefix = "Assume " if sections[0].startswith("env") else ""
    if condition:
        return f"{prefix}If {condition} then visit {listed}"
    return f"{prefix}{'v' if prefix else 'V'}isit {listed}"


def _stay(r: Reading) -> Clauses:
    return [r.sentence.safety(r.sentence.stay(r.toks[0]), r.forced)]


def _infinitely_often(r: Reading) -> Clauses:
    """``infinitely often G``: a goal (an assumption when G mentions sensing without ``do``)."""
    s, toks, forced = r.sentence, r.toks, r.forced
    body = toks[2:]
    if not body:
        raise s.error(toks[1].column + 5, "expected what happens infinitely often")
    goal = s.expr(body, "goal")
    if forced is None and body[0].low != "do" and s.mentions_input(goal):
        forced = "env"  # LTLMoP / the thesis' toolchain: a goal over sensing is an assumption
    return s.goals([goal], forced)


def _write_infinitely_often(w: Writer, f: Formula, section: str, env: bool) -> str | None:
    """``infinitely often …`` (``do`` when it mentions sensing, so that it stays the robot's goal)."""
    if not section.endswith("_liveness") or split_condition(f)[0] is not None or w.visited(f) is not None:
        return None
    text = w.expression(f, "goal", bare=True)
    if not env and any(isinstance(v, Var) and v.name not in w.outputs for v in walk(f)):
        return f"infinitely often do ({text})"
    return f"infinitely often {text}"


def _safety(r: Reading) -> Clauses:
    """A condition that always holds (``do a``, ``you are not in r1 or stop``)."""
    return [r.sentence.safety(r.sentence.expr(r.toks, "safety"), r.forced)]


def _everything(r: Reading) -> bool:
    return True


#: the sentence forms, in the order they are tried
FORMS: tuple[SentenceForm, ...] = (
    SentenceForm("group", lambda r: r.words[0] == "group" and len(r.words) > 2 and r.words[2] in ("is", "are"),
                 _group, words=frozenset({"group"})),
    SentenceForm("toggle", lambda r: len(r.words) >= 4 and r.words[1:3] == ["is", "toggled"]
                 and r.words[3] in ("on", "when"), _toggle, words=frozenset({"toggled", "when"})),
    SentenceForm("visit and stay", lambda r: not r.forced and r.words[0] in ("visit", "go")
                 and r.words[-3:] == ["and", "stay", "there"], _visit_and_stay, words=frozenset({"stay", "there"})),
    SentenceForm("environment start", lambda r: r.words[:2] in (["environment", "starts"], ["env", "starts"],
                                                                ["the", "environment"]),
                 _environment_start, ("environment starts with <sensor>",),
                 write_clause=_write_environment_start),
    SentenceForm("robot start", lambda r: len(r.words) > _robot_subject(r.words)
                 and r.words[_robot_subject(r.words)] in ("start", "starts"),
                 _robot_start, ("start in <region>", "robot starts with <action>"),
                 write_clause=_write_robot_start, write_group=_write_start_in),
    SentenceForm("memory", lambda r: len(r.words) >= 4 and r.words[1:4] == ["is", "set", "on"], _memory,
                 ("<memory> is set on <sensor> and reset on finished <action>",), write_group=_write_memory),
    SentenceForm("mutual exclusion", lambda r: r.words[-2:] == ["mutually", "exclusive"]
                 or r.words[-3:] == ["never", "true", "together"], _exclusive,
                 ("<p> and <p> are mutually exclusive",), write_group=_write_exclusive),
    SentenceForm("always", lambda r: r.words[0] == "always", _always, ("always <p>", "assume always <p>"),
                 write_clause=_write_always),
    SentenceForm("never", lambda r: r.words[0] == "never", _never, ("never <p>",)),
    SentenceForm("if", lambda r: r.words[0] == "if", _if,
                 ("if you are sensing <sensor> then do <action>", "if you are not sensing <sensor> then do <action>",
                  "if you are activating <p> then do <action>", "if you are in <region> then do <action>",
                  "if you were in <region> then do <action>", "if you have finished <action> then do <action>",
                  "if you are sensing <sensor> then visit <region>"),
                 follows_always=True, write_clause=_write_if),
    SentenceForm("if and only if", lambda r: r.sentence.find(r.toks, _IFF) is not None, _iff,
                 ("do <action> if and only if you are sensing <sensor>",), follows_always=True,
                 write_clause=_write_iff),
    SentenceForm("unless", lambda r: r.sentence.find(r.toks, ("unless",)) is not None, _unless,
                 ("do <action> unless you are sensing <sensor>",), follows_always=True),
    SentenceForm("visit", lambda r: not r.always and r.words[0] in ("visit", "go"), _visit,
                 ("visit <region>", "go to <region>"), follows_always=True,
                 write_clause=_write_visit, write_group=_write_visits),
    SentenceForm("stay", lambda r: r.words in (["stay", "there"], ["stay"]), _stay,
                 words=frozenset({"stay", "there"}), follows_always=True),
    SentenceForm("infinitely often", lambda r: not r.always and r.words[:2] == ["infinitely", "often"],
                 _infinitely_often, ("infinitely often <p>",), follows_always=True,
                 write_clause=_write_infinitely_often),
    SentenceForm("safety", _everything, _safety, ("do <action>",), follows_always=True),
)

#: every form's templates, for documentation and the fuzz tests
TEMPLATES = [template for form in FORMS for template in form.templates]
#: words a hint may put in place of a misspelt one
VOCABULARY = sorted(KEYWORDS | CONDITION_WORDS | {w for form in FORMS for w in form.words})
