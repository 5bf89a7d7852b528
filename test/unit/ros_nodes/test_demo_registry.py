"""``./tools/demo``'s scenario registry (``sim.demo.SCENARIOS``): every entry runs something that
exists, ``--help`` lists them all, and the story scenarios' stories fit their specs."""
from __future__ import annotations

import re

import pytest

from ltl_stack.runtime.resilience.story import load_story
from ltl_stack.sim.demo import SCENARIOS, Problems, build_parser, package_dir
from ltl_stack.spec import load_spec

ROOT = package_dir()


def test_default_scenario_is_still_clean_and_patrol():
    assert build_parser().parse_args([]).scenario == "clean_and_patrol"


def test_help_lists_every_scenario_with_its_description():
    text = build_parser().format_help()
    for name, scenario in SCENARIOS.items():
        assert f"  {name}: {scenario.description[:40]}" in text


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_each_scenario_names_a_launch_file_and_its_arguments(name):
    scenario = SCENARIOS[name]
    launch = (ROOT / "launch" / scenario.launch).read_text()
    assert f'<group ns="{scenario.namespace}">' in launch or f"ns=\"{scenario.namespace}\"" in launch
    for arg in scenario.launch_args:
        key = arg.partition(":=")[0]
        assert f'<arg name="{key}"' in launch, (name, key)
    if scenario.story:
        config = ROOT / "config" / (scenario.config or scenario.namespace)
        specs = list(config.glob("*.structuredslugs"))
        load_story(config / "story.yaml").check(load_spec(specs[0]))


@pytest.mark.parametrize("name", [n for n, s in SCENARIOS.items() if s.story])
def test_story_scenarios_pass_only_executor_options_that_exist(name):
    """resilience:= words become executor ~params in the launch file (``<param name="recovery"
    value="false" if="... 'no-recovery' in ...">``): each word the registry passes is one the
    launch file maps, onto an option the executor declares, and the other options the demo's story
    runs rely on exist too."""
    import argparse

    from ltl_stack.runtime.executor.options import add_option_arguments

    parser = argparse.ArgumentParser()
    add_option_arguments(parser)
    flags = {s for action in parser._actions for s in action.option_strings}
    launch = (ROOT / "launch" / SCENARIOS[name].launch).read_text()
    for arg in SCENARIOS[name].launch_args:
        key, _, value = arg.partition(":=")
        if key != "resilience":
            continue
        assert len(value.split()) == 2, value
        for word in value.split():
            assert f"--{word}" in flags, word
            option = word[3:] if word.startswith("no-") else word
            assert re.search(rf'<param name="{option}" value="{"false" if word.startswith("no-") else "true"}" '
                             rf"if=\"\$\(eval '{word}' in arg\('resilience'\)", launch), (name, word)
    for flag in ("--characterize-after-transitions", "--input-window", "--rate"):
        assert flag in flags, flag


def test_the_launch_log_names_the_first_node_that_died(tmp_path):
    """The demo stops as soon as roslaunch reports a scenario node's end, instead of
    waiting out --timeout; a line written in two pieces is read whole."""
    from ltl_stack.sim.demo import LaunchLog

    log = tmp_path / "roslaunch.log"
    log.write_text("started roslaunch server http://127.0.0.1:1/\nprocess[alice/sim_robot-1]: started with pid [7]\n")
    watch = LaunchLog(log)
    assert watch.died() is None
    with open(log, "a") as f:
        f.write("\x1b[31m[alice/story_environment-9] process has died [pid 42, exit code 2, cmd /x/story_en")
    assert watch.died() is None  # not a whole line yet
    with open(log, "a") as f:
        f.write("vironment __name:=story_environment].\nlog file: /tmp/x.log\n")
    assert watch.died() == "node alice/story_environment died (exit code 2)"
    assert watch.died() is None  # told once
    assert LaunchLog(tmp_path / "absent.log").died() is None


@pytest.mark.parametrize("name", [n for n, s in SCENARIOS.items() if s.negotiation is not None])
def test_negotiation_scenarios_name_robots_and_a_world_their_launch_file_starts(name):
    """The negotiation follower subscribes to /<namespace>/<robot>/… and /<namespace>/<events>: each
    robot is a group of the launch file and the world node publishing the events is started there."""
    scenario = SCENARIOS[name]
    launch = (ROOT / "launch" / scenario.launch).read_text()
    for robot, role in scenario.negotiation.robots:
        assert f'<group ns="{robot}"' in launch, (robot, role)  # (started unless start_<robot>:=false)
    node = scenario.negotiation.events.split("/")[0]
    assert f'name="{node}"' in launch, node


def test_the_kitchen_is_over_when_c_has_cooked_and_d_is_back_in_company_after_delivering():
    finished = SCENARIOS["kitchen"].negotiation.finished
    cooked, back = "C cooked the ingredients", "D is in company"
    delivered = "D delivered the ingredients to storage: ingredientArrived"
    assert finished([delivered, "A passed the ingredients to C", cooked, back])
    assert finished([back, delivered, back, cooked])
    assert not finished([back, delivered, cooked])          # in company only before the delivery
    assert not finished([delivered, back])                  # C has not cooked
    assert not finished([cooked, back, "D is in road"])     # nothing delivered


def test_the_demo_driver_holds_no_scenario_data():
    """Scenario data (robots, event texts) lives in the registry's entries, not in the driver's loop."""
    source = (ROOT / "src" / "ltl_stack" / "sim" / "demo.py").read_text()
    driver = source[source.index("def _run("):]
    for word in ("kitchen", "clean_and_patrol", "DeliveryAgent", "cooked", '"D"'):
        assert word not in driver, word


def test_a_standing_error_is_one_problem_however_often_diagnostics_repeat_it():
    problems = Problems()
    said = [problems.new("executor: health", True, "violated") for _ in range(5)]
    assert said == [True, False, False, False, False] and problems == ["violated"]
    assert problems.new("executor: health", True, "aborted")  # another error of the same status
    assert not problems.new("executor: health", False, "ok")  # cleared ...
    assert problems.new("executor: health", True, "aborted")  # ... and back: a new problem
    assert not problems.new("executor: mode", False, "normal")
    assert problems == ["violated", "aborted", "aborted"]
