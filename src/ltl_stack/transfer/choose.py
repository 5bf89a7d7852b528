"""Choosing the target's channel for each source channel: A.1, A.2 and their combination (§2.5.1).

A.1 takes the most probable name from the target robot's channel statistics, or, with
``by_distribution``, lets the user pick from the whole distribution, ranked, with probabilities (the
alternative §2.5.1 names). A.2 takes the channels of a live master with the same type; when more than
one fits, the user is asked (the prompt of §2.5.1), or, non-interactively, the one whose name is most
similar to the original is chosen and the choice is flagged. With both, A.1's most probable name that
A.2 confirms on the master wins.

An asker returns the index of the chosen option, or None when it has no answer (then the
non-interactive rule decides and the report flags it).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

from .codebase import ChannelStats
from .srdf import similarity

# ask(kind word, type, original name, options) -> index of the chosen option, or None: no answer
Asker = Callable[[str, str, str, Sequence[str]], Optional[int]]


@dataclass
class Decision:
    """The replacement chosen for one name, how, and whether the user had to say."""

    replacement: str | None
    method: str
    user_input: bool = False
    flagged: str | None = None
    candidates: list = field(default_factory=list)


def short_type(msg_type: str | None) -> str:
    return (msg_type or "?").split("/")[-1]


def types_match(a: str | None, b: str | None) -> bool:
    if not a or not b:
        return False
    if "/" in a and "/" in b:
        return a == b
    return short_type(a) == short_type(b)


def prompt_text(word: str, msg_type: str, original: str, options: Sequence[str]) -> str:
    """The §2.5.1 prompt, with the original name shown."""
    article = "an" if word[0] in "aeiou" else "a"
    subject = f" for {short_type(msg_type)}" if msg_type else ""
    lines = [f"Please select {article} {word}{subject} from the list.",
             f"The original {word} was '{original}'. Input Example: 1"]
    lines += [f"{i}. {option}" for i, option in enumerate(options, 1)]
    return "\n".join(lines)


def rule_choice(original: str, options: Sequence[str]) -> int:
    """Non-interactive rule: the option most similar to the original name (difflib), then alphabetical."""
    scored = sorted(range(len(options)),
                    key=lambda i: (-similarity(original.lstrip("/"), options[i].lstrip("/")), options[i]))
    return scored[0]


def distribution_label(name: str, count: int, probability: float) -> str:
    """One option of the A.1 distribution prompt: the name, its count and probability."""
    return f"{name} ({count} use{'s' if count != 1 else ''}, p={probability:.2f})"


def choose_channel(word: str, msg_type: str | None, original: str, stats: ChannelStats | None,
                   live: list[tuple[str, str]] | None, ask: Asker | None,
                   by_distribution: bool = False) -> Decision:
    """Pick the target name for a topic or action of ``msg_type`` whose source name is ``original``."""
    ranked = stats.candidates(msg_type) if stats else []
    live_names = None if live is None else [name for name, t in live if types_match(t, msg_type)]
    table = [{"name": n, "count": c, "probability": round(p, 2)} for n, c, p in ranked]
    if ranked:
        total = sum(c for _, c, _ in ranked)
        bare = {} if live_names is None else {n.lstrip("/"): n for n in live_names}
        usable = ranked if live_names is None else [(n, c, p) for n, c, p in ranked if n.lstrip("/") in bare]
        if usable:
            top = ranked[0][0]
            name, count, prob = usable[0]
            how = f"A.1 codebase ({count} of {total} uses, p={prob:.2f})"
            asked = False
            if by_distribution and ask is not None and len(usable) > 1:
                index = ask(word, msg_type or "?", original, [distribution_label(*u) for u in usable])
                if index is not None:
                    name, count, prob = usable[index]
                    how, asked = f"A.1 codebase distribution, chosen by the user ({count} of {total} uses, " \
                                 f"p={prob:.2f})", True
            flagged = None
            if by_distribution and not asked and len(usable) > 1:
                flagged = "took the most probable name without asking"
            if live_names is None:
                return Decision(name, how, user_input=asked, flagged=flagged, candidates=table)
            if name != top and not asked:
                flagged = f"the most probable name '{top}' is not on the live master; took the next one it has"
            return Decision(bare[name.lstrip("/")], how + " verified on the live master (A.2)",
                            user_input=asked, flagged=flagged, candidates=table)
    if live_names:
        options = sorted(live_names)
        live_table = [{"name": n} for n in options]
        if len(options) == 1:
            flagged = "the codebase's names are not on the live master" if ranked else None
            return Decision(options[0], "A.2 live master (the only channel of this type)",
                            flagged=flagged, candidates=live_table)
        index = ask(word, msg_type or "?", original, options) if ask is not None else None
        if index is not None:
            return Decision(options[index], "A.2 live master, chosen by the user", user_input=True,
                            candidates=live_table)
        index = rule_choice(original, options)
        return Decision(options[index], "A.2 live master, chosen by rule (most similar name)",
                        flagged=f"{len(options)} channels of this type; chose the one most similar to "
                                f"'{original}' without asking", candidates=live_table)
    if ranked:  # A.1 names exist but the master has none of this type
        top, count, prob = ranked[0]
        return Decision(top, f"A.1 codebase (p={prob:.2f})",
                        flagged="no channel of this type on the live master to verify it", candidates=table)
    return Decision(None, "none")


def choose_group(source_group: str, ranked: list[tuple[str, float]], usable: Callable[[str], bool],
                 ask: Asker | None) -> Decision:
    """A.3: the user picks from the similarity-ranked target groups, or the best usable one is taken."""
    table = [{"name": n, "similarity": round(s, 3)} for n, s in ranked]
    options = [n for n, _ in ranked]
    if not options:
        return Decision(None, "none", candidates=table)
    index = ask("MoveIt group", "", source_group, options) if ask is not None else None  # most similar first
    if index is not None:
        return Decision(options[index], "A.3 SRDF groups ranked by similarity, chosen by the user",
                        user_input=True, candidates=table)
    for name in options:
        if usable(name):
            flagged = None if name == options[0] else \
                f"higher-ranked group(s) skipped: no single pose frame ({', '.join(options[:options.index(name)])})"
            return Decision(name, "A.3 SRDF groups ranked by similarity, most similar usable group",
                            flagged=("chose without asking"
                                     + (f"; {flagged}" if flagged else "")), candidates=table)
    return Decision(None, "none", candidates=table)
