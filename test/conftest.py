"""Shared fixtures and suite-wide rules. Test file names must be unique across test/ (pytest's default
import mode).

- Hypothesis runs derandomized (profile ``suite``): every run checks the same examples, so a rare random
  case cannot turn one CI run red; ``--hypothesis-profile explore`` searches at random with more examples.
- Nothing a test starts talks to a master it did not start, nor logs into ``~/.ros``: ROS_MASTER_URI
  points at a closed port and ROS_HOME/ROS_LOG_DIR at a temporary folder of this pytest process
  (``ros_master`` gives each test its own).
- Modules with slow tests run first, then those with ROS tests (``pytest_collection_modifyitems``): under
  pytest-xdist's ``--dist loadscope`` the scenario runs then overlap and short modules fill the end.
- ``test/unit`` needs no ROS master and no catkin workspace: a unit test that starts a master fails,
  and in unit tests ROS_PACKAGE_PATH is empty, so ``rosrun``/``roslaunch`` cannot find the package.
"""
from __future__ import annotations

import gc
import os
import signal
import socket
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

sys.path.insert(0, str(Path(__file__).resolve().parent))

import helpers  # noqa: E402
from helpers import RosMaster  # noqa: E402

UNIT = Path(__file__).resolve().parent / "unit"

settings.register_profile("suite", derandomize=True, database=None, deadline=None, print_blob=True)
settings.register_profile("explore", max_examples=1000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
#: the suite's fixed examples where the BDDs are dd's pure-Python ones (Python 3.8, no CUDD wheel), fewer
#: of them: there every BDD operation costs tens of times the CPU, and the same properties run with all
#: their examples on CUDD in the other legs; tests that ask for more get this many (see below)
PURE_PYTHON_DD_PROFILE = "suite_pure_python_dd"
settings.register_profile(PURE_PYTHON_DD_PROFILE, parent=settings.get_profile("suite"), max_examples=10)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", PURE_PYTHON_DD_PROFILE if helpers.BDD_BACKEND != "cudd"
                                     else "suite"))
# saved variable orders (ltl_stack.synthesis.order_cache) would make a test depend on the runs
# before it and write into the user's cache: off unless a test points it at a folder of its own
os.environ["LTL_STACK_ORDER_CACHE"] = "off"


def _processes_stop_on_sigint() -> None:
    """A suite started in the background by a non-interactive shell (as a CI runner may do) inherits
    SIGINT ignored, and so would every process it starts: rosmaster, the probes and every node without
    rospy's own handler would then outlast the SIGINT that stops them, and each teardown would wait
    out its grace period (~5 s) before SIGTERM. Handled signals are reset to the default in children."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        try:
            signal.signal(signal.SIGINT, signal.default_int_handler)
        except ValueError:  # not the main thread: nothing to restore from here
            pass


_processes_stop_on_sigint()


def _closed_port() -> int:
    """A loopback port nothing listens on (bound and released: nothing can be connected to it)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_setup(item: pytest.Item):
    """Collect the garbage the previous test of this worker left before this one starts (before
    pytest-qt starts catching exceptions and before capsys): a BDD manager freed by the collector
    in a reference cycle with its nodes makes dd print "Still N nodes referenced upon shutdown",
    which must not land inside another test's body or captured output."""
    gc.collect()
    return (yield)


def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list[pytest.Item]) -> None:
    """Longest modules first (a module with a ``slow`` test, then one with a ``ros`` test, then the rest;
    the order within each group and within a module is kept): xdist hands modules to workers in this
    order, so a minute-long scenario module never starts last while the other workers idle."""
    weight: dict[str, int] = {}
    for item in items:
        module = item.nodeid.split("::")[0]
        w = 2 if item.get_closest_marker("slow") else 1 if item.get_closest_marker("ros") else 0
        weight[module] = max(weight.get(module, 0), w)
    items.sort(key=lambda item: -weight[item.nodeid.split("::")[0]])
    if helpers.BDD_BACKEND != "cudd":
        heavy = pytest.mark.skip(reason=helpers.HEAVY_GAME_REASON)
        listed = helpers.pure_python_dd_heavy()
        for item in items:
            if item.get_closest_marker("heavy_game") or item.nodeid in listed or item.nodeid.split("[")[0] in listed:
                item.add_marker(heavy)
    if settings.default is settings.get_profile(PURE_PYTHON_DD_PROFILE):
        _cap_examples(items, settings.default.max_examples)
    if not helpers.ROS_PYTHON:
        skip = pytest.mark.skip(reason="needs Debian's ROS Python modules (rospy, rosgraph), which this Python "
                                       "cannot import; the main run (Python 3.11) runs it")
        for item in items:
            if item.get_closest_marker("ros_python"):
                item.add_marker(skip)


def _cap_examples(items: list[pytest.Item], cap: int) -> None:
    """Hypothesis tests that set their own ``max_examples`` above ``cap`` run ``cap`` examples (the
    pure-Python dd profile): their settings object, which ``@settings`` stores on the test function, is
    replaced by one that differs only there."""
    for item in items:
        test = getattr(item, "obj", None)
        own = getattr(test, "_hypothesis_internal_use_settings", None)
        if own is not None and own.max_examples > cap:
            test._hypothesis_internal_use_settings = settings(own, max_examples=cap)


def pytest_report_header(config: pytest.Config) -> str:
    if helpers.BDD_BACKEND == "cudd":
        return "BDDs: CUDD"
    examples = (f"Hypothesis profile {PURE_PYTHON_DD_PROFILE} (at most {settings.default.max_examples} examples a "
                f"test)" if settings.default is settings.get_profile(PURE_PYTHON_DD_PROFILE) else "")
    return f"BDDs: dd's pure-Python dd.autoref (no CUDD here): {examples}; tests marked heavy_game skipped"


@pytest.fixture(scope="session", autouse=True)
def _private_ros_environment(tmp_path_factory):
    home = tmp_path_factory.mktemp("ros_home")
    saved = {k: os.environ.get(k) for k in ("ROS_MASTER_URI", "ROS_HOME", "ROS_LOG_DIR")}
    os.environ.update(ROS_MASTER_URI=f"http://127.0.0.1:{_closed_port()}/", ROS_HOME=str(home),
                      ROS_LOG_DIR=str(home / "log"))
    yield
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value


def is_unit_test(item: pytest.Item) -> bool:
    return UNIT in Path(item.path).resolve().parents


@pytest.fixture(autouse=True)
def _unit_tests_need_no_ros(request, monkeypatch):
    """Autouse fixtures run before the ones a test asks for: a unit test fails before a master starts."""
    if not is_unit_test(request.node):
        return
    if "ros_master" in request.fixturenames:
        pytest.fail("a test under test/unit uses the ros_master fixture: move it to test/integration",
                    pytrace=False)

    def refuse(*args, **kwargs):
        raise AssertionError("a test under test/unit starts a ROS master: move it to test/integration")

    monkeypatch.setattr(helpers.RosMaster, "__init__", refuse)
    monkeypatch.setenv("ROS_PACKAGE_PATH", "")


@pytest.fixture
def ros_master(tmp_path, monkeypatch):
    """A real rosmaster on a free loopback port; ROS_MASTER_URI points at it during the test.

    Every process started with ``ros_master.run(...)`` is stopped afterwards, even when the test fails.
    """
    master = RosMaster(tmp_path)
    for key in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME"):
        monkeypatch.setenv(key, master.env[key])
    monkeypatch.delenv("ROS_HOSTNAME", raising=False)
    try:
        yield master
    finally:
        master.shutdown()
