"""Velocity limits (Fig. 2.2 YAML), the B.1 check and the B.2 scaling of Eqs. 2.1/2.2."""
import pytest
from helpers import require_shared
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.errors import InputError
from ltl_stack.transfer.errors import TransferError
from ltl_stack.transfer.limits import AxisLimit, infer_drive, load_limits, parse_limits, scale_command

JACKAL_X, TURTLEBOT_X = AxisLimit(-2.0, 2.0), AxisLimit(-0.8, 0.8)
JACKAL_Z, TURTLEBOT_Z = AxisLimit(-4.0, 4.0), AxisLimit(-5.4, 5.4)


def test_example_1_figures_of_the_thesis():
    assert scale_command(0.5, JACKAL_X, TURTLEBOT_X) == pytest.approx(0.2)
    assert scale_command(-0.5, JACKAL_X, TURTLEBOT_X) == pytest.approx(-0.2)
    assert scale_command(0.5, JACKAL_Z, TURTLEBOT_Z) == pytest.approx(0.675)
    assert scale_command(-0.5, JACKAL_Z, TURTLEBOT_Z) == pytest.approx(-0.675)


def test_example_2_figure_of_the_thesis():
    assert scale_command(0.3, TURTLEBOT_X, JACKAL_X) == pytest.approx(0.75)


def test_negative_commands_scale_against_the_lower_limits():
    source, target = AxisLimit(-1.0, 4.0), AxisLimit(-0.5, 1.0)
    assert scale_command(-1.0, source, target) == pytest.approx(-0.5)
    assert scale_command(-0.5, source, target) == pytest.approx(-0.25)
    assert scale_command(2.0, source, target) == pytest.approx(0.5)


def test_deadbands_follow_eqs_2_1_and_2_2():
    source, target = AxisLimit(-80, 80, 30), AxisLimit(-2, 2, 0.5)
    assert scale_command(80, source, target) == pytest.approx(2)
    assert scale_command(-80, source, target) == pytest.approx(-2)
    assert scale_command(55, source, target) == pytest.approx(1.25)     # half-way above the deadband
    assert scale_command(-55, source, target) == pytest.approx(-1.25)
    assert scale_command(20, source, target) == 0.0                      # inside the deadband: no motion


def test_missing_range_cannot_be_scaled():
    with pytest.raises(ValueError, match="target"):
        scale_command(0.5, JACKAL_X, AxisLimit(None, None))
    with pytest.raises(ValueError, match="source"):
        scale_command(-0.5, AxisLimit(None, 1.0), TURTLEBOT_X)


limit_pairs = st.tuples(st.floats(-10, -0.1), st.floats(0.1, 10), st.floats(0, 0.05))


@given(limit_pairs, limit_pairs, st.floats(-1, 1))
def test_scaled_commands_keep_their_sign_and_stay_within_the_target(src, tgt, fraction):
    source, target = AxisLimit(*src), AxisLimit(*tgt)
    value = fraction * (source.upper if fraction >= 0 else -source.lower)
    got = scale_command(value, source, target)
    assert target.allows(got), (value, got)
    if abs(value) > source.deadband:
        assert (got > 0) == (value > 0), (value, got)
    else:
        assert got == 0.0, got


@given(limit_pairs, limit_pairs, st.floats(0, 1), st.floats(0, 1))
def test_scaling_preserves_order(src, tgt, a, b):
    source, target = AxisLimit(*src), AxisLimit(*tgt)
    lo, hi = sorted((a * source.upper, b * source.upper))
    assert scale_command(lo, source, target) <= scale_command(hi, source, target) + 1e-12


def test_the_shared_limit_files_load_with_none_meaning_not_applicable():
    folder = require_shared("robots", "limits")
    jackal = load_limits(folder / "jackal.yaml")
    assert jackal["linear.x"] == AxisLimit(-2.0, 2.0, 0.0), jackal["linear.x"]
    assert not jackal["linear.y"].applicable()
    assert jackal.applicable_fields() == ["linear.x", "angular.z"], jackal.applicable_fields()
    sphero = load_limits(folder / "sphero.yaml")
    assert sphero["linear.y"] == AxisLimit(-80, 80, 30), sphero["linear.y"]
    for path in sorted(folder.glob("*.yaml")):
        load_limits(path)  # every shared file is valid


@pytest.mark.parametrize("robot, drive", [("jackal", "differential"), ("turtlebot", "differential"),
                                          ("youbot", "holonomic"), ("sphero", "holonomic"),
                                          ("pepper", "differential")])
def test_drive_inferred_from_limits(robot, drive):
    limits = load_limits(require_shared("robots", "limits", f"{robot}.yaml"))
    assert infer_drive(limits) == drive, infer_drive(limits)


@pytest.mark.parametrize("data, where", [
    ({"linear": {"x": {"lower": "fast"}}}, "linear.x.lower"),
    ({"linear": {"w": {}}}, "linear.w"),
    ({"spin": {}}, "spin"),
    ({"angular": {"z": {"lower": 1.0, "upper": 2.0}}}, "angular.z"),
    ({"linear": {"x": {"lower": -1, "upper": 1, "deadband": 2}}}, "linear.x"),
])
def test_bad_limits_name_the_file_and_the_key(data, where):
    with pytest.raises(TransferError) as err:
        parse_limits(data, "robot.yaml")
    assert str(err.value).startswith(f"robot.yaml: {where}: "), str(err.value)


def test_unreadable_yaml_names_the_line(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("linear:\n  x: [1,\n")
    with pytest.raises(InputError) as err:
        load_limits(bad)
    assert str(err.value).startswith(f"{bad}:3: invalid YAML"), str(err.value)
