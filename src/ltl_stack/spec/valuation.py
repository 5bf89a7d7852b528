"""Truth assignments to propositions as users type and read them: ``a=1,b=false`` and ``a !b``."""
from __future__ import annotations

from collections.abc import Mapping

_TRUE = {"1", "true", "t", "yes", "on"}
_FALSE = {"0", "false", "f", "no", "off"}


def parse_valuation(text: str, known: list[str] | None = None) -> dict[str, bool]:
    """Parse ``"a=1, b=false, !c, d"`` into ``{"a": True, "b": False, "c": False, "d": True}``.

    A bare name means true and ``!name`` false. With ``known``, an unknown name is an error.
    Raises ValueError with a message naming the offending item.
    """
    result: dict[str, bool] = {}
    for raw in text.replace(";", ",").split(","):
        item = raw.strip()
        if not item:
            continue
        if "=" in item:
            name, _, value = (part.strip() for part in item.partition("="))
            if value.lower() in _TRUE:
                truth = True
            elif value.lower() in _FALSE:
                truth = False
            else:
                raise ValueError(f"{item!r}: expected {name}=true or {name}=false")
        elif item.startswith("!"):
            name, truth = item[1:].strip(), False
        else:
            name, truth = item, True
        if not name.replace("_", "").replace("@", "").replace(".", "").isalnum():
            raise ValueError(f"{item!r}: {name!r} is not a proposition name")
        if known is not None and name not in known:
            raise ValueError(f"unknown proposition {name!r} (known: {', '.join(known)})")
        if name in result and result[name] != truth:
            raise ValueError(f"proposition {name!r} is given both true and false")
        result[name] = truth
    return result


def format_valuation(valuation: Mapping[str, bool]) -> str:
    """``{"a": True, "b": False}`` as ``"a !b"`` (the order of the mapping is kept)."""
    return " ".join(name if value else f"!{name}" for name, value in valuation.items())
