"""The layering rule of docs/architecture.md, checked on the source: no package imports a layer above it,
the pure layers import no ROS and no Qt, and no module imports itself back through others. Imports inside
functions count as much as those at the top of a module."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[3] / "src"

# The layers from the bottom (docs/architecture.md); modules directly in ltl_stack/ are the foundation.
LAYERS = ("foundation", "spec", "synthesis", "runtime", "analysis", "transfer", "ros", "sim", "gui")
RANK = {"foundation": 0, "spec": 1, "synthesis": 2, "runtime": 3, "analysis": 4, "transfer": 4,
        "ros": 5, "sim": 6, "gui": 7}
PURE = ("foundation", "spec", "synthesis", "runtime", "analysis", "transfer")
# Top-level names of ROS 1 and Qt packages (Python modules of ROS message packages end in _msgs / _srvs).
ROS_OR_QT = {"rospy", "rosgraph", "roslib", "rosbag", "roslaunch", "rostopic", "rosnode", "rosservice",
             "rosparam", "rosmsg", "actionlib", "genpy", "genmsg", "tf", "tf2_ros", "message_filters",
             "python_qt_binding", "PyQt5", "PySide2", "qt_gui", "rqt_gui", "rqt_gui_py", "sip"}


def module_names(src: Path) -> dict[str, Path]:
    """Dotted module name -> file, for every module of every package under ``src``."""
    found = {}
    for path in sorted(src.rglob("*.py")):
        parts = list(path.relative_to(src).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


def imported(module: str, path: Path) -> list[tuple[str, list[str]]]:
    """``(origin, names)`` for every import statement that runs in ``module`` (``import a.b`` gives
    ``("a.b", [])``), relative imports resolved. Imports under ``if TYPE_CHECKING:`` never run and are
    left out; imports inside functions are in."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skipped = {id(n) for block in ast.walk(tree) if isinstance(block, ast.If) and _type_checking(block.test)
               for statement in block.body for n in ast.walk(statement)}
    found = []
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found.extend((alias.name, []) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                origin = ".".join(base + ([node.module] if node.module else []))
            else:
                origin = node.module or ""
            found.append((origin, [alias.name for alias in node.names]))
    return found


def _type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or \
        (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def import_graph(src: Path) -> dict[str, set[str]]:
    """Module -> the modules of the same tree it imports: ``from p import m`` imports the module
    ``p.m`` when there is one, else (a name defined in ``p``) the module ``p``."""
    modules = module_names(src)

    def known(name: str) -> str:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name

    graph = {}
    for module, path in modules.items():
        targets = set()
        for origin, names in imported(module, path):
            submodules = [f"{origin}.{name}" for name in names if f"{origin}.{name}" in modules]
            found = submodules if submodules and len(submodules) == len(names) else \
                submodules + [known(origin)]
            targets.update(name for name in found if name and name != module)
        graph[module] = targets
    return graph


def layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in RANK else "foundation"


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    """``a -> b`` for each import of a higher layer, or of another layer of the same rank."""
    found = []
    for module, targets in graph.items():
        for target in targets:
            here, there = layer(module), layer(target)
            if here != there and RANK[there] >= RANK[here]:
                found.append(f"{module} ({here}) -> {target} ({there})")
    return sorted(found)


def ros_or_qt_in_pure_layers(src: Path) -> list[str]:
    found = []
    for module, path in module_names(src).items():
        if layer(module) not in PURE:
            continue
        for name, _names in imported(module, path):
            top = name.split(".")[0]
            own_messages = name.startswith(("ltl_stack.msg", "ltl_stack.srv"))
            if top in ROS_OR_QT or top.endswith(("_msgs", "_srvs")) or own_messages:
                found.append(f"{module} imports {name}")
    return sorted(set(found))


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, without recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, successors = work[-1]
            for successor in successors:
                if successor not in index:
                    index[successor] = low[successor] = len(index)
                    stack.append(successor)
                    on_stack.add(successor)
                    work.append((successor, iter(sorted(graph.get(successor, ())))))
                    break
                if successor in on_stack:
                    low[node] = min(low[node], index[successor])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def test_no_package_imports_a_layer_above_it():
    assert upward_imports(import_graph(SRC)) == []


def test_the_pure_layers_import_neither_ros_nor_qt():
    assert ros_or_qt_in_pure_layers(SRC) == []


def test_no_import_cycles():
    assert cycles(import_graph(SRC)) == []


def test_every_layer_of_the_rule_exists():
    packages = {path.name for path in (SRC / "ltl_stack").iterdir() if (path / "__init__.py").exists()}
    assert packages - {"msg", "srv"} == set(LAYERS) - {"foundation"}


def write_tree(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


@pytest.fixture
def tree(tmp_path):
    return write_tree(tmp_path, {
        "ltl_stack/__init__.py": "",
        "ltl_stack/errors.py": "",
        "ltl_stack/spec/__init__.py": "",
        "ltl_stack/spec/model.py": "from ltl_stack import errors\n",
        "ltl_stack/runtime/__init__.py": "",
        "ltl_stack/runtime/controller.py": "from ..spec import model\n",
        "ltl_stack/ros/__init__.py": "",
        "ltl_stack/ros/node.py": "import rospy\nfrom ltl_stack.runtime.controller import x\n",
    })


def test_the_checks_pass_a_tree_that_keeps_the_rule(tree):
    graph = import_graph(tree)
    assert graph["ltl_stack.runtime.controller"] == {"ltl_stack.spec.model"}
    assert graph["ltl_stack.ros.node"] == {"ltl_stack.runtime.controller"}
    assert upward_imports(graph) == [] and cycles(graph) == [] and ros_or_qt_in_pure_layers(tree) == []


def test_an_upward_import_inside_a_function_is_found(tree):
    write_tree(tree, {"ltl_stack/spec/model.py": "def f():\n    from ltl_stack.ros import node\n"})
    assert upward_imports(import_graph(tree)) == ["ltl_stack.spec.model (spec) -> ltl_stack.ros.node (ros)"]


def test_a_sideways_import_between_layers_of_one_rank_is_found(tmp_path):
    root = write_tree(tmp_path, {"ltl_stack/analysis/__init__.py": "", "ltl_stack/transfer/__init__.py": "",
                                 "ltl_stack/analysis/a.py": "from ltl_stack.transfer import b\n",
                                 "ltl_stack/transfer/b.py": ""})
    assert upward_imports(import_graph(root)) == [
        "ltl_stack.analysis.a (analysis) -> ltl_stack.transfer.b (transfer)"]


def test_ros_and_qt_in_a_pure_layer_are_found(tree):
    write_tree(tree, {"ltl_stack/runtime/controller.py": "def f():\n    import rospy.names\n"
                                                         "from python_qt_binding import QtCore\n"
                                                         "from std_msgs.msg import Bool\n"
                                                         "from ltl_stack.msg import ControllerState\n"})
    assert ros_or_qt_in_pure_layers(tree) == [
        "ltl_stack.runtime.controller imports ltl_stack.msg",
        "ltl_stack.runtime.controller imports python_qt_binding",
        "ltl_stack.runtime.controller imports rospy.names",
        "ltl_stack.runtime.controller imports std_msgs.msg"]


def test_a_cycle_through_a_function_level_import_is_found(tree):
    write_tree(tree, {"ltl_stack/spec/other.py": "from ltl_stack.spec.model import y\n",
                      "ltl_stack/spec/model.py": "def f():\n    from . import other\n"})
    assert cycles(import_graph(tree)) == [["ltl_stack.spec.model", "ltl_stack.spec.other"]]


def test_imports_for_type_checkers_only_do_not_count(tree):
    write_tree(tree, {"ltl_stack/spec/model.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                                                 "    from ltl_stack.ros import node\n    import rospy\n"})
    assert upward_imports(import_graph(tree)) == [] and ros_or_qt_in_pure_layers(tree) == []


def test_a_name_from_a_package_is_an_import_of_the_package(tree):
    write_tree(tree, {"ltl_stack/spec/__init__.py": "from ltl_stack.spec.model import Spec\n",
                      "ltl_stack/spec/other.py": "from ltl_stack.spec import Spec\n"})
    graph = import_graph(tree)
    assert graph["ltl_stack.spec.other"] == {"ltl_stack.spec"}
    assert cycles(graph) == []
