"""The checks of the ROS computation graph (thesis §3.5.1-3.5.2), one module each.

A module of this package that defines ``CHECK`` (a ``base.GraphCheck``) is a check: ``CHECKS`` finds
them all, in their ``order``, and ``checks.analyze``, the reports (``analysis.report``) and the
analysis panel read nothing else. Adding a check is adding its module (and its test).
"""
from __future__ import annotations

import importlib
import pkgutil

from ltl_stack.analysis.graph_checks.base import GraphCheck


def _discover() -> tuple[GraphCheck, ...]:
    found = []
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        check = getattr(module, "CHECK", None)
        if isinstance(check, GraphCheck):
            found.append(check)
    codes = [c.code for c in found]
    if len(set(codes)) != len(codes):
        raise ImportError(f"two graph checks share a code: {sorted(codes)}")
    return tuple(sorted(found, key=lambda c: (c.order, c.code)))


#: Every graph check, in the order reports and the panel show them.
CHECKS = _discover()
BY_CODE = {c.code: c for c in CHECKS}

__all__ = ["BY_CODE", "CHECKS", "GraphCheck"]
