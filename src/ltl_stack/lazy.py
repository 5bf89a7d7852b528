"""Names of a package resolved on first use (PEP 562), so importing the package stays cheap.

``ltl_stack.spec`` and ``ltl_stack.synthesis`` re-export names of their submodules; a process that
needs one of them (``synthesize``'s verdict path, a node) should not import the others.
"""
from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping, Sequence


def lazy_exports(package: str, module_of: Mapping[str, str],
                 exported: Sequence[str]) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The package's ``__getattr__`` and ``__dir__``: ``name`` is imported from
    ``package.module_of[name]`` on first use and then kept in the package's globals."""

    def __getattr__(name: str) -> object:
        module = module_of.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(exported))

    return __getattr__, __dir__
