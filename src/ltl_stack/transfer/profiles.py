"""Robot profiles: name, drive type, velocity limits, URDF, SRDF and channel statistics.

A robots folder ``DIR`` is read with two conventions, so that the shared folder works as it is:

* an optional profile ``DIR/<robot>.yaml`` with keys ``name``, ``drive`` (differential | holonomic |
  none), ``limits``, ``urdf``, ``srdf``, ``channels`` (paths relative to ``DIR``);
* otherwise, or for any key the profile leaves out, ``DIR/limits/<robot>.yaml``,
  ``DIR/urdf/<robot>.urdf`` (or the one URDF whose file name starts with ``<robot>_`` or whose
  ``<robot name=...>`` is the robot's name), ``DIR/srdf/<robot>.srdf`` and ``DIR/channels/<robot>.yaml``.

The drive type, when not given, is inferred from the limits (a usable ``linear.y`` means holonomic).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.inputs import load_yaml

from .errors import TransferError
from .limits import VelocityLimits, infer_drive, load_limits

DRIVES = ("differential", "holonomic", "none")
PROFILE_KEYS = {"name", "drive", "limits", "urdf", "srdf", "channels"}


@dataclass
class RobotProfile:
    """Everything the transfer knows about one robot; files are loaded lazily by their users."""

    name: str
    drive: str = "none"
    limits: VelocityLimits | None = None
    urdf: Path | None = None
    srdf: Path | None = None
    channels: Path | None = None
    drive_inferred: bool = True
    sources: dict[str, str] = field(default_factory=dict)

    def describe(self) -> str:
        parts = [f"{self.name} ({self.drive} drive{' inferred from limits' if self.drive_inferred else ''})"]
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
    return match.group(1).decode() if match else None


def _find_by_convention(folder: Path, name: str, suffix: str, by_robot_name: bool = False) -> Path | None:
    exact = folder / f"{name}{suffix}"
    if exact.is_file():
        return exact
    if not folder.is_dir():
        return None
    candidates = sorted(folder.glob(f"{name}_*{suffix}"))
    if by_robot_name and not candidates:
        candidates = [p for p in sorted(folder.glob(f"*{suffix}")) if _urdf_robot_name(p) == name]
    return candidates[0] if len(candidates) == 1 else None


def list_robots(robots_dir: str | Path) -> list[str]:
    """Names of the robots the folder describes (profiles, limits, URDFs and SRDFs)."""
    base = Path(robots_dir)
    names = {p.stem for p in base.glob("*.yaml")}
    for sub, suffix in (("limits", ".yaml"), ("urdf", ".urdf"), ("srdf", ".srdf")):
        names |= {p.stem for p in (base / sub).glob(f"*{suffix}")}
    return sorted(names)


def load_profile(robots_dir: str | Path, name: str) -> RobotProfile:
    """Find and load the robot ``name`` in ``robots_dir``; a clear error when it is not there."""
    base = Path(robots_dir)
    if not base.is_dir():
        raise TransferError("robots folder does not exist", str(base))
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
    profile = RobotProfile(name=str(declared.get("name", name)), drive=drive or infer_drive(limits),
                           limits=limits, urdf=urdf, srdf=srdf, channels=channels, drive_inferred=drive is None)
    for key, path in (("limits", limits_path), ("urdf", urdf), ("srdf", srdf), ("channels", channels)):
        if path is not None:
            profile.sources[key] = str(path)
    return profile
