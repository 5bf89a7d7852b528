"""One sentence line of Structured English: its tokens, its errors, and the readers its sentence
forms (``forms``) build on: the condition reader (an operator-precedence loop over names, phrases,
not/and/or, parentheses and comma lists) and the pieces every form shares (goals, safety clauses,
``visit`` lists, ``stay there``).

Time is LTLMoP's (``parseEnglishToLTL``; ``Sentence._primed``, docs/spec_formats.md "Timing"): in a
safety sentence the present tense is the *next* state and the past tense the current one; a name
without a phrase in a condition is the current state; a memory's events read sensors next and the
robot's own propositions now. In goals and initial conditions everything is the current state.
"""
from __future__ import annotations

import difflib

from ltl_stack.spec.activation_completion import REGION_COMPLETION
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import FALSE, TRUE, And, Formula, Iff, Implies, Not, Or, Var, walk
from ltl_stack.spec.ops import Pending, settle
from ltl_stack.spec.structured_english.declarations import KIND_WORD, Declarations, article
from ltl_stack.spec.structured_english.vocabulary import (
    BINARY,
    KEYWORDS,
    LONGEST_PHRASE,
    PHRASE_STARTS,
    PHRASES,
    SENSING,
    TOKEN,
    UNSUPPORTED,
    Phrase,
    Token,
)


class Sentence:
    """One sentence line of a spec over ``decl``: its tokens and the readers its forms build on."""

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

    def _tokenize(self) -> list[Token]:
        out = []
        position = 0
        text = self.body
        while position < len(text):
            m = TOKEN.match(text, position)
            if not m:
                raise self.error(position + 1, f"unexpected character {text[position]!r} (a sentence has words, "
                                               "parentheses, commas and a final period)")
            if m.lastgroup != "space":
                kind = m.lastgroup if m.lastgroup in ("word", "number") else m.group()
                out.append(Token(kind, m.group(), position + 1))
            position = m.end()
        while out and out[-1].kind == ".":
            out.pop()
        for t in out:
            if t.kind == ".":
                raise self.error(t.column, "a period ends a sentence; write one sentence per line")
        return out

    # -- pieces the sentence forms share -----------------------------------------------------

    @staticmethod
    def combine(how: str, cond: Formula, req: Formula) -> Formula:
        """The requirement ``req`` under the condition ``cond``: ``if`` (->), ``iff`` (<->) or ``unless`` (or)."""
        if how == "if":
            return Implies(cond, req)
        if how == "iff":
            return Iff(req, cond)
        return Or((req, cond))

    def find(self, toks: list[Token], words: tuple[str, ...]) -> int | None:
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

    def visit(self, toks: list[Token]) -> list[Formula]:
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
                raise self.error(t.column, self.unknown(t.text, "region", self.decl.regions))
            pieces = [Var(p) if self.decl.regions_are_places else And((Var(p), Var(p + REGION_COMPLETION)))
                      for p in self.decl.areas.get(t.text, [t.text])]
            arrivals.append(pieces[0] if len(pieces) == 1 else Or(tuple(pieces)) if pieces else FALSE)
        if connective == "or":
            return [Or(tuple(arrivals))]
        return arrivals

    def goals(self, goals: list[Formula], forced: str | None) -> list[tuple[str, Formula]]:
        section = "env_liveness" if forced == "env" else "sys_liveness"
        return [(section, g) for g in goals]

    def safety(self, formula: Formula, forced: str | None) -> tuple[str, Formula]:
        robot_next = [v for v in walk(formula) if isinstance(v, Var) and v.primed and v.name in self.outputs]
        if forced == "env":
            if robot_next:
                raise self.error(1, f"an assumption cannot depend on what the robot does next ('{robot_next[0].name}'"
                                    f"); use the past tense, as in 'you were activating {robot_next[0].name}'")
            return "env_safety", formula
        return ("sys_safety" if robot_next else "env_safety"), formula

    @property
    def outputs(self) -> set[str]:
        """The robot's propositions (computed once per set of declarations: every name read asks)."""
        cached = self.decl.__dict__.get("_robot_names")
        if cached is None or cached[0] != len(self.decl.kind_of):
            names = {n for n, k in self.decl.kind_of.items()
                     if k in ("actions", "completion_actions", "memory", "regions")}
            cached = self.decl.__dict__["_robot_names"] = (len(self.decl.kind_of), names)
        return cached[1]

    def mentions_input(self, formula: Formula) -> bool:
        outputs = self.outputs
        return any(isinstance(v, Var) and v.name not in outputs for v in walk(formula))

    # -- expressions --------------------------------------------------------------------------

    def expr(self, toks: list[Token], mode: str, only: str | None = None, completion: bool = False) -> Formula:
        """A condition: names, true/false, not/and/or, parentheses, phrases, comma lists.

        ``mode`` is ``safety`` (present = next state), ``goal`` or ``init`` (present = current state).
        A phrase (``you are sensing``) applies to the names after it joined by and/or, or to the
        parenthesized group right after it; ``not`` in it negates that whole group. A connective
        followed by anything but a name (another phrase, ``not``, ``(``, true, false) ends it, as
        do the end and a ')' closing a '(' opened before it.
        """
        toks = self._lists(toks)
        values: list = []
        ops: list = []  # ("(", token) | ("phrase", Phrase, token) | ("not", token) | ("and"/"or", token)
        phrases: list[Phrase] = []
        expect = True
        previous: Token | None = None
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
            if t.low in BINARY:
                # A phrase covers the names after it joined by and/or; anything else after a
                # connective (a phrase, 'not', '(', true, false) ends it.
                following = toks[i + 1] if i + 1 < len(toks) else None
                if following is None or following.kind != "word" or following.low in KEYWORDS \
                        or self._edge_starts(toks, i + 1):
                    close_phrase()
                precedence = BINARY[t.low]
                while ops and (ops[-1][0] == "not" or (ops[-1][0] in BINARY and BINARY[ops[-1][0]] >= precedence)):
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
    def _edge_starts(toks: list[Token], i: int) -> bool:
        return (toks[i].low in ("start", "beginning", "end") and i + 2 < len(toks) and toks[i + 1].low == "of"
                and toks[i + 2].kind == "word")

    def _edge(self, toks: list[Token], i: int, phrase: Phrase | None, mode: str) -> Formula | None:
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

    def refuse_unsupported(self, toks: list[Token]) -> None:
        """Name LTLMoP's sentence forms this reader does not implement (rather than 'unknown word')."""
        words = [t.low for t in toks]
        for k, t in enumerate(toks):
            if t.text in self.decl.kind_of:
                continue
            for form, what in UNSUPPORTED:
                if tuple(words[k:k + len(form)]) == form:
                    raise self.error(t.column, f"{what} is not supported by ltl_stack's reader "
                                               "(see docs/spec_formats.md)")

    def stay(self, at: Token) -> Formula:
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

    def _lists(self, toks: list[Token]) -> list[Token]:
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
            elif t.low in BINARY and pending.get(d):
                for c in pending.pop(d):
                    out[c] = Token("word", t.text, out[c].column)
            elif t.kind == ")" and pending.get(d):
                break
        for commas in pending.values():
            if commas:
                raise self.error(out[commas[0]].column, "a list 'a, b and c' needs 'and' or 'or' before its last item")
        return out

    def _phrase(self, toks: list[Token], i: int) -> Phrase | None:
        if i >= len(toks) or toks[i].low not in PHRASE_STARTS:
            return None
        for length in range(min(LONGEST_PHRASE, len(toks) - i), 0, -1):
            key = tuple(t.low for t in toks[i:i + length])
            meaning = PHRASES.get(key)
            if meaning is not None:
                return Phrase(*meaning, length, " ".join(t.text for t in toks[i:i + length]),
                               any(w in SENSING for w in key))
        return None

    def _atom(self, t: Token, phrase: Phrase | None, mode: str, only: str | None, completion: bool) -> Formula:
        if t.low == "true":
            return TRUE
        if t.low == "false":
            return FALSE
        name = t.text
        if name not in self.decl.kind_of:
            pool = self.decl.regions if only == "regions" else list(self.decl.kind_of)
            raise self.error(t.column, self.unknown(name, "region" if only == "regions" else "proposition", pool))
        if only == "regions" and not self.decl.is_region(name):
            raise self.error(t.column, self.unknown(name, "region", self.decl.regions))
        if name in self.decl.areas:  # a region made of pieces: in any of them
            pieces = [Token("word", piece, t.column) for piece in self.decl.areas[name]]
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

    def _check_kind(self, t: Token, phrase: Phrase) -> None:
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
            raise self.error(t.column, f"'{t.text}' is {article(KIND_WORD.get(kind, kind))}, not a sensor: "
                                       f"'{phrase.text}' needs a sensor ({', '.join(self.decl.sensors) or 'none declared'})")

    def _primed(self, name: str, phrase: Phrase | None, mode: str) -> bool:
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
        robot = name in self.outputs
        if mode == "event":
            return not robot
        if phrase is None:
            return False
        return not (mode == "env_condition" and robot)

    def unknown(self, name: str, what: str, pool: list[str]) -> str:
        if name in self.decl.disabled:
            word = self.decl.disabled[name]
            return (f"'{name}' is a {word} the project disables ('{name}, 0' under "
                    f"{'Sensors' if word == 'sensor' else 'Actions'}:); enable it with '{name}, 1'")
        kind = self.decl.kind_of.get(name)
        if kind is not None:
            listed = ", ".join(pool[:8]) + (", …" if len(pool) > 8 else "") if pool else "none declared"
            return f"'{name}' is a {KIND_WORD.get(kind, 'completion')}, not a {what} ({what}s: {listed})"
        close = difflib.get_close_matches(name, pool, n=1, cutoff=0.6)
        if not close:
            close = [p for p in pool if p.lower() == name.lower()][:1]
        if close:
            return f"unknown {what} '{name}'; did you mean '{close[0]}'?"
        if not pool:
            return f"unknown {what} '{name}' (no {what} is declared)"
        listed = ", ".join(pool[:8]) + (", …" if len(pool) > 8 else "")
        return f"unknown {what} '{name}' (declared: {listed})"

