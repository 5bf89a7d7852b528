"""rospy_fixes' import hook: a fix runs right after its module is imported, or at once if it was."""
from __future__ import annotations

import subprocess
import sys

import pytest

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


def test_the_rosout_flag_is_asked_once_in_a_thread_of_its_own_and_never_blocks_a_log_line():
    """ros_comm#2337: rospy asks the master for an unset /rosout_disable_topics_generation on every
    log line; with the master unreachable that call blocks. A fake rospy whose lookup blocks until
    released stands for the unreachable master."""
    import threading
    import types

    from ltl_stack.ros import rospy_fixes

    release = threading.Event()
    asked = []

    def get_param_cached(name, *default):
        asked.append(name)
        if name == rospy_fixes.ROSOUT_FLAG:
            release.wait(60)  # the master answers only when released
            return True
        return f"value of {name}"

    fake = types.SimpleNamespace(get_param_cached=get_param_cached)
    rospy_fixes.log_without_master(fake)
    done = []
    logger = threading.Thread(target=lambda: done.extend(fake.get_param_cached(rospy_fixes.ROSOUT_FLAG, False)
                                                         for _ in range(100)), daemon=True)
    logger.start()
    logger.join(30)
    assert done == [False] * 100  # answered at once with rospy's default while the master is silent
    assert fake.get_param_cached("/other") == "value of /other"
    release.set()
    from helpers import wait_for

    wait_for(lambda: fake.get_param_cached(rospy_fixes.ROSOUT_FLAG) is True, 60, "the flag's answer kept")
    assert asked.count(rospy_fixes.ROSOUT_FLAG) == 1  # asked once, then kept
    rospy_fixes.log_without_master(fake)  # applied twice: still one wrapper
    assert fake.get_param_cached(rospy_fixes.ROSOUT_FLAG) is True and asked.count(rospy_fixes.ROSOUT_FLAG) == 1


def test_the_unregistration_at_shutdown_gives_up_on_a_master_that_never_answers():
    """rospy's RegManager.cleanup calls the master without a timeout: a fake whose cleanup blocks
    until released stands for the unreachable master; the bounded one returns, a quick one has run."""
    import threading

    from helpers import wait_for

    from ltl_stack.ros import rospy_fixes

    release = threading.Event()
    ran = []

    class Manager:
        def cleanup(self, reason):
            release.wait(120)
            ran.append(reason)

    rospy_fixes.bound_unregistration(Manager, timeout=0.2)
    rospy_fixes.bound_unregistration(Manager, timeout=0.2)  # applied twice: still one wrapper
    done = threading.Event()
    threading.Thread(target=lambda: (Manager().cleanup("cut off"), done.set()), daemon=True).start()
    assert done.wait(60), "the bounded cleanup never returned"
    assert ran == []  # it gave up on the master
    release.set()
    Manager().cleanup("master back")
    wait_for(lambda: "master back" in ran, 60, "the quick cleanup to have run")


PUBLISH_AT_SHUTDOWN = """
import ltl_stack.ros
import rospy.core
import rospy.topics
from std_msgs.msg import Bool

impl = rospy.topics._PublisherImpl("/p", Bool)
impl.close()
try:
    impl.publish(Bool(data=True))
except rospy.exceptions.ROSException as error:
    print("raised:", error)
rospy.core._in_shutdown = True  # rospy's pre-shutdown hooks run (they close every topic) before the flag
print("dropped:", impl.publish(Bool(data=True)))
"""


def test_a_publish_to_a_topic_the_shutdown_closed_is_dropped_and_any_other_closed_topic_still_raises():
    """rospy closes its topics in a pre-shutdown hook, before ``is_shutdown()``: a timer that republishes
    in that window died with 'publish() to a closed topic' in the node's output."""
    pytest.importorskip("rospy")
    proc = subprocess.run([sys.executable, "-c", PUBLISH_AT_SHUTDOWN], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == ["raised: publish() to a closed topic", "dropped: False"], proc.stdout
