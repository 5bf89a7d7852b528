"""The controller executor and a proposition node on ROS Noetic's Python (3.8), on a real master.

On Ubuntu 20.04 a ROS Noetic user runs our nodes with Python 3.8: their venv's packages (dd without
CUDD, numpy, ...) and, after them, the distribution's pure-Python ROS modules (rospy, rosgraph, genpy).
This leg rebuilds that: an interpreter made from tools/python_matrix.sh's Python 3.8 venv whose
sys.path holds that venv's site-packages and then Debian's /usr/lib/python3/dist-packages (a ``.pth``
file, as a ``--system-site-packages`` venv would place them), and the workspace's devel space (our
generated messages) on PYTHONPATH. The test itself and the master run on the main Python.

tools/python_matrix.sh runs it on every run (the 3.8 unit suite only when asked), with LTL_STACK_NOETIC_VENV naming that venv;
the main run skips it, saying so.
"""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
from helpers import RosProcess
from test_nodes_probe import make_session

pytestmark = [pytest.mark.ros, pytest.mark.timeout(600)]  # a hang guard, far above the waits

VENV = os.environ.get("LTL_STACK_NOETIC_VENV", "")
if not VENV:
    pytest.skip("the Python 3.8 ROS leg runs from tools/python_matrix.sh (LTL_STACK_NOETIC_VENV names its venv)",
                allow_module_level=True)

#: where Debian (and Ubuntu focal) keep their pure-Python ROS modules
DEBIAN_PYTHON = "/usr/lib/python3/dist-packages"

# stop follows person, step by step
SPEC = "[INPUT]\nperson\n\n[OUTPUT]\nstop\n\n[SYS_TRANS]\n| & stop' person' & ! stop' ! person'\n\n" \
       "[SYS_INIT]\n| & stop person & ! stop ! person\n"

WHERE = """
import json, sys
import dd, numpy, rospy, rosgraph, genpy, ltl_stack, ltl_stack.msg
print(json.dumps({"version": list(sys.version_info[:2]), "path": sys.path,
                  "files": {m.__name__: m.__file__ for m in (dd, numpy, rospy, rosgraph, genpy, ltl_stack.msg)}}))
"""


def purelib(python: str) -> str:
    return subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True, timeout=120).stdout.strip()


@pytest.fixture(scope="module")
def noetic_python(tmp_path_factory) -> str:
    """A Python 3.8 whose sys.path is the venv's packages, then Debian's ROS modules."""
    base = str(Path(VENV) / "bin" / "python")
    overlay = tmp_path_factory.mktemp("noetic") / "venv"
    subprocess.run([base, "-m", "venv", "--without-pip", str(overlay)], check=True, timeout=300)
    python = str(overlay / "bin" / "python")
    # .pth lines are read in order: the venv's site folder (and its own .pth files), then Debian's
    Path(purelib(python), "zz_noetic.pth").write_text(
        f"import site; site.addsitedir({purelib(base)!r})\n{DEBIAN_PYTHON}\n")
    return python


def devel_env(env: dict[str, str]) -> dict[str, str]:
    """``env`` with only the workspace's devel space on PYTHONPATH (not Debian's 3.11 folders)."""
    devel = [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if "/devel/lib/python3" in p]
    assert devel, f"no devel space on PYTHONPATH: {env.get('PYTHONPATH')!r} (source tools/env.sh)"
    return dict(env, PYTHONPATH=os.pathsep.join(devel))


def test_the_interpreter_puts_the_venv_before_debians_ros_modules(noetic_python):
    done = subprocess.run([noetic_python, "-c", WHERE], env=devel_env(dict(os.environ)), capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout)
    assert found["version"] == [3, 8], found["version"]
    venv_site = purelib(str(Path(VENV) / "bin" / "python"))
    assert found["path"].index(venv_site) < found["path"].index(DEBIAN_PYTHON), found["path"]
    files = found["files"]
    assert files["dd"].startswith(venv_site) and files["numpy"].startswith(venv_site), files
    for module in ("rospy", "rosgraph", "genpy"):
        assert files[module].startswith(DEBIAN_PYTHON + "/"), files
    assert "/devel/lib/python3" in files["ltl_stack.msg"], files


def test_executor_and_threshold_sensor_answer_an_input_change(noetic_python, request, tmp_path):
    from std_msgs.msg import Bool, Float64

    ros = make_session(request)
    ns = ros.ns.strip("/")
    spec = tmp_path / f"{ns}.slugsin"  # the executor's namespace is the spec's name
    spec.write_text(SPEC)
    env = devel_env(ros.master.env)
    devel = Path(env["PYTHONPATH"].split(os.pathsep)[0]).parents[2]  # .../devel

    def node(script: str, *args: str) -> RosProcess:
        proc = RosProcess([noetic_python, str(devel / "lib" / "ltl_stack" / script), *args], env,
                          tmp_path / f"{script}.log")
        ros.master.processes.append(proc)  # stopped when the session closes
        return proc

    stop = ros.record(f"/{ns}/outputs/stop", Bool)
    executor = node("controller_executor", str(spec))
    sensor = node("topic_threshold_sensor", f"__name:={ns}_person", f"_topic:=/{ns}/camera/person_distance",
                  "_type:=std_msgs/Float64", "_field:=data", "_comparison:=<", "_threshold:=1.5",
                  f"_proposition_topic:=/{ns}/inputs/person")
    try:
        stop.wait_last(lambda b: b.data is False, what="stop false while nobody is near")
        for distance, expected in ((0.8, True), (3.0, False), (1.0, True)):
            ros.publish(f"/{ns}/camera/person_distance", Float64(data=distance))
            stop.wait_last(lambda b, e=expected: b.data is e, what=f"stop {expected} at a person {distance} m away")
    except AssertionError as err:  # what the 3.8 nodes said (a traceback, an import error)
        raise AssertionError(f"{err}\n--- executor ---\n{executor.output()[-3000:]}\n"
                             f"--- sensor ---\n{sensor.output()[-3000:]}") from None
    log = executor.output()
    assert "Traceback" not in log, log[-4000:]
    assert "BDDs:" in log, log[-4000:]  # the backend line: this executor synthesized on 3.8's dd
