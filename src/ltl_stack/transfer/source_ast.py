"""What the other scanners need from Python's ``ast``: byte spans, import aliases, literal bindings.

Spans are byte offsets into the UTF-8 source (``ast`` columns are byte offsets), so that an edit
changes exactly the characters of one node and leaves every other byte of the file as it was.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass

from ltl_stack.errors import InputError

from .python2 import Python2Unsupported, parse_python2

#: deeper syntax trees than this are refused: real programs stay far below it, and the scanners walk
#: some expressions recursively (``- - - 1``)
MAX_AST_DEPTH = 200


@dataclass(frozen=True)
class Span:
    """Bytes ``start:end`` of the source, and the 1-based line where they begin."""

    start: int
    end: int
    line: int


class SourceFile:
    """A parsed program: its bytes, its tree, import aliases and the literal values names are bound to."""

    def __init__(self, text: str, filename: str = "<source>"):
        self.text = text
        self.filename = filename
        self.data = text.encode("utf-8")
        self.python = "3"
        self._shifts: list[int] | None = None   # Python 2: columns each line's indentation moved when parsed
        try:
            self.tree = parse_program(text, filename)
        except InvalidSyntax as err:
            try:
                self.tree, self._shifts = parse_python2(text, filename)
            except Python2Unsupported:
                raise
            except InputError:
                raise err from None  # not Python 2 either: Python 3's own message
            check_depth(self.tree, filename)
            self.python = "2"
        self._line_starts = [0]
        for i, byte in enumerate(self.data):
            if byte == 0x0A:
                self._line_starts.append(i + 1)
        self.aliases = _import_aliases(self.tree)
        self.parents: dict[ast.AST, ast.AST] = {}
        for parent in ast.walk(self.tree):
            for child in ast.iter_child_nodes(parent):
                self.parents[child] = parent
        self._bindings = _bindings(self.tree, self.parents)
        self._self_bindings: dict[tuple[ast.AST, str], list[ast.expr]] = {}
        self.functions: dict[str, list[ast.FunctionDef | ast.AsyncFunctionDef]] = {}
        for node in ast.walk(self.tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                self.functions.setdefault(node.name, []).append(node)
            elif isinstance(node, ast.Assign):
                for target in node.targets:
                    if _is_self_attribute(target):
                        self._self_bindings.setdefault((self.class_of(node), target.attr), []).append(node.value)

    def span(self, node: ast.AST) -> Span:
        start_shift = self._shifts[node.lineno - 1] if self._shifts else 0
        end_shift = self._shifts[node.end_lineno - 1] if self._shifts else 0
        start = self._line_starts[node.lineno - 1] + node.col_offset - start_shift
        end = self._line_starts[node.end_lineno - 1] + node.end_col_offset - end_shift
        return Span(start, end, node.lineno)

    def segment(self, node: ast.AST) -> str:
        span = self.span(node)
        return self.data[span.start:span.end].decode("utf-8")

    def qualname(self, node: ast.AST) -> str | None:
        """Dotted name of a Name/Attribute with import aliases resolved (``Twist`` -> ``geometry_msgs.msg.Twist``),
        also through plain aliases (``TwistMsg = Twist``: the first such binding, see :meth:`qualnames`)."""
        names = self.qualnames(node)
        return names[0] if names else None

    def qualnames(self, node: ast.AST, depth: int = 0) -> list[str]:
        """Every dotted name a Name/Attribute may stand for, in source order of the aliases' bindings
        (``TwistMsg = Twist`` and later ``TwistMsg = TwistStamped``: both)."""
        parts = []
        while isinstance(node, ast.Attribute):
            parts.append(node.attr)
            node = node.value
        if not isinstance(node, ast.Name):
            return []
        tail = ".".join(reversed(parts))
        heads = [self.aliases[node.id]] if node.id in self.aliases else []
        if not heads and depth < 10:
            bound = self.bindings(node)
            if bound and all(isinstance(v, (ast.Name, ast.Attribute)) and isinstance(v.ctx, ast.Load) for v in bound):
                for value in sorted(bound, key=lambda v: (v.lineno, v.col_offset)):
                    heads += [h for h in self.qualnames(value, depth + 1) if h not in heads]
        heads = heads or [node.id]
        return [h + "." + tail if tail else h for h in heads]

    def scope_of(self, node: ast.AST) -> ast.AST:
        while node in self.parents:
            node = self.parents[node]
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
                return node
        return self.tree

    def class_of(self, node: ast.AST) -> ast.AST | None:
        """The class a node is written in, or None."""
        while node in self.parents:
            node = self.parents[node]
            if isinstance(node, ast.ClassDef):
                return node
        return None

    def self_bindings(self, node: ast.Attribute) -> list[ast.expr]:
        """Values assigned to ``self.<attr>`` anywhere in the class of ``node`` (``self.topic = 'scan'``)."""
        if not _is_self_attribute(node):
            return []
        return self._self_bindings.get((self.class_of(node), node.attr), [])

    def calls_of(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[ast.Call]:
        """Calls of a function by its name (``f(...)``; a method: ``self.f(...)``, or ``client.f(...)`` where
        ``client`` is bound to an instance of the method's class), only when the name is defined once."""
        if len(self.functions.get(function.name, [])) != 1:
            return []
        owner = self.parents.get(function)
        calls = []
        for node in ast.walk(self.tree):
            if not isinstance(node, ast.Call):
                continue
            if not isinstance(owner, ast.ClassDef):
                if isinstance(node.func, ast.Name) and node.func.id == function.name:
                    calls.append(node)
            elif isinstance(node.func, ast.Attribute) and node.func.attr == function.name and \
                    (_is_self_attribute(node.func) or self._instance_of(node.func.value, owner.name)):
                calls.append(node)
        return calls

    def _instance_of(self, node: ast.AST, class_name: str) -> bool:
        """``node`` is a variable bound to ``ClassName(...)``."""
        return isinstance(node, ast.Name) and any(
            isinstance(v, ast.Call) and (self.qualname(v.func) or "").split(".")[-1] == class_name
            for v in self.bindings(node))

    def bindings(self, name: ast.Name) -> list[ast.expr]:
        """Values assigned to ``name`` by plain ``name = value`` in its scope, else at module level."""
        scope = self.scope_of(name)
        while True:
            found = self._bindings.get((scope, name.id))
            if found or scope is self.tree:
                return found or []
            scope = self.scope_of(scope)


def _is_self_attribute(node: ast.AST) -> bool:
    return isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self"


class InvalidSyntax(InputError):
    """A program Python 3's parser refuses (``SourceFile`` then tries it as Python 2)."""


def parse_program(text: str, filename: str) -> ast.Module:
    """``ast.parse`` with one ``InputError`` (file:line) for invalid or absurdly nested programs."""
    try:
        tree = ast.parse(text, filename=filename)
    except SyntaxError as err:  # also IndentationError ("too many levels of indentation")
        raise InvalidSyntax(filename, f"not valid Python: {err.msg}", err.lineno or 0) from None
    except (RecursionError, MemoryError):
        raise InputError(filename, "not a program this tool reads: nested too deeply for Python's parser") from None
    check_depth(tree, filename)
    return tree


def check_depth(tree: ast.Module, filename: str) -> None:
    """InputError for a syntax tree deeper than ``MAX_AST_DEPTH``."""
    stack = [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_AST_DEPTH:
            raise InputError(filename, f"nested more than {MAX_AST_DEPTH} levels deep",
                             getattr(node, "lineno", 0))
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node))


def _import_aliases(tree: ast.Module) -> dict[str, str]:
    aliases: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname:
                    aliases[alias.asname] = alias.name
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                if alias.name != "*":
                    aliases[alias.asname or alias.name] = f"{node.module}.{alias.name}"
    return aliases


def _bindings(tree: ast.Module, parents: dict) -> dict[tuple[ast.AST, str], list[ast.expr]]:
    found: dict[tuple[ast.AST, str], list[ast.expr]] = {}

    def scope_of(node):
        while node in parents:
            node = parents[node]
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
                return node
        return tree

    for node in ast.walk(tree):
        if isinstance(node, ast.Assign):
            pairs = []
            for target in node.targets:
                if isinstance(target, ast.Name):
                    pairs.append((target, node.value))
                elif isinstance(target, ast.Tuple) and isinstance(node.value, ast.Tuple) \
                        and len(target.elts) == len(node.value.elts):
                    pairs += [(t, v) for t, v in zip(target.elts, node.value.elts)
                              if isinstance(t, ast.Name)]
            for target, value in pairs:
                found.setdefault((scope_of(node), target.id), []).append(value)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.value is not None:
            found.setdefault((scope_of(node), node.target.id), []).append(node.value)
        elif isinstance(node, ast.AugAssign) and isinstance(node.target, ast.Name):
            found.setdefault((scope_of(node), node.target.id), []).append(node)  # arithmetic: not a literal
        elif isinstance(node, (ast.For, ast.comprehension)) and isinstance(node.target, ast.Name):
            found.setdefault((scope_of(node), node.target.id), []).append(node.target)
    return found


def number_value(node: ast.AST) -> float | None:
    """The value of a numeric literal, also ``-0.5`` and ``+1``; None for anything else."""
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        inner = number_value(node.operand)
        if inner is None:
            return None
        return -inner if isinstance(node.op, ast.USub) else inner
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
            and not isinstance(node.value, bool):
        return float(node.value)
    return None


def string_value(node: ast.AST) -> str | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    return None


def call_argument(call: ast.Call, position: int, keyword: str) -> ast.expr | None:
    """The argument at ``position`` or given as ``keyword=``; None when absent or behind ``*args``."""
    for kw in call.keywords:
        if kw.arg == keyword:
            return kw.value
    if position < len(call.args) and not any(isinstance(a, ast.Starred) for a in call.args[:position + 1]):
        return call.args[position]
    return None


def format_number(value: float, digits: int = 6) -> str:
    """Short decimal text of a float that reads back as a float (``0.675``, ``-0.2``, ``1.0``)."""
    text = repr(round(value, digits))
    if text in ("-0.0",):
        text = "0.0"
    return text


def format_string(value: str, like: str) -> str:
    """A string literal for ``value`` in the quote style of the literal ``like``."""
    like = like.lstrip("rRbBuU")
    quote = like[:3] if like[:3] in ('"""', "'''") else (like[:1] or "'")
    if quote in value or "\\" in value or "\n" in value:
        return repr(value)
    return quote + value + quote


def format_angle(value: float) -> str:
    """Four decimals, without a negative zero."""
    text = f"{value:.4f}"
    return "0.0000" if text == "-0.0000" else text


def format_list(items: list[str], like: str, width: int = 100) -> str:
    """A list literal of already-formatted items, wrapped like ``like`` when that spanned several lines."""
    if "\n" not in like:
        return "[" + ", ".join(items) + "]"
    second = like.split("\n")[1]
    indent = second[: len(second) - len(second.lstrip())]
    lines, current = [], "["
    for item in items:
        piece = item + ","
        budget = width - (len(indent) if not lines else 0)  # the first line starts about where the indent is
        if current.strip() not in ("[", "") and len(current) + 1 + len(piece) > budget:
            lines.append(current)
            current = indent + piece
        else:
            current = current + ("" if current.endswith("[") or not current.strip() else " ") + piece
    lines.append(current[:-1] + "]")
    return "\n".join(lines)
