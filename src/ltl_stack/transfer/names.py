"""Following a name in a program's text to the literal it stands for (thesis §2.5.1).

Through variables, ``self.<attr>`` assignments, ``rospy.get_param`` defaults and the parameters of a
wrapper function (one context per call of it). What cannot be followed carries its reason.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass, field
from typing import Dict

from .source_ast import SourceFile, Span, call_argument, string_value


@dataclass
class NameRef:
    """A channel's name: a literal (maybe through variables), or why it cannot be resolved."""

    value: str | None
    via: str | None = None            # variable name when bound through one
    problem: str | None = None        # why it cannot be resolved
    spans: list[Span] = field(default_factory=list)   # every literal a change of the name edits
    note: str | None = None           # e.g. 'the default of the parameter ~topic'


Subst = Dict[str, ast.expr]   # a wrapper's parameters -> the arguments of one call of it


def _function_of(src: SourceFile, node: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
    scope = src.scope_of(node)
    return scope if isinstance(scope, (ast.FunctionDef, ast.AsyncFunctionDef)) else None


def _parameters(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    return [a.arg for a in function.args.posonlyargs + function.args.args]


def _is_parameter(src: SourceFile, node: ast.Name) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
    """The function whose (not rebound) parameter ``node`` is, or None."""
    function = _function_of(src, node)
    if function is None or node.id not in _parameters(function) + [a.arg for a in function.args.kwonlyargs]:
        return None
    rebound = [v for v in src.bindings(node) if src.scope_of(v) is function]
    return None if rebound else function


def _argument_of(src: SourceFile, function, call: ast.Call, name: str) -> ast.expr | None:
    """The argument a call passes for parameter ``name`` (or the parameter's default)."""
    params = _parameters(function)
    position = params.index(name) if name in params else 99
    if isinstance(src.parents.get(function), ast.ClassDef) and params and params[0] == "self":
        position -= 1
    found = call_argument(call, position, name) if position >= 0 else None
    if found is not None:
        return found
    positional = function.args.posonlyargs + function.args.args
    defaults = dict(zip([a.arg for a in positional[len(positional) - len(function.args.defaults):]],
                        function.args.defaults))
    defaults.update({a.arg: d for a, d in zip(function.args.kwonlyargs, function.args.kw_defaults)
                     if d is not None})
    return defaults.get(name)


def call_contexts(src: SourceFile, site: ast.AST, nodes: list[ast.expr | None]) -> list[tuple[Subst, int | None]]:
    """One context per call of the wrapper function whose parameters give these argument nodes; the
    call itself (an empty substitution) when none is a parameter."""
    params = {n.id: f for n in nodes if isinstance(n, ast.Name) and (f := _is_parameter(src, n)) is not None}
    if not params:
        return [({}, None)]
    function = next(iter(params.values()))
    contexts = []
    for outer in src.calls_of(function):
        contexts.append(({name: _argument_of(src, function, outer, name) for name in params}, outer.lineno))
    return contexts or [({}, None)]


def resolve_name(src: SourceFile, node: ast.expr | None, subst: Subst | None = None, depth: int = 0) -> NameRef:
    """What a name argument evaluates to, when it is known in the program text: a string literal, a
    variable or ``self.<attr>`` bound only to one such value, a ``rospy.get_param`` default, or a
    wrapper's parameter (``subst``). Otherwise the reason it is not known."""
    subst = subst or {}
    if node is None:
        return NameRef(None, problem="no name argument")
    if depth > 20:
        return NameRef(None, problem="bound through too many variables")
    text = string_value(node)
    if text is not None:
        return NameRef(text, spans=[src.span(node)])
    if isinstance(node, ast.Name) and node.id in subst:
        if subst[node.id] is None:
            return NameRef(None, problem=f"the wrapper's parameter {node.id!r} is not given at a call")
        return resolve_name(src, subst[node.id], None, depth + 1)
    if isinstance(node, ast.Name):
        function = _is_parameter(src, node)
        if function is not None:
            callers = src.calls_of(function)
            return NameRef(None, problem=f"parameter {node.id!r} of {function.name}()" + (
                "; passed on through more than one function" if callers else f", and {function.name}() is not "
                                                                              "called in this program"))
        return _from_bindings(src, node.id, src.bindings(node), depth)
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self":
        return _from_bindings(src, f"self.{node.attr}", src.self_bindings(node), depth)
    if isinstance(node, ast.Call) and (src.qualname(node.func) or "").endswith("get_param"):
        param = string_value(call_argument(node, 0, "param_name"))
        default = call_argument(node, 1, "default")
        label = repr(param) if param is not None else src.segment(call_argument(node, 0, "param_name") or node)
        if default is None:
            return NameRef(None, problem=f"given at run time by the parameter {label} (no default in the program)")
        ref = resolve_name(src, default, subst, depth + 1)
        if ref.value is not None:
            ref.note = f"the default of the parameter {label}; a launch file may set another name"
        return ref
    return NameRef(None, problem=f"computed name {src.segment(node)!r}")


def _from_bindings(src: SourceFile, label: str, values: list[ast.expr], depth: int) -> NameRef:
    if not values:
        return NameRef(None, problem=f"variable {label!r} is not bound to a string literal here")
    refs = [resolve_name(src, v, None, depth + 1) for v in values]
    names = {r.value for r in refs}
    if None in names:
        problems = [r.problem for r in refs if r.problem]
        why = problems[0] if len(refs) == 1 and problems else "a computed or varying value"
        return NameRef(None, problem=f"variable {label!r} is bound to {why}")
    if len(names) > 1:
        return NameRef(None, problem=f"variable {label!r} is bound to different names ({', '.join(sorted(names))})")
    notes = [r.note for r in refs if r.note]
    return NameRef(names.pop(), via=label, spans=[s for r in refs for s in r.spans],
                   note=notes[0] if notes else None)  # every binding gets the same edit
