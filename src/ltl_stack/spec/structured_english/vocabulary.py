"""The words of Structured English: the reserved words, the tokens of a sentence line and the phrases
(``you are sensing``, ``you were in``, ``finished``, ``do not`` …) that say how the names after them
read (completion or not, current or next state, negated)."""
from __future__ import annotations

import re
from dataclasses import dataclass

# Words of the sentences; a proposition may not be called one of these.
KEYWORDS = frozenset("""
and or not if then only unless always never assume do visit go to infinitely often you the robot it
are is were was have has had did sensing sensed sense activating activated activate in finished finish
set reset on start starts with environment env true false mutually exclusive together
""".split())

TOKEN = re.compile(r"(?P<space>\s+)|(?P<word>[A-Za-z_][A-Za-z0-9_]*)|(?P<number>\d+(?:\.\d+)?)|(?P<punct>[(),.])")


class Token:
    """A word, number, parenthesis, comma or period of a sentence line, at its 1-based column."""

    __slots__ = ("kind", "text", "column", "low")

    def __init__(self, kind: str, text: str, column: int):
        self.kind = kind  # word ( ) , .
        self.text = text
        self.column = column
        self.low = text.lower()


@dataclass(frozen=True)
class Phrase:
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
SENSING = ("sensing", "sensed", "sense")
LONGEST_PHRASE = max(len(k) for k in PHRASES)
PHRASE_STARTS = frozenset(k[0] for k in PHRASES)
BINARY = {"and": 2, "or": 1}
#: LTLMoP's forms that need its geometry or its internal memories, named when refused
UNSUPPORTED = (
    (("between",), "'between R1 and R2' (a region LTLMoP computes from the map's geometry)"),
    (("within",), "'within N of R' (a region LTLMoP computes from the map's geometry)"),
    (("near",), "'near R' (a region LTLMoP computes from the map's geometry)"),
    (("at", "least", "once"), "'at least once' (LTLMoP's generated memory propositions)"),
    (("after", "each", "time"), "'after each time' (LTLMoP's generated memory propositions)"),
)
#: words of conditions that are not reserved (``start of x``, ``all rooms``); each sentence form adds
#: its own (``forms.SentenceForm.words``) to the words a hint may put in place of a misspelt one
CONDITION_WORDS = frozenset({"of", "end", "beginning", "all", "any", "each", "sense"})
