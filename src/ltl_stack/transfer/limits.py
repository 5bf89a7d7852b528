"""Velocity limits in the unified YAML of thesis Fig. 2.2, the B.1 check and the B.2 scaling.

The file maps ``linear|angular`` -> ``x|y|z`` -> ``lower``, ``upper``, ``deadband``; the word ``None``
(or a null) means "not applicable". Scaling follows Eqs. 2.1 (commands >= 0, against the upper limits)
and 2.2 (commands < 0, against the lower limits), so asymmetric limits and deadbands are respected.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ltl_stack.inputs import load_yaml

from .errors import TransferError

GROUPS = ("linear", "angular")
AXES = ("x", "y", "z")
FIELDS = tuple(f"{g}.{a}" for g in GROUPS for a in AXES)


@dataclass(frozen=True)
class AxisLimit:
    """Limits of one Twist field; ``None`` bounds mean the robot does not use that direction."""

    lower: float | None
    upper: float | None
    deadband: float = 0.0

    def applicable(self) -> bool:
        return self.lower is not None or self.upper is not None

    def allows(self, value: float) -> bool:
        """B.1: is ``value`` a command this field accepts (zero is always accepted)?"""
        if value == 0:
            return True
        if value > 0:
            return self.upper is not None and value <= self.upper + 1e-12
        return self.lower is not None and value >= self.lower - 1e-12

    def clamp(self, value: float) -> float:
        if self.upper is not None and value > self.upper:
            return self.upper
        if self.lower is not None and value < self.lower:
            return self.lower
        if (self.upper is None and value > 0) or (self.lower is None and value < 0):
            return 0.0
        return value

    def describe(self) -> str:
        text = f"[{self.lower}, {self.upper}]"
        return text + (f" deadband {self.deadband}" if self.deadband else "")


@dataclass(frozen=True)
class VelocityLimits:
    """The six Twist fields' limits of one robot, keyed ``'linear.x'`` ... ``'angular.z'``."""

    fields: dict[str, AxisLimit]
    file: str = "<limits>"

    def __getitem__(self, field: str) -> AxisLimit:
        return self.fields.get(field, AxisLimit(None, None))

    def applicable_fields(self) -> list[str]:
        return [f for f in FIELDS if self[f].applicable()]


def _number(value, file: str, where: str) -> float | None:
    if value is None or (isinstance(value, str) and value.strip().lower() in ("none", "null", "")):
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TransferError(f"expected a number or None, got {value!r}", file, where)
    return float(value)


def parse_limits(data, file: str = "<limits>") -> VelocityLimits:
    """Build limits from the parsed YAML mapping; one clear error names the file and the key."""
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise TransferError("expected a mapping with 'linear' and/or 'angular'", file)
    for key in data:
        if key not in GROUPS:
            raise TransferError(f"unknown key {key!r} (expected 'linear' or 'angular')", file, str(key))
    fields: dict[str, AxisLimit] = {}
    for group in GROUPS:
        axes = data.get(group) or {}
        if not isinstance(axes, dict):
            raise TransferError("expected a mapping of x/y/z", file, group)
        for axis, spec in axes.items():
            where = f"{group}.{axis}"
            if axis not in AXES:
                raise TransferError(f"unknown axis {axis!r} (expected x, y or z)", file, where)
            spec = spec or {}
            if not isinstance(spec, dict):
                raise TransferError("expected lower/upper/deadband", file, where)
            unknown = set(spec) - {"lower", "upper", "deadband"}
            if unknown:
                raise TransferError(f"unknown key(s) {sorted(unknown)}", file, where)
            lower = _number(spec.get("lower"), file, where + ".lower")
            upper = _number(spec.get("upper"), file, where + ".upper")
            deadband = _number(spec.get("deadband"), file, where + ".deadband") or 0.0
            if deadband < 0:
                raise TransferError(f"deadband must not be negative, got {deadband}", file, where)
            if lower is not None and lower > 0:
                raise TransferError(f"lower limit {lower} is above zero", file, where)
            if upper is not None and upper < 0:
                raise TransferError(f"upper limit {upper} is below zero", file, where)
            if upper is not None and 0 < upper < deadband or lower is not None and 0 > lower > -deadband:
                raise TransferError(f"deadband {deadband} is wider than the limits [{lower}, {upper}]", file, where)
            fields[where] = AxisLimit(lower, upper, deadband)
    return VelocityLimits(fields, file)


def load_limits(path: str | Path) -> VelocityLimits:
    """Read a unified velocity-limit YAML file (``ltl_stack.inputs``: bad files are one error naming file:line)."""
    return parse_limits(load_yaml(path, "velocity limits file"), str(path))


def scale_command(value: float, source: AxisLimit, target: AxisLimit) -> float:
    """B.2: map a source command onto the target's range (Eq. 2.1 for >= 0, Eq. 2.2 for < 0).

    A command inside the source deadband has no effect on the source robot, so it becomes zero.
    Raises ``ValueError`` when either side lacks the limit this command's sign needs.
    """
    if abs(value) <= source.deadband:
        return 0.0
    d_s, d_t = source.deadband, target.deadband
    if value > 0:
        if not source.upper or not target.upper:
            raise ValueError("no positive range on " + ("the source" if not source.upper else "the target"))
        return (value - d_s) / (source.upper - d_s) * (target.upper - d_t) + d_t  # Eq. 2.1
    if not source.lower or not target.lower:
        raise ValueError("no negative range on " + ("the source" if not source.lower else "the target"))
    return (value + d_s) / (source.lower + d_s) * (target.lower + d_t) - d_t  # Eq. 2.2


def infer_drive(limits: VelocityLimits | None) -> str:
    """'holonomic' when linear.y has a non-zero range, 'differential' when it drives at all, else 'none'."""
    if limits is None:
        return "none"
    y = limits["linear.y"]
    if (y.upper or 0) > 0 or (y.lower or 0) < 0:
        return "holonomic"
    if limits.applicable_fields():
        return "differential"
    return "none"
