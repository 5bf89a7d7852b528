"""rospy_fixes' import hook: a fix runs right after its module is imported, or at once if it was."""
from __future__ import annotations

import subprocess
import sys

CODE = """
import sys
sys.path.insert(0, sys.argv[1])
from ltl_stack.ros import rospy_fixes
seen = []
rospy_fixes.when_imported("fixme_pkg.inner", lambda module: seen.append(module.VALUE))
rospy_fixes.when_imported("sys", lambda module: seen.append(module.__name__))
print(seen, "fixme_pkg.inner" in sys.modules)
import fixme_pkg.inner
print(seen, fixme_pkg.inner.VALUE)
import importlib
importlib.reload(fixme_pkg.inner)
print(seen, [f.name for f in sys.meta_path if isinstance(f, rospy_fixes.AfterImport) and f.name.startswith("fixme")])
"""


def test_a_fix_runs_once_right_after_its_module_is_imported(tmp_path):
    package = tmp_path / "fixme_pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "inner.py").write_text("VALUE = 42\n")
    proc = subprocess.run([sys.executable, "-c", CODE, str(tmp_path)], capture_output=True, text=True,
                          timeout=120, check=False)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == ["['sys'] False", "['sys', 42] 42", "['sys', 42] []"], proc.stdout
