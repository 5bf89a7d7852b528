"""A missing PyPI package is one line naming it and the command that installs it, exit 2 (no traceback).

ROS users build ltl_stack in their own catkin workspace; rosdep installs what has a rosdep key, and
the rest comes from ``requirements.txt`` (README, "Install into your catkin workspace"). When one of
those packages is absent, a script would otherwise end in a ``ModuleNotFoundError`` traceback (and,
under roslaunch, in a dead required node with the reason buried in it). ``install`` puts a
``sys.excepthook`` in place that turns exactly that case into one line and exit status 2; every other
uncaught exception goes to the hook that was there before.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path
from types import TracebackType

#: the import names of requirements.txt's run-time packages, and their PyPI names
PYPI_NAMES = {"dd": "dd", "numpy": "numpy", "scipy": "scipy", "yaml": "PyYAML", "lxml": "lxml",
              "shapely": "shapely", "yourdfpy": "yourdfpy", "omega": "omega"}
EXIT_MISSING = 2
#: requirements.txt of a source checkout (a devel space links to it); an install space has it in
#: share/ltl_stack, which ``rospack find ltl_stack`` names
REQUIREMENTS = Path(__file__).resolve().parents[2] / "requirements.txt"


def message(module: str) -> str | None:
    """The line for a ``ModuleNotFoundError`` of ``module``; None when it is not one of our PyPI packages."""
    package = PYPI_NAMES.get(module.partition(".")[0])
    if package is None:
        return None
    where = REQUIREMENTS if REQUIREMENTS.is_file() else "$(rospack find ltl_stack)/requirements.txt"
    return (f"the Python package {package!r} is missing; install ltl_stack's Python packages with: "
            f"python3 -m pip install -r {where} (in a venv, or with --user; README: "
            f"Install into your catkin workspace)")


def install() -> None:
    """Make the process's uncaught ``ModuleNotFoundError`` of a PyPI dependency one line, exit 2."""
    previous = sys.excepthook

    def hook(kind: type[BaseException], error: BaseException, tb: TracebackType | None) -> None:
        line = message(error.name or "") if isinstance(error, ModuleNotFoundError) else None
        if line is None:
            previous(kind, error, tb)
            return
        prog = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "ltl_stack"
        print(f"{prog}: error: {line}", file=sys.stderr)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(EXIT_MISSING)

    sys.excepthook = hook
