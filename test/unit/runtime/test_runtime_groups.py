"""The runtime layer's groups (docs/architecture.md, "Rank 3: runtime"): every module sits in one group,
each group declares its public API in ``__all__``, the code outside a group uses only that API, and
importing a group stays cheap (its names are imported on first use)."""
from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

RUNTIME = Path(__file__).resolve().parents[3] / "src" / "ltl_stack" / "runtime"
GROUPS = ("config", "executor", "propositions", "resilience", "runs")


def test_every_runtime_module_is_in_a_group():
    assert sorted(p.name for p in RUNTIME.glob("*.py")) == ["__init__.py"]
    packages = sorted(p.name for p in RUNTIME.iterdir() if (p / "__init__.py").exists())
    assert packages == sorted(GROUPS)
    assert importlib.import_module("ltl_stack.runtime").__all__ == list(GROUPS)


@pytest.mark.parametrize("group", GROUPS)
def test_each_name_of_a_group_is_its_module_s_object(group):
    package = importlib.import_module(f"ltl_stack.runtime.{group}")
    assert package.__all__ == sorted(package.__all__) and len(set(package.__all__)) == len(package.__all__)
    for name in package.__all__:
        module = importlib.import_module(f"{package.__name__}.{package._MODULE_OF[name]}")
        assert getattr(package, name) is getattr(module, name), name
    modules = {p.stem for p in (RUNTIME / group).glob("*.py")} - {"__init__"}
    assert set(package._EXPORTS) <= modules
    assert not set(package.__all__) & modules  # a name that is also a module's name would change meaning


def imports_from_groups(root: Path) -> list[tuple[str, str, str, str]]:
    """``(importing file, group, module, name)`` for each ``from ltl_stack.runtime.<group>.<module> import
    name`` in the files under ``root``."""
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("ltl_stack.runtime."):
                parts = node.module.split(".")
                if len(parts) >= 4 and parts[2] in GROUPS:
                    found.extend((str(path), parts[2], parts[3], alias.name) for alias in node.names)
    return found


def test_code_outside_a_group_uses_only_its_declared_api():
    src = RUNTIME.parents[1]
    undeclared = []
    for path, group, module, name in imports_from_groups(src):
        if RUNTIME / group in Path(path).parents or module == "negotiation":  # (a package with its own API)
            continue
        if name in {p.stem for p in (RUNTIME / group).glob("*.py")}:
            continue  # a function named as its module (``running_spec``) cannot be a name of the group
        if name not in importlib.import_module(f"ltl_stack.runtime.{group}").__all__:
            undeclared.append(f"{Path(path).relative_to(src)}: {group}.{module}.{name}")
    assert undeclared == []


def test_the_check_finds_a_name_outside_the_api(tmp_path):
    (tmp_path / "user.py").write_text("from ltl_stack.runtime.config.mapping import _TOP_KEYS\n")
    found = imports_from_groups(tmp_path)
    assert found == [(str(tmp_path / "user.py"), "config", "mapping", "_TOP_KEYS")]
    assert "_TOP_KEYS" not in importlib.import_module("ltl_stack.runtime.config").__all__


@pytest.mark.parametrize("group", GROUPS)
def test_importing_a_group_imports_none_of_its_modules(group):
    code = (f"import sys, ltl_stack.runtime.{group}\n"
            f"print(sorted(m for m in sys.modules if m.startswith('ltl_stack.runtime.{group}.')))")
    shown = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    assert shown.stdout.strip() == "[]"
