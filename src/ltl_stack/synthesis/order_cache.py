"""Variable orders kept between runs, keyed by the specification's content.

Dynamic reordering (CUDD's sifting) is often the largest part of a solve on small games (20-94 %
on slugs' moving_obstacle and cinderella families), and with the order CUDD ends with the same
fixpoint costs several times less. So once a game is solved its final order is saved here, and the
next ``Game`` of the same spec starts in it without any sifting (a second ``synthesize``, the
executor starting after ``synthesize``). A spec that differs only in its clauses but has the same
propositions (a resynthesis after an edit, a negotiated variant) starts in the saved order of the
last spec with those propositions and keeps dynamic reordering on, so a worse fit is still
corrected. An order never changes a verdict or a strategy's moves: only the BDDs' shape.

Where: ``$LTL_STACK_ORDER_CACHE`` when set (an empty value or ``off`` switches the cache off), else
``$XDG_CACHE_HOME/ltl_stack/orders`` (``~/.cache/ltl_stack/orders``). Bounded: at most
``MAX_ENTRIES`` files (the least recently used are deleted), each a small JSON list of names.
A cache that cannot be read or written is ignored: it is only ever a hint.
"""
from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from ltl_stack.spec.model import Spec
from ltl_stack.spec.slugsin import write_slugsin

#: files kept at most (two per spec: its content key and its propositions key)
MAX_ENTRIES = 256


def cache_dir() -> Path | None:
    """The folder of saved orders, or None when the cache is switched off."""
    value = os.environ.get("LTL_STACK_ORDER_CACHE")
    if value is not None:
        return None if value.strip() in ("", "off") else Path(value)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "ltl_stack" / "orders"


def keys(spec: Spec) -> tuple[str, str]:
    """(content key, propositions key) of a spec: hashes of its slugsin text and of its names."""
    content = hashlib.sha256(write_slugsin(spec).encode()).hexdigest()[:32]
    names = "\n".join(["[INPUT]", *spec.inputs, "[OUTPUT]", *spec.outputs])
    return content, "p" + hashlib.sha256(names.encode()).hexdigest()[:31]


def load(spec: Spec, variables: set[str]) -> tuple[list[str], bool] | None:
    """(order, exact) saved for ``spec``: exact when saved for this very content, else an order
    saved for a spec with the same propositions; None when there is none (or it does not name
    exactly ``variables``)."""
    folder = cache_dir()
    if folder is None:
        return None
    content, propositions = keys(spec)
    for key, exact in ((content, True), (propositions, False)):
        path = folder / f"{key}.json"
        try:
            order = json.loads(path.read_text())
            os.utime(path)  # recently used
        except (OSError, ValueError):
            continue
        if isinstance(order, list) and set(order) == variables and len(order) == len(variables):
            return [str(v) for v in order], exact
    return None


def save(spec: Spec, order: list[str]) -> None:
    """Keep ``order`` (variable names, top level first) for ``spec`` and its propositions."""
    folder = cache_dir()
    if folder is None:
        return
    try:
        folder.mkdir(parents=True, exist_ok=True)
        text = json.dumps(order)
        for key in keys(spec):
            tmp = folder / f".{key}.{os.getpid()}.tmp"
            tmp.write_text(text)
            os.replace(tmp, folder / f"{key}.json")
        _trim(folder)
    except OSError:
        pass


def _trim(folder: Path) -> None:
    """Delete the least recently used files beyond ``MAX_ENTRIES``."""
    files = sorted(folder.glob("*.json"), key=lambda p: p.stat().st_mtime)
    for path in files[:max(0, len(files) - MAX_ENTRIES)]:
        try:
            path.unlink()
        except OSError:
            pass
