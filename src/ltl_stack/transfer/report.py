"""The transfer report: what changed, how, what the user said, what could not be resolved (Table 2.5)."""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field


@dataclass
class ChannelChange:
    kind: str                 # topic | action | MoveIt group | pose frame
    msg_type: str | None
    line: int
    original: str | None
    replacement: str | None
    method: str
    user_input: bool = False
    flagged: str | None = None
    candidates: list = field(default_factory=list)

    @property
    def changed(self) -> bool:
        return self.replacement is not None and self.replacement != self.original


@dataclass
class ParameterChange:
    what: str                 # 'linear.x', 'joint_names', 'positions', ...
    line: int
    original: str
    replacement: str
    method: str               # 'B.2 scaled', 'B.1 clamped', 'B.3 retargeted', 'B.1 checked'
    within_target_limits: bool = True
    note: str | None = None

    @property
    def changed(self) -> bool:
        return self.replacement != self.original


@dataclass
class Unresolved:
    what: str
    line: int | None
    reason: str


@dataclass
class TransferReport:
    source_file: str
    source_robot: str
    target_robot: str
    output_file: str | None = None
    channels: list[ChannelChange] = field(default_factory=list)
    parameters: list[ParameterChange] = field(default_factory=list)
    unresolved: list[Unresolved] = field(default_factory=list)
    retargeting: dict | None = None
    notes: list[str] = field(default_factory=list)
    target_examples: int | None = None
    lines_in_file: int = 0
    seconds: float = 0.0
    refused: str | None = None
    python: str = "3"         # the Python the source is written for; the output is for the same one

    @property
    def channels_replaced(self) -> int:
        return sum(1 for c in self.channels if c.changed)

    @property
    def parameters_replaced(self) -> int:
        return sum(1 for p in self.parameters if p.changed)

    @property
    def user_inputs(self) -> int:
        return sum(1 for c in self.channels if c.user_input)

    def summary(self) -> dict:
        """The Table 2.5 row of this transfer."""
        return {"time_s": round(self.seconds, 3), "channels_replaced": self.channels_replaced,
                "parameters_replaced": self.parameters_replaced,
                "total_replacements": self.channels_replaced + self.parameters_replaced,
                "user_inputs": self.user_inputs, "target_robot_examples": self.target_examples,
                "lines_in_file": self.lines_in_file, "unresolved": len(self.unresolved)}

    def to_json(self) -> str:
        data = asdict(self)
        data["summary"] = self.summary()
        return json.dumps(data, indent=2) + "\n"

    def to_text(self) -> str:
        s = self.summary()
        out = [f"Code transfer {self.source_robot} -> {self.target_robot}: {self.source_file}"
               + (f" -> {self.output_file}" if self.output_file else "")]
        if self.refused:
            out += ["", f"REFUSED: {self.refused}"]
        out += ["", f"time taken {s['time_s']:.2f} s | channels replaced {s['channels_replaced']} | "
                    f"parameters replaced {s['parameters_replaced']} | total {s['total_replacements']} | "
                    f"user inputs {s['user_inputs']} | target robot examples "
                    f"{'-' if s['target_robot_examples'] is None else s['target_robot_examples']} | "
                    f"lines {s['lines_in_file']} | unresolved {s['unresolved']}"]
        if self.channels:
            out += ["", "Channels (§2.5.1):"]
            for c in self.channels:
                mark = "replaced" if c.changed else "kept"
                typ = f" ({c.msg_type})" if c.msg_type else ""
                out.append(f"  line {c.line}: {c.kind}{typ} '{c.original}' {mark}"
                           + (f" -> '{c.replacement}'" if c.changed else "") + f"  [{c.method}]"
                           + ("  [user input]" if c.user_input else ""))
                if c.flagged:
                    out.append(f"      ! {c.flagged}")
        if self.parameters:
            out += ["", "Parameters (§2.5.2):"]
            for p in self.parameters:
                arrow = f"{p.original} -> {p.replacement}" if p.changed else f"{p.original} (unchanged)"
                limit = "" if p.within_target_limits else "  OUT OF TARGET LIMITS"
                out.append(f"  line {p.line}: {p.what} {arrow}  [{p.method}]{limit}")
                if p.note:
                    out.append(f"      {p.note}")
        if self.retargeting:
            r = self.retargeting
            out += ["", "Joint retargeting (B.3):",
                    f"  source chain: {' -> '.join(r['source_joints'])} (tip {r['source_tip']})",
                    f"  target chain: {' -> '.join(r['target_joints'])} (tip {r['target_tip']})",
                    f"  target chain rule: {r['target_rule']}"]
            for i, point in enumerate(r["points"], 1):
                out.append(f"  point {i}: end-effector error {point['ee_error_m'] * 1000:.1f} mm, "
                           f"shape distance {point['shape_distance']:.3f}, weight {point['weight']:g}")
        if self.notes:
            out += ["", "Notes:"] + [f"  {n}" for n in self.notes]
        out += ["", "Could not be resolved:" if self.unresolved else "Everything was resolved."]
        for u in self.unresolved:
            out.append(f"  {'line ' + str(u.line) + ': ' if u.line else ''}{u.what}: {u.reason}")
        return "\n".join(out) + "\n"
