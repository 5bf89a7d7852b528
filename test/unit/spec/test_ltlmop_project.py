"""LTLMoP project files as LTLMoP ships them: the container, enabled flags, compile options,
both .regions formats and the free space LTLMoP's decomposition turns into regions."""
from __future__ import annotations

from pathlib import Path

import pytest

from ltl_stack.spec import load_spec
from ltl_stack.spec.english_files import read_english
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.region_map import parse_region_map
from ltl_stack.synthesis import is_realizable

DATA = Path(__file__).resolve().parents[2] / "data" / "ltlmop"
HALL = DATA / "hall.spec"


def _variant(tmp_path: Path, *replacements: tuple[str, str], name: str = "hall.spec") -> Path:
    """A copy of hall.spec (with its maps) with some lines changed."""
    text = HALL.read_text()
    for old, new in replacements:
        assert old in text
        text = text.replace(old, new)
    for regions in DATA.glob("*.regions"):
        (tmp_path / regions.name).write_text(regions.read_text())
    path = tmp_path / name
    path.write_text(text)
    return path


def test_project_file_as_shipped_reads_through_load_spec():
    spec = load_spec(HALL)
    # enabled flags: beep and alarm are listed with 0 and are not part of the spec
    assert "beep" not in spec.outputs and "alarm" not in spec.inputs
    assert {"load", "unload", "loaded", "office", "lab", "dock", "others"} <= set(spec.outputs)
    assert spec.inputs == ["parcel"]  # regions are where the robot is (no R_rc without fastslow)
    assert is_realizable(spec)
    lines = {c.line for c in spec.sys_liveness}
    assert len(spec.sys_liveness) == 5 and 55 in lines  # 'visit all rooms' is one goal per room


def test_free_space_inside_the_boundary_connects_the_rooms():
    english = read_english(HALL.read_text(), str(HALL))
    topology = english.declarations.topology
    assert topology.regions == ["office", "lab", "dock", "others"]  # 'Boundary' (any case) is not a region
    assert topology.neighbours("others") == {"office", "lab", "dock"}
    assert topology.neighbours("office") == {"others"}
    assert english.spec.warnings == []


def test_without_decompose_isolated_rooms_are_named_in_a_warning(tmp_path):
    path = _variant(tmp_path, ("decompose: True", "decompose: False"))
    spec = load_spec(path)
    assert "others" not in spec.outputs
    assert len(spec.warnings) == 3 and all("touches no other region" in w for w in spec.warnings)
    assert any("region office " in w for w in spec.warnings)
    assert not is_realizable(spec)


def test_tab_separated_regions_read_like_json():
    json_map = parse_region_map((DATA / "hall.regions").read_text(), "hall.regions", decompose=True)
    tab_map = parse_region_map((DATA / "hall_tabs.regions").read_text(), "hall_tabs.regions", decompose=True)
    assert json_map.regions == tab_map.regions
    assert json_map.adjacent == tab_map.adjacent


def test_project_with_the_older_region_format(tmp_path):
    path = _variant(tmp_path, ("hall.regions\n", "hall_tabs.regions\n"))
    assert is_realizable(load_spec(path))


def test_fastslow_uses_activation_completion_regions(tmp_path):
    spec = load_spec(_variant(tmp_path, ("fastslow: False", "fastslow: True")))
    assert {"office_rc", "others_rc"} <= set(spec.inputs)
    assert is_realizable(spec)


def test_slurp_is_refused_in_one_line_naming_it(tmp_path):
    path = _variant(tmp_path, ("parser: structured", "parser: slurp"))
    with pytest.raises(SpecError) as caught:
        load_spec(path)
    assert "SLURP" in str(caught.value) and "parser: slurp" in str(caught.value)
    assert str(caught.value).startswith(f"{path}:15:")
    assert "\n" not in str(caught.value)


def test_a_disabled_proposition_is_named_as_disabled(tmp_path):
    path = _variant(tmp_path, ("infinitely often not parcel", "infinitely often not alarm"))
    with pytest.raises(SpecError, match=r"'alarm' is a sensor the project disables \('alarm, 0' under Sensors:\)"):
        load_spec(path)


def test_raw_ltl_project(tmp_path):
    text = HALL.read_text()
    spec_part = text[:text.index("Spec:")] + (
        "Spec: # raw LTL\n"
        "!e.parcel\n"
        "[]<>(!parcel)\n"
        "----\n"
        "s.office & !load\n"
        "[](next(load) -> (next(dock) & !loaded))\n"
        "[](next(s.loaded) <-> (load | (loaded & !unload)))\n"
        "[](next(unload) <-> (office & loaded))\n"
        "[]<>(dock)\n"
        "[]<>(lab)\n"
        "[](next(load) -> STAY_THERE)\n")
    spec_part = spec_part.replace("parser: structured", "parser: ltl")
    path = tmp_path / "raw.spec"
    path.write_text(spec_part)
    for regions in DATA.glob("*.regions"):
        (tmp_path / regions.name).write_text(regions.read_text())
    spec = load_spec(path)
    assert [c.line for c in spec.env_init] == [43] and len(spec.env_liveness) == 1
    assert len(spec.sys_liveness) == 2
    text_of = {c.text for c in spec.sys_safety}
    assert "[](next(s.loaded) <-> (load | (loaded & !unload)))" in text_of
    stay = [c.formula for c in spec.sys_safety if c.text == "[](next(load) -> STAY_THERE)"]
    assert len(stay) == 1 and "dock" in str(stay[0]) and "others" in str(stay[0])  # every region keeps its value
    assert is_realizable(spec)


def test_raw_ltl_without_the_dashes_is_an_error(tmp_path):
    text = HALL.read_text().replace("parser: structured", "parser: ltl")
    text = text[:text.index("Spec:")] + "Spec:\n[]<>(dock)\n"
    path = tmp_path / "raw.spec"
    path.write_text(text)
    for regions in DATA.glob("*.regions"):
        (tmp_path / regions.name).write_text(regions.read_text())
    with pytest.raises(SpecError, match="a line of dashes"):
        load_spec(path)


def test_between_is_the_area_ltlmop_computes(tmp_path):
    """'between office and lab' is the convex hull of both without them (LTLMoP's findRegionBetween):
    here the stretch of hall between the two rooms, cut out of the free space."""
    path = _variant(tmp_path, ("if you are sensing parcel then visit dock",
                               "if you are sensing parcel then visit between office and lab"))
    english = read_english(path.read_text(), str(path))
    areas = english.declarations.areas
    topology = english.declarations.topology
    assert set(areas) == {"office", "lab", "dock", "between_office_and_lab", "others"}
    (middle,) = areas["between_office_and_lab"]
    touching = {area for area, pieces in areas.items() for p in pieces if p in topology.neighbours(middle)}
    assert {"office", "lab", "others"} <= touching and "dock" not in touching
    goal = [c for c in english.spec.sys_liveness if c.line == 57]
    assert len(goal) == 1 and middle in {v.name for v in _vars(goal[0].formula)}
    assert is_realizable(english.spec)


def test_overlapping_regions_are_cut_into_pieces(tmp_path):
    (tmp_path / "o.regions").write_text(
        "Regions:\n[{\"name\": \"boundary\", \"type\": \"rect\", \"position\": [0, 0], \"size\": [30, 10]},\n"
        " {\"name\": \"a\", \"type\": \"rect\", \"position\": [0, 0], \"size\": [20, 10]},\n"
        " {\"name\": \"b\", \"type\": \"rect\", \"position\": [10, 0], \"size\": [20, 10]}]\n")
    text = HALL.read_text().replace("hall.regions\n", "o.regions\n")
    text = text[:text.index("Spec:")] + "Spec:\nvisit a\nvisit b\nalways not (a and b)\n"
    path = tmp_path / "o.spec"
    path.write_text(text)
    english = read_english(text, str(path))
    areas = english.declarations.areas
    assert len(english.spec.outputs) == 3 + 3  # load, unload, loaded and the pieces a-only, both, b-only
    assert len(set(areas["a"]) & set(areas["b"])) == 1
    assert not is_realizable(english.spec)  # a only and b only do not touch: the robot must cross both


def _vars(formula):
    from ltl_stack.spec.formula import Var, walk

    return [v for v in walk(formula) if isinstance(v, Var)]


def test_an_overlay_that_would_make_too_many_pieces_is_refused(monkeypatch):
    import json

    from ltl_stack.spec import region_map

    monkeypatch.setattr(region_map, "MAX_PIECES", 30)
    cells = [{"name": "boundary", "type": "rect", "position": [0, 0], "size": [100, 100]}]
    cells += [{"name": f"r{i}", "type": "rect", "position": [3 * i, 3 * i], "size": [40, 40]} for i in range(20)]
    with pytest.raises(SpecError, match="more than 30 pieces; refused"):
        parse_region_map("Regions:\n" + json.dumps(cells) + "\n", "x.regions", decompose=True)
