"""Rules for the whole repository that keep CI green on any machine.

- No test asserts a measured time or a ratio of times: on a loaded 2-core machine any clock comparison
  fails sometimes. Speed and linearity are checked by counting work (``helpers.work``).
- No test master on ROS' default port 11311.
- No absolute path of a particular machine in any tracked file (the shared folder is ``../shared``).
"""
from __future__ import annotations

import ast
import re
import subprocess
from pathlib import Path

import pytest
from helpers import REPO_ROOT, _port_range, pure_python_dd_heavy

TEST_ROOT = REPO_ROOT / "test"

#: functions that read a clock (module ``time``, ``datetime``, ``timeit``, ROS time)
CLOCKS = {"perf_counter", "perf_counter_ns", "monotonic", "monotonic_ns", "process_time", "process_time_ns",
          "thread_time", "thread_time_ns", "time", "time_ns", "now", "utcnow", "timeit", "repeat",
          "default_timer", "get_time", "get_rostime"}
CLOCK_OWNERS = {"time", "datetime", "timeit", "rospy", "Time"}


def _is_clock_call(node: ast.AST) -> bool:
    if not isinstance(node, ast.Call):
        return False
    func = node.func
    if isinstance(func, ast.Attribute) and func.attr in CLOCKS:
        owner = func.value
        name = owner.attr if isinstance(owner, ast.Attribute) else getattr(owner, "id", None)
        return name in CLOCK_OWNERS
    return isinstance(func, ast.Name) and func.id in {"perf_counter", "monotonic", "process_time",
                                                       "default_timer", "thread_time"}


def _names(node: ast.AST) -> set[str]:
    return {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}


def _reads_clock(node: ast.AST, tainted: set[str], clock_functions: set[str]) -> bool:
    """Whether ``node`` holds a clock reading, a value computed from one, or a call of a function
    returning one."""
    for sub in ast.walk(node):
        if _is_clock_call(sub):
            return True
        if isinstance(sub, ast.Call) and isinstance(sub.func, ast.Name) and sub.func.id in clock_functions:
            return True
    return bool(_names(node) & tainted)


def timing_assertions(source: str) -> list[int]:
    """Lines of ``assert`` statements (and ``pytest.approx``-free comparisons in them) that test a
    value derived from a clock reading: names assigned from a clock, from such names, or from
    functions returning them, followed to a fixed point within the module."""
    tree = ast.parse(source)
    tainted: set[str] = set()
    clock_functions: set[str] = set()
    functions = [f for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))]
    changed = True
    while changed:
        changed = False
        for node in ast.walk(tree):
            if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.NamedExpr)) and node.value is not None:
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                if _reads_clock(node.value, tainted, clock_functions):
                    new = set().union(*(_names(t) for t in targets)) - tainted
                    if new:
                        tainted |= new
                        changed = True
        for function in functions:
            if function.name in clock_functions:
                continue
            returns = [r.value for r in ast.walk(function) if isinstance(r, ast.Return) and r.value is not None]
            if any(_reads_clock(r, tainted, clock_functions) for r in returns):
                clock_functions.add(function.name)
                changed = True
    return sorted(node.lineno for node in ast.walk(tree)
                  if isinstance(node, ast.Assert) and _reads_clock(node.test, tainted, clock_functions))


def suite_files() -> list[Path]:
    """The suite's Python files (benchmarks measure time on purpose and are not part of it)."""
    return sorted(p for p in TEST_ROOT.rglob("*.py") if "benchmarks" not in p.relative_to(TEST_ROOT).parts)


TIMED = '''
import time

def _seconds(n):
    start = time.process_time()
    work(n)
    return time.process_time() - start

def test_linear():
    small = min(_seconds(10) for _ in range(3))
    large = _seconds(80)
    assert large / small < 20
'''


@pytest.mark.parametrize("source, lines", [
    (TIMED, [12]),
    ("import time\nt0 = time.perf_counter()\nf()\nassert time.perf_counter() - t0 < 1.0\n", [4]),
    ("from time import monotonic\ndef test():\n    s = monotonic()\n    f()\n    took = monotonic() - s\n"
     "    assert took < 2, took\n", [6]),
    ("import datetime\nstart = datetime.datetime.now()\nf()\nassert (datetime.datetime.now() - start).seconds < 3\n",
     [4]),
    ("import rospy\nt = rospy.Time.now()\nassert (rospy.Time.now() - t).to_sec() < 0.5\n", [3]),
    # waiting for a condition with a deadline is fine; so is asserting on counted work
    ("import time\ndeadline = time.monotonic() + 60\nwhile not done() and time.monotonic() < deadline:\n"
     "    time.sleep(0.1)\nassert done()\n", []),
    ("assert work(big) / work(small) < 9\n", []),
])
def test_the_check_finds_assertions_on_measured_time(source, lines):
    assert timing_assertions(source) == lines


def test_no_test_asserts_a_measured_time():
    found = [f"{path.relative_to(REPO_ROOT)}:{line}" for path in suite_files()
             for line in timing_assertions(path.read_text(encoding="utf-8"))]
    assert not found, f"assertions on measured time (count work instead, helpers.work): {found}"


@pytest.mark.parametrize("worker", [f"gw{i}" for i in range(16)] + ["master", ""])
def test_no_test_master_port_range_holds_the_default_port(worker, monkeypatch):
    monkeypatch.setenv("PYTEST_XDIST_WORKER", worker)
    ports = _port_range()
    assert len(ports) >= 50 and 11311 not in ports, ports


# written in pieces so that this file does not match itself
MACHINE_PATH = re.compile("(?<![\\w.~$-])/(?:" + "|".join(["wo" + "rk", "ro" + "ot", "ho" + "me/[^/\\s]+",
                                                               "Us" + "ers/[^/\\s]+"]) + ")/")


def tracked_files() -> list[Path]:
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=REPO_ROOT, capture_output=True, check=True,
                             timeout=120).stdout
        return [REPO_ROOT / name for name in out.decode().split("\0") if name]
    except (OSError, subprocess.SubprocessError):  # not a git checkout: every file but build output
        skip = {".git", "build", "devel", "install", "__pycache__"}
        return [p for p in REPO_ROOT.rglob("*") if p.is_file() and not skip & set(p.relative_to(REPO_ROOT).parts)]


@pytest.mark.parametrize("text, found", [
    ("SHARED = Path('/" "work/shared')", True), ("--slugs /" "root/.cache/slugs", True),
    ("see /" "home/alice/x", True), ("../shared/specs", False), ("~/.cache/slugs", False),
    ("/usr/bin/env python", False), ("file:///" "home/u/x", True), ("/opt/ros/noetic/", False),
])
def test_the_machine_path_pattern(text, found):
    assert bool(MACHINE_PATH.search(text)) is found


def test_no_absolute_path_of_a_particular_machine_in_the_repository():
    found = []
    for path in tracked_files():
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            continue
        found += [f"{path.relative_to(REPO_ROOT)}:{n}" for n, line in enumerate(text.splitlines(), 1)
                  if MACHINE_PATH.search(line)]
    assert not found, f"absolute paths of one machine (use paths relative to the repository): {found}"


@pytest.mark.parametrize("bench", ["bench_explicit", "bench_resilience", "bench_cli_latency", "bench_synthesis",
                                   "bench_transfer"])
def test_benchmarks_find_the_shared_folder_beside_the_repository(bench):
    """``../shared`` relative to the repository (bench_explicit and bench_resilience looked one level
    too high, then fell back to one machine's absolute path)."""
    source = (TEST_ROOT / "benchmarks" / f"{bench}.py").read_text(encoding="utf-8")
    shared = next(node for node in ast.parse(source).body if isinstance(node, ast.Assign)
                  and any(isinstance(t, ast.Name) and t.id == "SHARED" for t in node.targets))
    text = ast.get_source_segment(source, shared.value)
    assert text.split(" / ")[0] in ("ROOT.parent", "REPO.parent") and '"shared"' in text, text
    assert "if" not in text.split(), text  # no fallback


def test_every_test_listed_as_heavy_on_pure_python_dd_exists():
    """test/pure_python_dd_heavy.txt names tests by id: a renamed or removed test must leave it too,
    or the 3.8 leg would run a heavy test again without anyone noticing."""
    for test_id in sorted(pure_python_dd_heavy()):
        path, _, function = test_id.split("[")[0].partition("::")
        source = REPO_ROOT / path
        assert source.is_file(), test_id
        assert re.search(rf"^def {re.escape(function)}\(", source.read_text(), re.MULTILINE), test_id
