"""Find the command literals of a program (thesis §2.5.2): Twist velocities and joint trajectories.

Velocity commands: ``Twist(Vector3(...), Vector3(...))`` (positional or keyword), assignments
``msg.linear.x = 0.5`` (also tuple assignments and ``msg.linear = Vector3(...)``), and variables that
hold the literal (``vel = .3`` ... ``msg.linear.x = vel``): then the literal at the binding is the
command, and nothing else with the same value is touched (§2.8 challenge 1).

Joint commands: ``joint_names`` and ``positions`` of JointTrajectory/JointTrajectoryPoint, given
inline or through a variable bound to a list literal, and their ``velocities``/``accelerations``:
numeric list literals (scaled against the joints' velocity limits) or zero lists ``[0] * n`` whose
length follows the number of joints.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass, field

from .limits import AXES
from .source_ast import SourceFile, Span, call_argument, number_value, string_value


@dataclass
class VelocityCommand:
    """One numeric literal that sets a Twist field."""

    field: str                 # 'linear.x' ...
    value: float
    span: Span                 # the literal (with its sign) to edit
    line: int                  # where the command is given (the assignment or constructor)
    via: str | None = None     # the variable that carries the literal, if any


@dataclass
class UnresolvedCommand:
    """A command whose value is not a literal (arithmetic, sensor data, ...): reported, not changed."""

    field: str
    line: int
    text: str
    reason: str


@dataclass
class JointList:
    """A list literal of joint names or of joint positions."""

    span: Span
    values: list
    line: int
    via: str | None = None


@dataclass
class JointTrajectoryUse:
    """The joint names and the successive position lists a program commands."""

    names: list[JointList] = field(default_factory=list)
    points: list[JointList] = field(default_factory=list)
    zero_lists: list[tuple[Span, str, int]] = field(default_factory=list)  # (span, kind, line)
    rates: list[tuple[str, JointList]] = field(default_factory=list)  # ('velocities'|'accelerations', list)
    unresolved: list[UnresolvedCommand] = field(default_factory=list)
    # every joint array the program gives: (scope it is used in, kind, line, literal span or None if not one)
    members: list[tuple[ast.AST, str, int, Span | None]] = field(default_factory=list)
    by_group: bool = False   # joints commanded through a MoveIt group (moveToJointPosition)


#: MoveIt calls that command joints by name: method -> ((position, keyword) of names, of positions)
JOINT_POSITION_METHODS = {"moveToJointPosition": ((0, "joints"), (1, "positions"))}


def _is_call_to(src: SourceFile, node: ast.AST, name: str) -> bool:
    return isinstance(node, ast.Call) and (src.qualname(node.func) or "").split(".")[-1] == name


def _twist_field(target: ast.AST) -> str | None:
    """``<expr>.linear.x`` -> 'linear.x'."""
    if isinstance(target, ast.Attribute) and target.attr in AXES and isinstance(target.value, ast.Attribute) \
            and target.value.attr in ("linear", "angular"):
        return f"{target.value.attr}.{target.attr}"
    return None


def _group_target(target: ast.AST) -> str | None:
    if isinstance(target, ast.Attribute) and target.attr in ("linear", "angular"):
        return target.attr
    return None


class _VelocityScanner:
    def __init__(self, src: SourceFile):
        self.src = src
        self.commands: list[VelocityCommand] = []
        self.unresolved: list[UnresolvedCommand] = []

    def value(self, fld: str, node: ast.expr, line: int) -> None:
        if number_value(node) is not None:
            self.commands.append(VelocityCommand(fld, number_value(node), self.src.span(node), line))
            return
        if isinstance(node, ast.Name):
            bound = self.src.bindings(node)
            literals = [v for v in bound if number_value(v) is not None]
            for lit in literals:
                self.commands.append(VelocityCommand(fld, number_value(lit), self.src.span(lit), line, node.id))
            if not bound:
                self.unresolved.append(UnresolvedCommand(fld, line, node.id, "not bound in this program"))
            elif len(literals) < len(bound):
                self.unresolved.append(UnresolvedCommand(
                    fld, line, node.id, "some of its values are computed (arithmetic or runtime data)"))
            return
        self.unresolved.append(UnresolvedCommand(
            fld, line, self.src.segment(node), "computed value (arithmetic or runtime data), not a literal"))

    def vector(self, group: str, node: ast.expr, line: int) -> None:
        if _is_call_to(self.src, node, "Vector3"):
            for i, axis in enumerate(AXES):
                arg = call_argument(node, i, axis)
                if arg is not None:
                    self.value(f"{group}.{axis}", arg, line)
        else:
            self.unresolved.append(UnresolvedCommand(group, line, self.src.segment(node), "not a Vector3(...)"))

    def scan(self) -> None:
        for node in ast.walk(self.src.tree):
            if _is_call_to(self.src, node, "Twist"):
                for i, group in enumerate(("linear", "angular")):
                    arg = call_argument(node, i, group)
                    if arg is not None:
                        self.vector(group, arg, node.lineno)
            elif isinstance(node, ast.Assign):
                for target in node.targets:
                    self.assignment(target, node.value, node.lineno)
            elif isinstance(node, ast.AugAssign) and _twist_field(node.target):
                self.unresolved.append(UnresolvedCommand(
                    _twist_field(node.target), node.lineno, self.src.segment(node), "arithmetic update"))

    def assignment(self, target: ast.AST, value: ast.expr, line: int) -> None:
        if isinstance(target, (ast.Tuple, ast.List)):
            if isinstance(value, (ast.Tuple, ast.List)) and len(value.elts) == len(target.elts):
                for t, v in zip(target.elts, value.elts):
                    self.assignment(t, v, line)
            return
        fld = _twist_field(target)
        if fld:
            self.value(fld, value, line)
        elif _group_target(target):
            self.vector(_group_target(target), value, line)


def find_velocity_commands(src: SourceFile) -> tuple[list[VelocityCommand], list[UnresolvedCommand]]:
    """Velocity command literals (one per literal and field) and the commands that are not literals."""
    scanner = _VelocityScanner(src)
    scanner.scan()
    seen: set = set()
    unique = []
    for cmd in sorted(scanner.commands, key=lambda c: (c.span.start, c.field)):
        if (cmd.span, cmd.field) not in seen:
            seen.add((cmd.span, cmd.field))
            unique.append(cmd)
    return unique, sorted(scanner.unresolved, key=lambda u: u.line)


def _list_literal(src: SourceFile, node: ast.expr | None, kind: str):
    """(list node, variable name) for an inline list or a name bound only to list literals."""
    if node is None:
        return []
    if isinstance(node, (ast.List, ast.Tuple)):
        return [(node, None)]
    if isinstance(node, ast.Name):
        bound = src.bindings(node)
        if bound and all(isinstance(v, (ast.List, ast.Tuple)) for v in bound):
            return [(v, node.id) for v in bound]
    return None


def find_joint_trajectories(src: SourceFile) -> JointTrajectoryUse:
    """Joint names and positions in the order the program uses them (successive trajectory points)."""
    use = JointTrajectoryUse()
    sites: list[tuple[str, ast.expr | None, int]] = []  # (kind, value node, line)
    for node in ast.walk(src.tree):
        if _is_call_to(src, node, "JointTrajectory"):
            arg = call_argument(node, 99, "joint_names")
            if arg is not None:
                sites.append(("names", arg, node.lineno))
        elif _is_call_to(src, node, "JointTrajectoryPoint"):
            for kw in ("positions", "velocities", "accelerations"):
                arg = call_argument(node, 99, kw)
                if arg is not None:
                    sites.append((kw, arg, node.lineno))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr in JOINT_POSITION_METHODS:
            use.by_group = True
            for kind, at in zip(("names", "positions"), JOINT_POSITION_METHODS[node.func.attr]):
                arg = call_argument(node, *at)
                if arg is not None:
                    sites.append((kind, arg, node.lineno))
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Attribute) and target.attr in ("joint_names", "positions",
                                                                          "velocities", "accelerations"):
                    kind = "names" if target.attr == "joint_names" else target.attr
                    sites.append((kind, node.value, node.lineno))
    sites.sort(key=lambda s: (s[2], getattr(s[1], "col_offset", 0)))
    seen: set = set()
    for kind, value, line in sites:
        scope = src.scope_of(value)
        unresolved_before = len(use.unresolved)
        if kind in ("velocities", "accelerations"):
            spans = _zero_list(src, value, kind, line, use)
        else:
            spans = _names_or_positions(src, value, kind, line, use, seen)
        if len(use.unresolved) > unresolved_before:
            use.members.append((scope, kind, line, None))
        use.members += [(scope, kind, line, span) for span in spans]
    return use


def _names_or_positions(src: SourceFile, value: ast.expr, kind: str, line: int, use: JointTrajectoryUse,
                        seen: set) -> list[Span]:
    found = _list_literal(src, value, kind)
    if not found:
        use.unresolved.append(UnresolvedCommand(
            "joint_names" if kind == "names" else "positions", line, src.segment(value),
            "not a list literal (or a variable bound to one)"))
        return []
    spans = []
    for lst, via in found:
        span = src.span(lst)
        if span in seen:
            spans.append(span)
            continue
        seen.add(span)
        if kind == "names":
            values = [string_value(e) for e in lst.elts]
            if None in values:
                use.unresolved.append(UnresolvedCommand("joint_names", line, src.segment(lst),
                                                        "a joint name is not a string literal"))
                continue
            use.names.append(JointList(span, values, line, via))
        else:
            values = [number_value(e) for e in lst.elts]
            if None in values:
                use.unresolved.append(UnresolvedCommand("positions", line, src.segment(lst),
                                                        "a position is not a numeric literal"))
                continue
            use.points.append(JointList(span, values, line, via))
        spans.append(span)
    return spans


def _zero_list(src: SourceFile, value: ast.expr, kind: str, line: int, use: JointTrajectoryUse) -> list[Span]:
    """Remember ``[0]*n`` / ``[0, 0, ...]`` (length follows the joints) and numeric lists (scaled)."""
    if isinstance(value, ast.BinOp) and isinstance(value.op, ast.Mult) and isinstance(value.left, ast.List) \
            and len(value.left.elts) == 1 and number_value(value.left.elts[0]) == 0 \
            and isinstance(value.right, ast.Constant) and isinstance(value.right.value, int):
        use.zero_lists.append((src.span(value), kind, line))
        return [src.span(value)]
    if isinstance(value, ast.List) and value.elts and all(number_value(e) == 0 for e in value.elts):
        use.zero_lists.append((src.span(value), kind, line))
        return [src.span(value)]
    found = _list_literal(src, value, kind)
    if not found:
        use.unresolved.append(UnresolvedCommand(kind, line, src.segment(value),
                                                "not a list literal (or a variable bound to one)"))
        return []
    spans = []
    for lst, via in found:
        spans.append(src.span(lst))
        values = [number_value(e) for e in lst.elts]
        if None in values:
            use.unresolved.append(UnresolvedCommand(kind, line, src.segment(lst), f"an element of {kind} is not a "
                                                                                  "numeric literal"))
            continue
        joint_list = JointList(src.span(lst), values, line, via)
        if all(v == 0 for v in values):
            use.zero_lists.append((joint_list.span, kind, line))
        elif all(joint_list.span != other.span for _, other in use.rates):
            use.rates.append((kind, joint_list))
    return spans


def array_length(text: str) -> int | None:
    """Entries of a list literal or ``[x] * n`` given as text; None for anything else."""
    try:
        node = ast.parse(text.strip(), mode="eval").body
    except SyntaxError:
        return None
    if isinstance(node, (ast.List, ast.Tuple)):
        return len(node.elts)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult) and isinstance(node.left, ast.List) \
            and isinstance(node.right, ast.Constant) and isinstance(node.right.value, int):
        return len(node.left.elts) * node.right.value
    return None


def inconsistent_joint_arrays(src: SourceFile, use: JointTrajectoryUse, new_text: dict[Span, str]) -> list[str]:
    """Scopes (functions) whose joint arrays — names, positions, velocities, accelerations — would not all
    have one length once ``new_text`` replaces their literals; one description per scope, naming the lines.
    Only scopes where an array changes length are checked (a source that was already so is reported by B.3)."""
    by_scope: dict = {}
    for scope, kind, line, span in use.members:
        if span is None:
            continue
        before = array_length(src.data[span.start:span.end].decode("utf-8"))
        after = array_length(new_text[span]) if span in new_text else before
        by_scope.setdefault(scope, []).append((line, kind, before, after))
    problems = []
    for scope, arrays in by_scope.items():
        if all(a == b for _, _, b, a in arrays) or len({a for *_, a in arrays if a is not None}) <= 1:
            continue
        where = f"in {scope.name}()" if hasattr(scope, "name") else "at module level"
        listed = ", ".join(f"line {line} {'joint_names' if kind == 'names' else kind}: {after}"
                           for line, kind, _, after in sorted(arrays, key=lambda a: a[0]))
        problems.append(f"joint arrays of different lengths {where} after retargeting ({listed})")
    return problems
