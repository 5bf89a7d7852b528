"""The Example 7 (two youBots) and Example 9 (four spheros) scenarios: their proposition launch files
are what generate_launch makes of their mappings, and the mappings fit their specs."""
from __future__ import annotations

from pathlib import Path

import pytest

from ltl_stack.runtime.config.launch import generate_launch
from ltl_stack.runtime.config.mapping import check_mapping, load_mapping
from ltl_stack.spec import load_spec

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize(("name", "spec"), [("spheros", "config/spheros/spheros.slugsin"),
                                            ("youbots", "config/simple/simple.structuredslugs")])
def test_proposition_launch_is_generated_from_the_mapping(name, spec, monkeypatch):
    monkeypatch.chdir(ROOT)  # the launch file names the mapping as generate_launch was run: from the root
    mapping = load_mapping(f"config/{name}/{name}.yaml")
    loaded = load_spec(ROOT / spec)
    assert check_mapping(mapping, loaded.inputs, loaded.outputs) == []
    result = generate_launch(mapping, spec_path=str((ROOT / spec).resolve()), namespace=name,
                             propositions=(loaded.inputs, loaded.outputs))
    assert result.warnings == []
    assert (ROOT / "launch" / f"{name}_propositions.launch").read_text() == result.xml, \
        f"regenerate: rosrun ltl_stack generate_launch config/{name}/{name}.yaml --spec {spec} " \
        f"-o launch/{name}_propositions.launch"


def test_every_sphero_output_drives_all_four_robots():
    mapping = load_mapping(ROOT / "config" / "spheros" / "spheros.yaml")
    robots = ["sphero_wpw", "sphero_ggw", "sphero_rgw", "sphero_wpp"]
    for prop, entries in mapping.outputs.items():
        topics = sorted(e.parameters["publish_topic"] for e in entries)
        kind = "cmd_vel" if prop.startswith("move") or prop == "stop" else "set_color"
        assert topics == sorted(f"{r}/{kind}" for r in robots), prop
