"""Bad input to the ROS tools, through the real scripts (``rosrun ltl_stack …``) against a real master.

Command-line tools (``set_propositions``, ``proposition_monitor``, ``send_proposition_goal``,
``controller_trace``): exactly one ``<tool>: error:`` line naming the argument or file, the exit
code of the one table (2 bad input, 3 no master), no traceback. Nodes (``timed_proposition_server``,
``scripted_environment``, ``region_sensor``): exactly one ``[FATAL]`` line naming the parameter or
file (and line), exit 2. No file is created or changed.
"""
from __future__ import annotations

import subprocess

import pytest
from helpers import (
    REPO_ROOT,
    RosMaster,
    assert_one_error_line,
    assert_one_fatal_line,
    closed_port,
    direct_script,
    folder_files,
    run_case,
    run_script,
    wait_for,
)

from ltl_stack.errors import Exit

pytestmark = pytest.mark.ros

DEEP = 100000
LONG = "7" * 5000
GOOD_SCHEDULE = "events:\n  - {at: 0.5, topic: /env/person, value: true}\n"
GOOD_REGIONS = ('Regions: # name\n[{"name": "boundary", "type": "rect", "position": [0, 0], "size": [10, 10]},\n'
                ' {"name": "left", "type": "rect", "position": [0, 0], "size": [5, 10]}]\n')
UNREACHABLE = f"http://127.0.0.1:{closed_port()}/"

# case: (command after `rosrun ltl_stack`, files {name: bytes}, exit code, expected text of the error line)
# {d} is the case's folder.
TOOLS = {
    "set_propositions illegal topic": (["set_propositions", "bad topic!", "a=1"], {}, Exit.BAD_INPUT,
                                       "argument topic: 'bad topic!' is not a legal ROS name"),
    "proposition_monitor illegal topic": (["proposition_monitor", "1abc"], {}, Exit.BAD_INPUT,
                                          "argument topic: '1abc' is not a legal ROS name"),
    "send_proposition_goal illegal action": (["send_proposition_goal", "my action"], {}, Exit.BAD_INPUT,
                                             "argument action: 'my action' is not a legal ROS name"),
    "controller_trace illegal topic": (["controller_trace", "a//b"], {}, Exit.BAD_INPUT,
                                       "argument topic: 'a//b' is not a legal ROS name"),
    "set_propositions malformed master URI": (["set_propositions", "/x", "a=1", "--master-uri", "garbage"], {},
                                              Exit.BAD_INPUT, "--master-uri 'garbage' is not a ROS master URI"),
    "proposition_monitor master port out of range": (
        ["proposition_monitor", "/x", "--master-uri", "http://127.0.0.1:99999/"], {}, Exit.BAD_INPUT,
        "--master-uri 'http://127.0.0.1:99999/' is not a ROS master URI"),
    "send_proposition_goal master URI scheme": (["send_proposition_goal", "/a", "--master-uri", "ftp://h:1/"], {},
                                                Exit.BAD_INPUT, "--master-uri 'ftp://h:1/' is not a ROS master URI"),
    "controller_trace malformed __master": (["controller_trace", "__master:=localhost"], {}, Exit.BAD_INPUT,
                                            "__master:= 'localhost' is not a ROS master URI"),
    "set_propositions unreachable master": (["set_propositions", "/x", "a=1", "--master-uri", UNREACHABLE,
                                             "--timeout", "1"], {}, Exit.NO_ROS, f"no ROS master at {UNREACHABLE}"),
    "proposition_monitor unreachable master": (["proposition_monitor", "/x", "--master-uri", UNREACHABLE,
                                                "--timeout", "1"], {}, Exit.NO_ROS, f"no ROS master at {UNREACHABLE}"),
    "send_proposition_goal unreachable master": (["send_proposition_goal", "/a", "--master-uri", UNREACHABLE,
                                                  "--timeout", "1"], {}, Exit.NO_ROS,
                                                 f"no ROS master at {UNREACHABLE}"),
    "send_proposition_goal no server": (["send_proposition_goal", "/nobody", "--timeout", "1"], {}, Exit.NO_ROS,
                                        "no action server at /nobody"),
    "set_propositions rate nan": (["set_propositions", "/x", "a=1", "--rate", "nan"], {}, Exit.BAD_INPUT,
                                  "argument --rate: 'nan' is not a number >= 0"),
    "set_propositions rate negative": (["set_propositions", "/x", "a=1", "--rate", "-5"], {}, Exit.BAD_INPUT,
                                       "argument --rate: '-5' is not a number >= 0"),
    "set_propositions long count": (["set_propositions", "/x", "a=1", "--wait-subscribers", LONG], {},
                                    Exit.BAD_INPUT, "argument --wait-subscribers: '7777777777"),
    "proposition_monitor negative count": (["proposition_monitor", "/x", "--count", "-1"], {}, Exit.BAD_INPUT,
                                           "argument --count: '-1' is not an integer >= 0"),
    "proposition_monitor timeout inf": (["proposition_monitor", "/x", "--timeout", "inf"], {}, Exit.BAD_INPUT,
                                        "argument --timeout: 'inf' is not a number > 0"),
    "send_proposition_goal timeout 0": (["send_proposition_goal", "/a", "--timeout", "0"], {}, Exit.BAD_INPUT,
                                        "argument --timeout: '0' is not a number > 0"),
    "send_proposition_goal cancel-after nan": (["send_proposition_goal", "/a", "--cancel-after", "nan"], {},
                                               Exit.BAD_INPUT, "argument --cancel-after: 'nan' is not a number"),
    "controller_trace long cycles": (["controller_trace", "--cycles", LONG], {}, Exit.BAD_INPUT,
                                     "has 5000 digits"),
    "controller_trace negative timeout": (["controller_trace", "--timeout", "-1"], {}, Exit.BAD_INPUT,
                                          "argument --timeout: '-1' is not a number >= 0"),
    "controller_trace binary spec": (["controller_trace", "--spec", "{d}/s.slugsin"],
                                     {"s.slugsin": b"[INPUT]\na\n\x00"}, Exit.BAD_INPUT,
                                     "{d}/s.slugsin:3: not a text spec file: it holds a NUL byte"),
    "controller_trace non-UTF-8 spec": (["controller_trace", "--spec", "{d}/s.slugsin"],
                                        {"s.slugsin": b"[INPUT]\n\xe9\n"}, Exit.BAD_INPUT,
                                        "{d}/s.slugsin:2: not a text spec file: not UTF-8"),
    "controller_executor spec FIFO": (["controller_executor", "{d}/s.slugsin"], {"s.slugsin": None},
                                      Exit.BAD_INPUT, "{d}/s.slugsin: is a FIFO (named pipe), not a regular file"),
    "controller_executor mapping /dev/zero": (["controller_executor", "{d}/s.slugsin", "/dev/zero"],
                                              {"s.slugsin": b"[INPUT]\na\n[OUTPUT]\nb\n"}, Exit.BAD_INPUT,
                                              "/dev/zero: is a character device, not a regular file"),
    "controller_executor mapping misfit": (["controller_executor", "{d}/s.slugsin", "{d}/m.yaml"],
                                           {"s.slugsin": b"[INPUT]\na\n[OUTPUT]\nb\n",
                                            "m.yaml": b"inputs:\n  nosuch: {node: /x}\n  other: {node: /y}\n"},
                                           Exit.BAD_INPUT, "{d}/m.yaml:2: input 'nosuch' is not a proposition of the "
                                                           "spec (its inputs: a) (and 1 more mapping errors)"),
    "controller_trace spec /dev/zero": (["controller_trace", "--spec", "/dev/zero"], {}, Exit.BAD_INPUT,
                                        "/dev/zero: is a character device, not a regular file"),
}

NODES = {
    "timed_proposition_server duration nan": (["timed_proposition_server", "_duration:=nan"], {},
                                              "parameter ~duration must be a number >= 0"),
    "timed_proposition_server rate 0": (["timed_proposition_server", "_feedback_rate:=0"], {},
                                        "parameter ~feedback_rate must be a number > 0"),
    "timed_proposition_server duration of 5000 digits": (["timed_proposition_server", f"_duration:={LONG}"], {},
                                                         "parameter ~duration must be a number of at most 18 digits, "
                                                         "got one of 5000 digits"),
    "timed_proposition_server duration of 22 digits": (["timed_proposition_server", "_duration:=" + "1" * 22], {},
                                                       "parameter ~duration must be a number of at most 18 digits"),
    "timed_proposition_server duration 1e19": (["timed_proposition_server", "_duration:=1e19"], {},
                                               "parameter ~duration must be a number of at most 18 digits"),
    "timed_proposition_server feedback rate 1e-300": (["timed_proposition_server", "_feedback_rate:=1e-300"], {},
                                                      "parameter ~feedback_rate must be 0 or at least 1e-09"),
    "sim_robot rate 1e-300": (["sim_robot", "_rate:=1e-300"], {}, "parameter ~rate must be 0 or at least 1e-09"),
    "topic_threshold_sensor rate 1e-300": (["topic_threshold_sensor", "_topic:=/x", "_type:=std_msgs/Float64",
                                            "_rate:=1e-300"], {}, "parameter ~rate must be 0 or at least 1e-09"),
    "scripted_environment rate 1e-300": (["scripted_environment", "_schedule:=/nonexistent", "_rate:=1e-300"], {},
                                         "parameter ~rate must be 0 or at least 1e-09"),
    "timed_proposition_server illegal action": (["timed_proposition_server", "_action:=bad-name"], {},
                                                "parameter ~action must be a legal ROS name"),
    "scripted_environment binary schedule": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                             {"env.yaml": GOOD_SCHEDULE.encode() + b"\x00"},
                                             "{d}/env.yaml:3: not a text schedule: it holds a NUL byte"),
    "scripted_environment non-UTF-8 schedule": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                                {"env.yaml": b"events:\n  - {at: 1, topic: /caf\xe9, value: 1}\n"},
                                                "{d}/env.yaml:2: not a text schedule: not UTF-8"),
    "scripted_environment key 5": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                   {"env.yaml": GOOD_SCHEDULE.encode() + b"5: x\n"},
                                   "{d}/env.yaml:3: key '5' is not a string"),
    "scripted_environment key yes": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                     {"env.yaml": b"yes: 1\n" + GOOD_SCHEDULE.encode()},
                                     "{d}/env.yaml:1: key 'yes' is not a string"),
    "scripted_environment key ~": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                   {"env.yaml": b"~: 1\n" + GOOD_SCHEDULE.encode()},
                                   "{d}/env.yaml:1: key '~' is not a string"),
    "scripted_environment deep schedule": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                           {"env.yaml": b"events: " + b"[" * DEEP},
                                           "{d}/env.yaml:1: nested more than 100 levels deep"),
    "scripted_environment long integer": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                          {"env.yaml": GOOD_SCHEDULE.replace("0.5", LONG).encode()},
                                          "{d}/env.yaml:2: integer of 5000 digits"),
    "scripted_environment illegal event topic": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                                 {"env.yaml": GOOD_SCHEDULE.replace("/env/person", "'a b'").encode()},
                                                 "{d}/env.yaml:2: event #0: 'topic' must be a ROS topic name"),
    "scripted_environment rate nan": (["scripted_environment", "_schedule:={d}/env.yaml", "_rate:=nan"],
                                      {"env.yaml": GOOD_SCHEDULE.encode()}, "parameter ~rate must be a number > 0"),
    "scripted_environment time_scale 0": (["scripted_environment", "_schedule:={d}/env.yaml", "_time_scale:=0"],
                                          {"env.yaml": GOOD_SCHEDULE.encode()},
                                          "parameter ~time_scale must be a number > 0"),
    "scripted_environment schedule /dev/zero": (["scripted_environment", "_schedule:=/dev/zero"], {},
                                                "/dev/zero: is a character device, not a regular file"),
    "scripted_environment schedule FIFO": (["scripted_environment", "_schedule:={d}/env.yaml"], {"env.yaml": None},
                                           "{d}/env.yaml: is a FIFO (named pipe), not a regular file"),
    "region_sensor region map FIFO": (["region_sensor", "_region:=left", "_regions_file:={d}/map.regions"],
                                      {"map.regions": None}, "{d}/map.regions: is a FIFO (named pipe), not a regular"),
    "region_sensor region map /dev/zero": (["region_sensor", "_region:=left", "_regions_file:=/dev/zero"], {},
                                           "/dev/zero: is a character device, not a regular file"),
    "scripted_environment loop 'false'": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                          {"env.yaml": b"loop: 'false'\n" + GOOD_SCHEDULE.encode()},
                                          "{d}/env.yaml: 'loop' must be true or false (unquoted), got 'false'"),
    "scripted_environment loop period 1 ns": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                              {"env.yaml": b"loop: true\nperiod: 1.0e-9\nevents:\n"
                                                           b"  - {at: 0, topic: /env/person, value: true}\n"},
                                              "'loop: true' needs events and a period of at least 0.01 s"),
    "story_environment user names no proposition": (["story_environment", "_story:={d}/story.yaml"],
                                                    {"story.yaml": b"inputs: {door: true}\nuser: 'TRUE'\nbeats: []\n"},
                                                    "{d}/story.yaml:2: 'user': 'TRUE' names no proposition"),
    "story_environment user does not parse": (["story_environment", "_story:={d}/story.yaml"],
                                              {"story.yaml": b"inputs: {door: true}\nuser: 'door &'\nbeats: []\n"},
                                              "{d}/story.yaml:2: 'user': 'door &' does not parse"),
    "region_sensor binary region map": (["region_sensor", "_region:=left", "_regions_file:={d}/map.regions"],
                                        {"map.regions": GOOD_REGIONS.encode() + b"\x00"},
                                        "{d}/map.regions:4: not a text regions file: it holds a NUL byte"),
    "region_sensor non-UTF-8 region map": (["region_sensor", "_region:=left", "_regions_file:={d}/map.regions"],
                                           {"map.regions": b"Regions: # \xe9\n[]\n"},
                                           "{d}/map.regions:1: not a text regions file: not UTF-8"),
    "region_sensor deep region map": (["region_sensor", "_region:=left", "_regions_file:={d}/map.regions"],
                                      {"map.regions": b"Regions:\n" + b"[" * DEEP + b"\n"},
                                      "{d}/map.regions:2: Regions section: nested more than 100 levels deep"),
    "region_sensor long integer region map": (
        ["region_sensor", "_region:=left", "_regions_file:={d}/map.regions"],
        {"map.regions": GOOD_REGIONS.replace('"size": [5, 10]', f'"size": [{LONG}, 10]').encode()},
        "{d}/map.regions: Regions section: invalid JSON value"),
}


@pytest.fixture(scope="module")
def master(tmp_path_factory):
    """One real master for the whole table (each case is a short-lived process)."""
    ros = RosMaster(tmp_path_factory.mktemp("master"))
    try:
        yield ros
    finally:
        ros.shutdown()


@pytest.mark.parametrize("case", list(TOOLS))
def test_tool_bad_input_one_error_and_exit_code(master, tmp_path, case):
    command, files, code, message = TOOLS[case]
    done, before = run_case(master, tmp_path, command, files)
    assert_one_error_line(done, command[0], code, message.format(d=tmp_path))
    assert folder_files(tmp_path) == before


@pytest.mark.parametrize("case", list(NODES))
def test_node_bad_parameter_or_file_one_fatal_and_exit_2(master, tmp_path, case):
    command, files, message = NODES[case]
    # a node name of its own: the master keeps private parameters (_x:=…) after the node is gone
    name = f"__name:=case{list(NODES).index(case)}"
    done, before = run_case(master, tmp_path, [*command, name], files)
    assert_one_fatal_line(done, message.format(d=tmp_path))
    assert folder_files(tmp_path) == before


@pytest.mark.parametrize("tool", ["timed_proposition_server", "scripted_environment", "set_propositions",
                                  "proposition_monitor", "send_proposition_goal", "controller_trace"])
def test_help_prints_help_and_starts_nothing(master, tool):
    done = subprocess.run(direct_script(["rosrun", "ltl_stack", tool, "--help"], master.env), env=master.env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0 and "usage:" in done.stdout and "exit codes:" in done.stdout, done
    nodes = {n for _, who in master.system_state()[0] for n in who}
    assert not any(tool in n for n in nodes), nodes


@pytest.mark.parametrize("tool", ["set_propositions", "proposition_monitor", "controller_trace"])
def test_master_uri_of_a_node_is_refused_not_waited_on(master, tmp_path, tool):
    """A node's XML-RPC URI answers getPid like a master; rospy would wait forever to register there."""
    schedule = tmp_path / "env.yaml"
    schedule.write_text(GOOD_SCHEDULE)
    node = master.run(["rosrun", "ltl_stack", "scripted_environment", f"_schedule:={schedule}",
                       f"__name:=uri_probe_{tool}"], name=f"uri_probe_{tool}")
    try:
        def node_uri():
            code, _, uri = master.proxy().lookupNode("/pytest", f"/uri_probe_{tool}")
            return uri if code == 1 else None

        uri = wait_for(node_uri, 60, "the probe node to register")
        args = {"set_propositions": ["/x", "a=1"], "proposition_monitor": ["/x"], "controller_trace": []}[tool]
        done = run_script(["rosrun", "ltl_stack", tool, *args, "--master-uri", uri], env=master.env,
                              capture_output=True, text=True, timeout=300, cwd=tmp_path)
        assert done.returncode == Exit.NO_ROS, (done.returncode, done.stdout[-1000:], done.stderr[-2000:])
        assert done.stderr.strip().splitlines()[-1].startswith(f"{tool}: error: {uri} answers but is not a ROS master"), \
            done.stderr[-2000:]
        assert "Traceback" not in done.stderr + done.stdout
    finally:
        node.stop()


SCRIPTS = sorted(p.name for p in (REPO_ROOT / "scripts").iterdir() if p.is_file())


def test_every_script_is_covered():
    assert len(SCRIPTS) >= 25 and "synthesize" in SCRIPTS and "story_environment" in SCRIPTS, SCRIPTS


@pytest.mark.parametrize("tool", SCRIPTS)
def test_help_of_every_script_with_stdout_closed_is_one_error_line_and_exit_4(master, tool, tmp_path):
    """``tool --help >&-``: no traceback, one line saying stdout is closed, exit 4 (as for a full disk)."""
    command = ["bash", "-c", 'exec "$@" >&-', "bash", *direct_script(["rosrun", "ltl_stack", tool, "--help"],
                                                                    master.env)]
    done = subprocess.run(command, env=master.env, stderr=subprocess.PIPE, text=True, timeout=300, cwd=tmp_path)
    assert "Traceback" not in done.stderr, done.stderr[-3000:]
    assert (done.returncode, done.stderr) == (Exit.WRITE_FAILED, f"{tool}: error: cannot write the output: "
                                                                 "standard output is closed\n"), done.stderr[-2000:]


@pytest.mark.parametrize("case", list(NODES)[:3])
def test_a_node_with_stdout_closed_still_gives_its_one_fatal_line(master, tmp_path, case):
    command, files, message = NODES[case]
    args = [a.format(d=tmp_path) for a in [*command, f"__name:=closed{list(NODES).index(case)}"]]
    done = subprocess.run(["bash", "-c", 'exec "$@" >&-', "bash",
                           *direct_script(["rosrun", "ltl_stack", *args], master.env)],
                          env=master.env, stderr=subprocess.PIPE, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == Exit.BAD_INPUT, (done.returncode, done.stderr[-2000:])
    fatal = [line for line in done.stderr.splitlines() if "[FATAL]" in line]
    assert len(fatal) == 1 and message in fatal[0] and "Traceback" not in done.stderr, done.stderr[-2000:]
