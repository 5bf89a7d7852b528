"""Without CUDD (a Python older than dd's wheels, or dd built without its C extension) synthesis falls
back to dd's pure-Python BDDs (``dd.autoref``) and gives the same answers (docs/python_versions.md)."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]

PROBE = """
import json, sys
sys.modules["dd.cudd"] = None  # as if dd had been installed without CUDD
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import game, is_realizable
print(json.dumps({"backend": game.BACKEND,
                  "realizable": [is_realizable(load_spec(path)) for path in sys.argv[1:]]}))
"""


def test_synthesis_without_cudd_uses_autoref_and_agrees():
    specs = [ROOT / "config" / "simple" / "simple.structuredslugs",
             ROOT / "config" / "clean_and_patrol" / "clean_and_patrol.structuredslugs",
             ROOT / "test" / "unit" / "runtime" / "lock.slugsin"]
    done = subprocess.run([sys.executable, "-c", PROBE, *map(str, specs)], capture_output=True, text=True,
                          timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["backend"] == "autoref"
    from ltl_stack.spec import load_spec
    from ltl_stack.synthesis import is_realizable

    assert result["realizable"] == [is_realizable(load_spec(path)) for path in specs]
