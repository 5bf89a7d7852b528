"""Transfer a ROS Python program from a source robot to a target robot (thesis chapter 2, Problem 1).

Communication (§2.5.1): every topic/action name is replaced by the target's (A.1 codebase statistics,
A.2 live master, or both), MoveIt groups by the most similar SRDF group (A.3) and pose frames by that
group's tip link. Parameters (§2.5.2): velocity literals are scaled by Eqs. 2.1/2.2 (B.2) and checked
against the target's limits (B.1); joint trajectories are retargeted by optimisation (B.3). Only the
spans that change are edited; the report says what changed, how, and what could not be resolved.
"""
from __future__ import annotations

import ast
import time
from dataclasses import dataclass, field

from .channels import ChannelSite, find_channel_sites
from .choose import Asker, Decision, choose_channel, choose_group, short_type
from .codebase import ChannelStats
from .commands import (
    JointTrajectoryUse,
    find_joint_trajectories,
    find_velocity_commands,
    inconsistent_joint_arrays,
)
from .errors import TransferRefused
from .limits import scale_command
from .names import resolve_name
from .open_loop import describe_change, find_time_literals
from .profiles import RobotProfile
from .report import ChannelChange, ParameterChange, TransferReport, Unresolved
from .rewrite import Edit, apply_edits
from .source_ast import SourceFile, call_argument, format_number, format_string
from .srdf import check_against_urdf, load_srdf, rank_groups
from .urdf_tree import load_urdf_tree

__all__ = ["TransferOptions", "TransferRefused", "TransferResult", "transfer_program"]

@dataclass
class TransferOptions:
    stats: ChannelStats | None = None              # A.1: the target robot's channel statistics
    live: list[tuple[str, str]] | None = None      # A.2: (name, type) on the target's master
    ask: Asker | None = None                       # None: non-interactive (rules, flagged)
    progress: object = None                        # callable(str) for long work
    choose_by_distribution: bool = False           # A.1: ask from the ranked distribution
    keep_distances: bool = False                   # open loop: one speed factor, durations scaled back


@dataclass
class TransferResult:
    text: str
    report: TransferReport
    edits: list[Edit] = field(default_factory=list)


def transfer_program(text: str, source: RobotProfile, target: RobotProfile,
                     options: TransferOptions | None = None, filename: str = "<source>") -> TransferResult:
    """Write the target program for ``text`` and report on it; raises TransferRefused/TransferError."""
    started = time.perf_counter()
    options = options or TransferOptions()
    src = SourceFile(text, filename)
    report = TransferReport(filename, source.name, target.name)
    report.lines_in_file = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
    report.target_examples = options.stats.scripts if options.stats else None
    report.python = src.python
    if src.python == "2":
        report.notes.append("read as Python 2 (indentation tabs expanded to multiples of 8 as Python 2 does; "
                            "print statements and 'except E, name' read); only literals were edited, so the "
                            "output is a Python 2 program like the input (Python 3 does not run either)")
    edits: list[Edit] = []
    sites = find_channel_sites(src)
    velocity, unresolved_velocity = find_velocity_commands(src)
    _refuse_mixed_drives(sites, velocity, source, target, report)
    _channels(src, sites, source, target, options, report, edits)
    scaled = _velocities(velocity, unresolved_velocity, source, target, report, edits, src)
    _open_loop(src, scaled, target, options.keep_distances, report, edits)
    joints = find_joint_trajectories(src)
    retargeted = _without_unresolved_scopes(src, joints, report)
    if retargeted.names or retargeted.points:
        # Imported here: numpy, scipy and yourdfpy cost ~0.6 s of start-up that a program without joint
        # commands (most of them: velocity and topic changes) never needs.
        from .retarget import transfer_joint_commands
        groups = [c.replacement for c in report.channels if c.kind == "MoveIt group" and c.replacement]
        transfer_joint_commands(src, retargeted, source, target, report, edits, options.progress,
                                group=groups[0] if joints.by_group and groups else None)
    for u in joints.unresolved:
        report.unresolved.append(Unresolved(u.field, u.line, f"'{u.text}': {u.reason}"))
    problems = inconsistent_joint_arrays(src, joints, {e.span: e.text for e in edits})
    if problems:
        report.refused = "; ".join(problems) + ". Every point of a trajectory needs one length for its names, " \
                                                "positions, velocities and accelerations."
        raise TransferRefused(report.refused, report.source_file)
    new_text = apply_edits(src.data, edits).decode("utf-8")
    report.seconds = time.perf_counter() - started
    return TransferResult(new_text, report, edits)


def _without_unresolved_scopes(src: SourceFile, joints: JointTrajectoryUse, report: TransferReport) -> JointTrajectoryUse:
    """The joint arrays B.3 may rewrite: none of a function (scope) where one of them is not a literal,
    so that every trajectory point keeps one length; each such scope is reported."""
    unclean = {scope for scope, _, _, span in joints.members if span is None}
    if not unclean:
        return joints
    kept = {span for scope, _, _, span in joints.members if scope in unclean and span is not None}
    # literals such a scope computes its arrays from ([NAMES[i] for i in order]) are kept too
    arrays = {span for *_, span in joints.members if span is not None}
    read = set()
    for scope in unclean:
        for node in ast.walk(scope):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and src.scope_of(node) is scope:
                read |= {src.span(v) for v in src.bindings(node)} & arrays
    if read - kept:
        report.unresolved.append(Unresolved(
            "joint lists", min(sp.line for sp in read - kept),
            f"kept: the lists at line(s) {', '.join(str(sp.line) for sp in sorted(read - kept, key=lambda x: x.start))} "
            "are also read by code whose joint arrays are computed; retargeting them would change what that code "
            "commands"))
    kept |= read
    for scope in unclean:
        where = f"{scope.name}()" if hasattr(scope, "name") else "module level"
        bad = sorted({line for s, _, line, span in joints.members if s is scope and span is None})
        others = sorted({line for s, _, line, span in joints.members if s is scope and span is not None})
        report.unresolved.append(Unresolved(
            f"joint trajectory in {where}", bad[0],
            f"not retargeted: its joint arrays at line(s) {', '.join(map(str, bad))} are not literals"
            + (f"; its other arrays (line(s) {', '.join(map(str, others))}) are kept as they are, so that "
               "its points keep one length" if others else "")))
    return JointTrajectoryUse(
        names=[n for n in joints.names if n.span not in kept], points=[p for p in joints.points if p.span not in kept],
        zero_lists=[z for z in joints.zero_lists if z[0] not in kept],
        rates=[r for r in joints.rates if r[1].span not in kept], by_group=joints.by_group)


def _refuse_mixed_drives(sites: list[ChannelSite], velocity, source: RobotProfile, target: RobotProfile,
                         report: TransferReport) -> None:
    twist = velocity or any(short_type(s.use.msg_type) == "Twist" for s in sites)
    drives = {source.drive, target.drive}
    if twist and drives == {"differential", "holonomic"}:
        reason = (f"{source.name} has a {source.drive} drive ({source.drive_source}) and {target.name} a "
                  f"{target.drive} drive ({target.drive_source}). "
                  "Velocity commands do not carry over between the two (thesis §2.8, challenge 2): a "
                  "holonomic program may set linear.x and linear.y at different places, and whether they "
                  "form one diagonal motion or two motions can only be told by running it. Transfer "
                  "between robots with the same drive, or set 'drive:' in a robot profile if a drive "
                  "is wrong.")
        report.refused = reason
        raise TransferRefused(reason, report.source_file)


def _channels(src: SourceFile, sites: list[ChannelSite], source: RobotProfile, target: RobotProfile,
              options: TransferOptions, report: TransferReport, edits: list[Edit]) -> None:
    decided: dict = {}
    answered: set = set()   # a user's answer counts once, at the first place it applies
    chosen_groups: list[tuple[int, str | None]] = []   # (line, target group) for pose frames
    target_srdf = _load_srdf(target) if any(s.use.kind == "move_group" for s in sites) else None
    service_types = {s.use.name.value: s.use.msg_type for s in sites
                     if s.use.word == "service" and s.use.msg_type and s.use.name.value}
    for site in sites:
        use = site.use
        if use.name.value is None:
            report.unresolved.append(Unresolved(f"{use.word} name", use.line, use.name.problem or "unknown"))
            continue
        if use.kind in ("pose_frame", "frame", "own_frame", "ee_group", "joint", "named_state"):
            continue  # after all groups are chosen
        if use.kind == "service_wait":  # wait_for_service names no type: the service's own use does
            use.msg_type = service_types.get(use.name.value)
        if use.name.value.startswith("~"):  # the node's private namespace exists wherever it runs
            report.notes.append(f"line {use.line}: {use.word} '{use.name.value}' kept: a private name of "
                                "the program's own node")
            continue
        key = (use.word, use.name.value, use.msg_type)
        if key not in decided:
            if use.kind == "move_group":
                decided[key] = _choose_group(use.name.value, target, target_srdf, options.ask)
            else:
                decided[key] = choose_channel(use.word, use.msg_type, use.name.value, options.stats,
                                              options.live, options.ask, options.choose_by_distribution)
        decision = decided[key]
        asked_here = decision.user_input and key not in answered
        answered.add(key)
        flagged = "; ".join(f for f in (decision.flagged, use.name.note) if f) or None
        change = ChannelChange(use.word, use.msg_type, use.line, use.name.value, decision.replacement,
                               decision.method, asked_here, flagged, decision.candidates)
        if use.kind == "move_group":
            chosen_groups.append((use.line, decision.replacement))
        report.channels.append(change)
        if decision.replacement is None:
            report.unresolved.append(Unresolved(
                f"{use.word} '{use.name.value}'", use.line,
                f"no {use.word} of type {short_type(use.msg_type)} known for {target.name} "
                "(no codebase statistics or live master listing has one); kept the original name"
                if use.kind != "move_group" else f"{target.name} has no SRDF planning groups; kept it"))
        elif change.changed:
            _edit_name(src, site, decision.replacement, edits)
    own_frames = {s.use.name.value for s in sites if s.use.kind == "own_frame" and s.use.name.value}
    for site in sites:
        if site.use.kind == "pose_frame" and site.use.name.value is not None:
            _pose_frame(src, site, chosen_groups, target, target_srdf, report, edits)
        elif site.use.kind in ("frame", "own_frame") and site.use.name.value is not None:
            _tf_frame(site, target, own_frames, report)
        elif site.use.kind == "ee_group" and site.use.name.value is not None:
            _end_effector_group(src, site, chosen_groups, target, target_srdf, report, edits)
        elif site.use.kind == "joint" and site.use.name.value is not None:
            _joint_name(site, target, report)
        elif site.use.kind == "named_state" and site.use.name.value is not None:
            report.unresolved.append(Unresolved(
                f"MoveIt named state '{site.use.name.value}'", site.use.line,
                f"a group state of {source.name}'s SRDF; check that {target.name}'s SRDF defines it (kept it)"))
    _check_planning_frames(src, sites, target, report)


def _check_planning_frames(src: SourceFile, sites: list[ChannelSite], target: RobotProfile,
                           report: TransferReport) -> None:
    """The frame a MoveGroupInterface plans in (its second argument) must exist on the target."""
    urdf = _target_urdf(target)
    if urdf is None:
        return
    for site in sites:
        call = site.call
        if site.use.kind != "move_group" or not isinstance(call, ast.Call) \
                or not (src.qualname(call.func) or "").endswith("MoveGroupInterface"):
            continue
        frame = resolve_name(src, call_argument(call, 1, "frame")).value
        if frame and not urdf.has_link(frame):
            report.unresolved.append(Unresolved(f"planning frame '{frame}'", site.use.line,
                                                f"{target.name}'s URDF has no link {frame!r}; the goal poses "
                                                "are given in it, so choose the target's equivalent frame"))


#: frames of REP 105 that are not links of a robot's URDF but exist on every mobile robot's tf tree
REP105_FRAMES = ("map", "odom", "earth")


def _tf_frame(site: ChannelSite, target: RobotProfile, own_frames: set[str], report: TransferReport) -> None:
    """A tf frame is kept when the target has it (a URDF link, a REP 105 frame, or a frame the program
    broadcasts itself), else unresolved."""
    use = site.use
    frame = use.name.value.lstrip("/")
    urdf = _target_urdf(target)
    if use.name.value in own_frames or frame in REP105_FRAMES or (urdf is not None and urdf.has_link(frame)):
        where = "broadcast by this program" if use.name.value in own_frames else \
            "a REP 105 frame" if frame in REP105_FRAMES else f"a link of {target.name}'s URDF"
        report.notes.append(f"line {use.line}: tf frame '{use.name.value}' kept: {where}"
                            + (f" ({use.name.note})" if use.name.note else ""))
        return
    reason = f"{target.name}'s URDF has no link {frame!r}" if urdf is not None else \
        f"no URDF for {target.name}, so the frame cannot be checked"
    report.unresolved.append(Unresolved(f"tf frame '{use.name.value}'", use.line, reason + "; kept it"))


def _group_before(chosen_groups: list[tuple[int, str | None]], line: int) -> str | None:
    """The target group of the last MoveIt group opened up to ``line`` (else the first one)."""
    before = [g for at, g in chosen_groups if at <= line] or [g for _, g in chosen_groups]
    return before[-1] if before else None


def _end_effector_group(src: SourceFile, site: ChannelSite, chosen_groups, target: RobotProfile, srdf,
                        report: TransferReport, edits: list[Edit]) -> None:
    """A.3 for ``PickPlaceInterface``'s end-effector group: the target SRDF's end effector on the tip of
    the chosen arm group (its ``parent_group``, or its ``parent_link`` = the group's tip link)."""
    use = site.use
    group = _group_before(chosen_groups, use.line)
    found = []
    if srdf is not None and group:
        tip = srdf.tip_link(group, _target_urdf(target))
        found = sorted({e.group for e in srdf.end_effectors if e.parent_group == group or e.parent_link == tip})
    if len(found) != 1:
        why = f"{target.name} has no SRDF" if srdf is None else \
            f"{target.name}'s SRDF has {'no' if not found else len(found)} end effector(s) on the group {group!r}"
        report.unresolved.append(Unresolved(f"{use.word} '{use.name.value}'", use.line, why + "; kept it"))
        return
    change = ChannelChange(use.word, None, use.line, use.name.value, found[0],
                           f"A.3 end effector of the target group '{group}'")
    report.channels.append(change)
    if change.changed:
        _edit_name(src, site, found[0], edits)


def _joint_name(site: ChannelSite, target: RobotProfile, report: TransferReport) -> None:
    """A joint named outside a joint array (``set_joint_value_target``) must be a joint of the target."""
    use = site.use
    urdf = _target_urdf(target)
    if urdf is not None and urdf.has_joint(use.name.value):
        report.notes.append(f"line {use.line}: joint '{use.name.value}' kept: a joint of {target.name}'s URDF")
        return
    reason = f"{target.name}'s URDF has no joint {use.name.value!r}" if urdf is not None else \
        f"no URDF for {target.name}, so the joint cannot be checked"
    report.unresolved.append(Unresolved(f"joint '{use.name.value}'", use.line,
                                        reason + "; give the target's joint by hand (kept it)"))


def _edit_name(src: SourceFile, site: ChannelSite, new: str, edits: list[Edit]) -> None:
    for span in site.spans:
        old = src.data[span.start:span.end].decode("utf-8")
        edits.append(Edit(span, format_string(new, old)))


def _load_srdf(robot: RobotProfile):
    if robot.srdf is None:
        return None
    srdf = load_srdf(robot.srdf)
    if robot.urdf is not None:
        check_against_urdf(srdf, load_urdf_tree(robot.urdf))
    return srdf


def _choose_group(source_group: str, target: RobotProfile, srdf, ask: Asker | None):
    if srdf is None:
        return Decision(None, "A.3 needs the target's SRDF")
    urdf = _target_urdf(target)
    return choose_group(source_group, rank_groups(source_group, srdf),
                        lambda name: srdf.tip_link(name, urdf) is not None, ask)


def _target_urdf(target: RobotProfile):
    if target.urdf is None:
        return None
    return load_urdf_tree(target.urdf)


def _pose_frame(src: SourceFile, site: ChannelSite, chosen_groups, target: RobotProfile, srdf,
                report: TransferReport, edits: list[Edit]) -> None:
    use = site.use
    group = _group_before(chosen_groups, use.line)
    tip = srdf.tip_link(group, _target_urdf(target)) if (srdf is not None and group) else None
    change = ChannelChange(use.word, None, use.line, use.name.value, tip,
                           f"A.3 tip link of the target group '{group}'" if tip else "none")
    report.channels.append(change)
    if tip is None:
        report.unresolved.append(Unresolved(f"pose frame '{use.name.value}'", use.line,
                                            f"no single tip link for the target group {group!r}; kept it"))
    elif change.changed:
        _edit_name(src, site, tip, edits)


def _open_loop(src: SourceFile, scaled: list[tuple], target: RobotProfile, keep: bool, report: TransferReport,
               edits: list[Edit]) -> None:
    """Say when scaled speeds change what an open-loop program drives; with ``keep``, scale every speed by
    one factor and the durations by its inverse (see ``open_loop.py``)."""
    factors: dict[str, list[float]] = {}
    for _, cmds, old, new, _ in scaled:
        if old != 0 and abs(new / old - 1) > 1e-9:
            for field in {c.field for c in cmds}:
                factors.setdefault(field, []).append(new / old)
    times = find_time_literals(src) if factors else []
    if not times:
        return
    if not keep:
        report.notes.append(describe_change(factors, times))
        return
    common = min(r for ratios in factors.values() for r in ratios)
    for span, cmds, old, _, change in scaled:
        value = old * common
        if not all(target.limits[c.field].allows(value) and abs(value) >= target.limits[c.field].deadband
                   for c in cmds):
            report.unresolved.append(Unresolved(change.what, span.line, f"{value:g} (x{common:.3g}, to keep the "
                                                                        f"distances) is not a motion {target.name} "
                                                                        "makes; kept the B.2 value"))
            continue
        edits[:] = [e for e in edits if e.span != span]
        change.replacement, change.method = format_number(value), f"B.2 one factor x{common:.3g} (keep distances)"
        if change.replacement != change.original:
            edits.append(Edit(span, change.replacement))
    for t in times:
        original = src.data[t.span.start:t.span.end].decode("utf-8")
        new = format_number(t.value * common if t.frequency else t.value / common)
        report.parameters.append(ParameterChange(f"{t.text} {'frequency' if t.frequency else 'duration'}", t.line,
                                                 original, new, f"kept distances: x{common:.3g}"
                                                 if t.frequency else f"kept distances: /{common:.3g}"))
        if new != original:
            edits.append(Edit(t.span, new))
    report.notes.append(f"open loop, distances kept: every speed was scaled by x{common:.3g} (the smallest B.2 "
                        f"factor) and every duration by 1/{common:.3g}, so the program drives the same distances "
                        "and angles, more slowly or quickly")


def _velocities(commands, unresolved, source: RobotProfile, target: RobotProfile, report: TransferReport,
                edits: list[Edit], src: SourceFile) -> list[tuple]:
    """B.1/B.2 on the velocity literals; returns (span, commands, old, new, change) of each one written."""
    for u in unresolved:
        report.unresolved.append(Unresolved(u.field, u.line, f"'{u.text}': {u.reason}; not checked against "
                                                             f"{target.name}'s limits (§2.8 challenges 3-4)"))
    scaled: list[tuple] = []
    if not commands:
        return scaled
    if target.limits is None:
        report.unresolved.append(Unresolved("velocity commands", commands[0].line,
                                            f"no velocity limits for {target.name}; nothing checked (B.1)"))
        return scaled
    by_span: dict = {}
    zeros = 0
    for cmd in commands:
        if cmd.value == 0:
            zeros += 1
            continue
        by_span.setdefault(cmd.span, []).append(cmd)
    if zeros:
        report.notes.append(f"{zeros} zero velocity literal(s) are valid on any robot and were left as they are")
    for span, cmds in by_span.items():
        original = src.data[span.start:span.end].decode("utf-8")
        results = [_scale_one(cmd, source, target) for cmd in cmds]
        values = {r[0] for r in results}
        cmd, (new, method, note) = cmds[0], results[0]
        what = " & ".join(sorted({c.field for c in cmds})) + (f" (variable {cmd.via})" if cmd.via else "")
        if len(values) > 1:
            report.unresolved.append(Unresolved(what, span.line, f"the literal {original} commands fields "
                                                                  "with different limits; left unchanged"))
            continue
        if new is None:
            report.unresolved.append(Unresolved(what, span.line, note))
            continue
        replacement = original if new == cmd.value else format_number(new)
        within = all(target.limits[c.field].allows(new) for c in cmds)
        change = ParameterChange(what, span.line, original, replacement, method, within, note)
        report.parameters.append(change)
        scaled.append((span, cmds, cmd.value, new, change))
        if replacement != original:
            edits.append(Edit(span, replacement))
    return scaled


def _scale_one(cmd, source: RobotProfile, target: RobotProfile):
    """(new value or None, method, note) for one velocity command."""
    tgt = target.limits[cmd.field]
    if not tgt.applicable():
        if cmd.value == 0:
            return cmd.value, "B.1 checked", None
        return None, "", f"{target.name} has no {cmd.field} (None in its limits); the command {cmd.value:g} " \
                         "cannot be carried over"
    src_limit = source.limits[cmd.field] if source.limits else None
    note = None
    if cmd.value == 0:
        return 0.0, "B.1 checked", None
    if src_limit is not None and src_limit.applicable():
        try:
            new = scale_command(cmd.value, src_limit, tgt)
            method = "B.2 scaled (Eq. 2.1)" if cmd.value > 0 else "B.2 scaled (Eq. 2.2)"
            if cmd.value != 0 and new == 0:
                note = f"inside {source.name}'s deadband {src_limit.deadband:g}: no motion, so zero"
            if not src_limit.allows(cmd.value):
                note = f"already outside {source.name}'s limits {src_limit.describe()}"
        except ValueError as err:
            new, method, note = cmd.value, "B.1 checked", f"not scaled: {err}"
    else:
        new, method = cmd.value, "B.1 checked"
        note = f"{source.name} has no limits for {cmd.field}; checked only"
    if not tgt.allows(new):
        clamped = tgt.clamp(new)
        note = (note + "; " if note else "") + f"{new:g} is outside {target.name}'s {cmd.field} " \
                                               f"{tgt.describe()}, clamped to {clamped:g}"
        new, method = clamped, "B.1 clamped"
    return new, method, note
