"""Robot profiles: name, drive type, velocity limits, URDF, SRDF and channel statistics.

A robots folder ``DIR`` is read with two conventions, so that the shared folder works as it is:

* an optional profile ``DIR/<robot>.yaml`` with keys ``name``, ``drive`` (differential | holonomic |
  none), ``limits``, ``urdf``, ``srdf``, ``channels`` (paths relative to ``DIR``; ``urdf`` and ``srdf``
  may name our YAML data of ``robot_data`` instead of the XML files);
* otherwise, or for any key the profile leaves out, ``DIR/limits/<robot>.yaml``,
  ``DIR/urdf/<robot>.urdf`` (or the one URDF whose file name starts with ``<robot>_`` or whose
  ``<robot name=...>`` is the robot's name), ``DIR/srdf/<robot>.srdf`` and ``DIR/channels/<robot>.yaml``.

The drive type (§2.5.2 B.2 scales only between robots with the same drive) is, in this order: the
profile's ``drive:``, the table ``KNOWN_DRIVES`` of what the robots' bases really are, or an inference
from the limits (a usable ``linear.y`` means holonomic). The table is needed because limits files do
not always say it: the shared Pepper file has ``linear.y: 0..0`` although Pepper's base is
omnidirectional.

The source robot may be ``unknown`` (``UNKNOWN``, thesis Example 6): no files, no drive, so channels
are chosen for the target alone and nothing is scaled (commands are only checked against the target).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.inputs import load_yaml

from .errors import TransferError
from .limits import VelocityLimits, infer_drive, load_limits

DRIVES = ("differential", "holonomic", "none")
#: the robot profiles shipped in the package (our own data files: each base's velocity limits and
#: drive, the channel statistics of the thesis' Tables 2.1-2.5, the arms' joints and MoveIt groups);
#: the default ``--robots``
SHIPPED_ROBOTS = Path(__file__).resolve().parent / "robots"
PROFILE_KEYS = {"name", "drive", "limits", "urdf", "srdf", "channels"}
#: the source robot name of a program written for no robot in particular (thesis Example 6)
UNKNOWN = "unknown"
#: what the bases of well-known robots are (manufacturers' descriptions); a profile's ``drive:`` wins
KNOWN_DRIVES = {
    "jackal": "differential",      # Clearpath Jackal: skid-steer
    "turtlebot": "differential",   # Kobuki base
    "turtlebot2": "differential",
    "kobuki": "differential",
    "fetch": "differential",       # two drive wheels and casters
    "pepper": "holonomic",         # three omni wheels
    "nao": "holonomic",            # walks in x, y and theta (ALMotion moveToward)
    "pr2": "holonomic",            # four powered casters
    "youbot": "holonomic",         # mecanum wheels
    "sphero": "holonomic",         # a rolling sphere driven in x and y
}


@dataclass
class RobotProfile:
    """Everything the transfer knows about one robot; files are loaded lazily by their users."""

    name: str
    drive: str = "none"
    limits: VelocityLimits | None = None
    urdf: Path | None = None
    srdf: Path | None = None
    channels: Path | None = None
    drive_source: str = "inferred from the limits"   # or "profile", "known robots table"
    sources: dict[str, str] = field(default_factory=dict)

    @property
    def unknown(self) -> bool:
        return self.name == UNKNOWN and not self.sources

    def describe(self) -> str:
        parts = [f"{self.name} ({self.drive} drive, {self.drive_source})"]
        for key in ("limits", "urdf", "srdf", "channels"):
            if key in self.sources:
                parts.append(f"{key}: {self.sources[key]}")
        return "; ".join(parts)


_ROBOT_NAME = re.compile(rb"<robot\b[^>]*\bname\s*=\s*[\"']([^\"']+)[\"']")


def _urdf_robot_name(path: Path) -> str | None:
    try:
        with open(path, "rb") as f:
            match = _ROBOT_NAME.search(f.read(8192))
    except OSError:
        return None
    try:
        return match.group(1).decode() if match else None
    except UnicodeDecodeError:  # not this robot's file: a robot is named in ASCII on the command line
        return None


def _find_by_convention(folder: Path, name: str, suffix: str, by_robot_name: bool = False) -> Path | None:
    exact = folder / f"{name}{suffix}"
    if exact.is_file():
        return exact
    if not folder.is_dir():
        return None
    candidates = sorted(folder.glob(f"{name}_*{suffix}"))
    if by_robot_name and not candidates:
        candidates = [p for p in sorted(folder.glob(f"*{suffix}")) if p.is_file() and _urdf_robot_name(p) == name]
    return candidates[0] if len(candidates) == 1 else None


def list_robots(robots_dir: str | Path) -> list[str]:
    """Names of the robots the folder describes (profiles, limits, URDFs and SRDFs)."""
    base = Path(robots_dir)
    names = {p.stem for p in base.glob("*.yaml")}
    for sub, suffix in (("limits", ".yaml"), ("urdf", ".urdf"), ("srdf", ".srdf")):
        names |= {p.stem for p in (base / sub).glob(f"*{suffix}")}
    return sorted(names)


def unknown_profile() -> RobotProfile:
    """The source robot of a program written for no robot in particular: no files, nothing to scale from."""
    return RobotProfile(UNKNOWN, "none", drive_source="source robot unknown")


def load_profile(robots_dir: str | Path, name: str, allow_unknown: bool = False) -> RobotProfile:
    """Find and load the robot ``name`` in ``robots_dir``; a clear error when it is not there.

    With ``allow_unknown`` (the source robot), ``unknown`` gives ``unknown_profile()`` unless the
    folder describes a robot of that name.
    """
    base = Path(robots_dir)
    if not base.is_dir():
        raise TransferError("robots folder does not exist", str(base))
    if allow_unknown and name == UNKNOWN and UNKNOWN not in list_robots(base):
        return unknown_profile()
    declared: dict = {}
    profile_file = base / f"{name}.yaml"
    if profile_file.is_file():
        declared = load_yaml(profile_file, "robot profile") or {}
        if not isinstance(declared, dict):
            raise TransferError("a robot profile must be a mapping", str(profile_file))
        unknown = set(declared) - PROFILE_KEYS
        if unknown:
            raise TransferError(f"unknown key(s) {sorted(unknown)}; expected {sorted(PROFILE_KEYS)}",
                                str(profile_file))

    def declared_path(key: str) -> Path | None:
        if declared.get(key) is None:
            return None
        path = (base / str(declared[key])).resolve()
        if not path.is_file():
            raise TransferError(f"{key} file {declared[key]!r} does not exist", str(profile_file), key)
        return path

    limits_path = declared_path("limits") or _find_by_convention(base / "limits", name, ".yaml")
    urdf = declared_path("urdf") or _find_by_convention(base / "urdf", name, ".urdf", by_robot_name=True)
    srdf = declared_path("srdf") or _find_by_convention(base / "srdf", name, ".srdf")
    channels = declared_path("channels") or _find_by_convention(base / "channels", name, ".yaml")
    if not (declared or limits_path or urdf or srdf):
        known = ", ".join(list_robots(base)) or "none"
        raise TransferError(f"no robot named {name!r} (robots there: {known})", str(base))
    limits = load_limits(limits_path) if limits_path else None
    drive = declared.get("drive")
    if drive is not None and drive not in DRIVES:
        raise TransferError(f"drive must be one of {', '.join(DRIVES)}, got {drive!r}", str(profile_file), "drive")
    if drive is not None:
        drive_source = "profile"
    elif name in KNOWN_DRIVES:
        drive, drive_source = KNOWN_DRIVES[name], "known robots table"
    else:
        drive, drive_source = infer_drive(limits), "inferred from the limits"
    profile = RobotProfile(name=str(declared.get("name", name)), drive=drive, limits=limits, urdf=urdf,
                           srdf=srdf, channels=channels, drive_source=drive_source)
    for key, path in (("limits", limits_path), ("urdf", urdf), ("srdf", srdf), ("channels", channels)):
        if path is not None:
            profile.sources[key] = str(path)
    return profile
