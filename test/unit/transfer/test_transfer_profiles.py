"""Robot profiles from a robots folder: the shared layout and explicit profile files."""
import pytest
from helpers import require_shared

from ltl_stack.transfer.errors import TransferError
from ltl_stack.transfer.profiles import list_robots, load_profile


@pytest.mark.parametrize("robot, urdf, srdf, drive", [
    ("jackal", None, None, "differential"),
    ("ur5", "ur5.urdf", None, "none"),
    ("j2n6s300", "j2n6s300.urdf", "j2n6s300.srdf", "none"),
    ("nao", "nao_robot_v3.urdf", "nao.srdf", "holonomic"),
    ("pr2", "pr2.urdf", "pr2.srdf", "holonomic"),
    ("pepper", "pepper.urdf", "pepper.srdf", "holonomic"),   # its limits say linear.y 0..0; the table knows
    ("fetch", "fetch.urdf", "fetch.srdf", "differential"),
    ("jaco", "jaco_arm.urdf", "jaco.srdf", "none"),
])
def test_shared_layout_by_convention(robot, urdf, srdf, drive):
    profile = load_profile(require_shared("robots"), robot)
    assert (profile.urdf.name if profile.urdf else None) == urdf, profile
    assert (profile.srdf.name if profile.srdf else None) == srdf, profile
    assert profile.drive == drive, profile


def test_profile_file_overrides_conventions(tmp_path):
    (tmp_path / "limits").mkdir()
    (tmp_path / "limits" / "bot.yaml").write_text("linear: {x: {lower: -1, upper: 1}}\n")
    (tmp_path / "my.yaml").write_text("linear: {x: {lower: -2, upper: 2}}\n")
    (tmp_path / "bot.yaml").write_text("drive: holonomic\nlimits: my.yaml\n")
    profile = load_profile(tmp_path, "bot")
    assert (profile.drive, profile.drive_source, profile.limits["linear.x"].upper) == ("holonomic", "profile", 2.0)
    assert list_robots(tmp_path) == ["bot", "my"], list_robots(tmp_path)


@pytest.mark.parametrize("content, message", [
    ("drive: tracked\n", "drive must be one of"),
    ("urdf: missing.urdf\n", "urdf file 'missing.urdf' does not exist"),
    ("colour: red\n", "unknown key(s) ['colour']"),
])
def test_bad_profiles_name_file_and_key(tmp_path, content, message):
    (tmp_path / "bot.yaml").write_text(content)
    with pytest.raises(TransferError) as err:
        load_profile(tmp_path, "bot")
    assert str(err.value).startswith(str(tmp_path / "bot.yaml")) and message in str(err.value), str(err.value)
