"""What the two spec formats share: sections, comments, declarations and the checks on names.

Both ``.slugsin`` and the structured format are line based::

    [INPUT]            one proposition per line, or an integer ``name:lo...hi``
    [OUTPUT]
    [ENV_INIT] [SYS_INIT] [ENV_TRANS] [SYS_TRANS] [ENV_LIVENESS] [SYS_LIVENESS]
                       one clause per line; a section may appear more than once
    # comment          from a ``#`` that starts a word to the end of the line

Declarations are collected from the whole file before any clause is read, so sections may come
in any order. A reader gives ``SpecBuilder`` the clause lines' formulas; the builder makes the
``Spec`` and adds the range constraints of declared integers.
"""
from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import Formula, Var
from ltl_stack.spec.integers import (
    detect_integers,
    integer_variable,
    needs_range_constraint,
    range_constraint,
    range_text,
)
from ltl_stack.spec.model import SLUGSIN_SECTIONS, Clause, IntegerVariable, Spec

SECTION_OF_HEADER = {header: name for name, header in SLUGSIN_SECTIONS.items()}
HEADERS = ("INPUT", "OUTPUT", *SLUGSIN_SECTIONS.values())
INIT_SECTIONS = ("env_init", "sys_init")

_COMMENT = re.compile(r"(^|\s)#")
_HEADER = re.compile(r"^\s*\[(?P<name>[^\]]*)\]\s*$")
_INTEGER_DECLARATION = re.compile(
    r"^(?P<name>[^\s:]+)\s*:\s*(?P<low>-?\d+)\s*\.\.\.\s*(?P<high>-?\d+)\s*$")


@dataclass(frozen=True)
class Line:
    """One line of a spec file with its comment removed (columns unchanged)."""

    number: int
    text: str

    def first_column(self) -> int:
        return len(self.text) - len(self.text.lstrip()) + 1


def strip_comment(raw: str) -> str:
    m = _COMMENT.search(raw)
    return raw[:m.start()] if m else raw


def read_spec(text: str, file: str, valid_name: Callable[[str], bool], name_rule: str,
              parse_clause: Callable[[Line, Names], Formula]) -> Spec:
    """The reading loop both formats share; ``parse_clause`` turns one clause line into a formula."""
    builder = SpecBuilder(file, valid_name, name_rule)
    builder.read_layout(text)
    for section, line in builder.clause_lines:
        builder.add_clause(section, parse_clause(line, builder.names(section, line)), line)
    return builder.finish()


class SpecBuilder:
    """Collects sections, declarations and clauses of one file; ``names`` answers the readers."""

    def __init__(self, file: str, valid_name: Callable[[str], bool], name_rule: str):
        self.file = file
        self._valid_name = valid_name
        self._name_rule = name_rule
        self.inputs: list[str] = []
        self.outputs: list[str] = []
        self.integers: dict[str, IntegerVariable] = {}
        self.declared_at: dict[str, str] = {}  # Boolean proposition (integer bits too) -> where
        self._integer_at: dict[str, str] = {}  # integer name -> where
        self._declared_integers: list[tuple[IntegerVariable, str, Line]] = []
        self.clause_lines: list[tuple[str, Line]] = []
        self.sections: dict[str, list[Clause]] = {name: [] for name in SLUGSIN_SECTIONS}
        self.vars: dict[tuple[str, bool], Var] = {}  # one object per variable, shared by all clauses
        # the variables clauses used so far by their word (x, x'): in init sections / in others
        self._words: tuple[dict[str, Var], dict[str, Var]] = ({}, {})

    def error(self, line: int, column: int, message: str) -> SpecError:
        return SpecError(self.file, line, column, message)

    # -- pass 1: sections and declarations -------------------------------------------------

    def read_layout(self, text: str) -> None:
        """Split ``text`` into sections; declare propositions; keep clause lines for the reader."""
        current: str | None = None
        for number, raw in enumerate(text.splitlines(), start=1):
            line = Line(number, strip_comment(raw).rstrip())
            if not line.text.strip():
                continue
            header = _HEADER.match(line.text)
            if header:
                current = self._section(header["name"].strip(), line)
                continue
            if line.text.lstrip().startswith("["):
                raise self.error(number, line.first_column(),
                                 "a section header stands alone on its line, like [SYS_TRANS]")
            if current is None:
                raise self.error(number, line.first_column(),
                                 "expected a section header such as [INPUT] before the first clause")
            if current in ("INPUT", "OUTPUT"):
                self._declare(current, line)
            else:
                self.clause_lines.append((current, line))
        for var, _, _ in self._declared_integers:
            self.integers[var.name] = var
        bits = {b for var, _, _ in self._declared_integers for b in var.bits}
        plain = [n for n in (*self.inputs, *self.outputs) if n not in bits]
        for var in detect_integers(plain):
            if var.name not in self.declared_at:
                self.integers.setdefault(var.name, var)

    def _section(self, name: str, line: Line) -> str:
        if name in ("INPUT", "OUTPUT"):
            return name
        if name in SECTION_OF_HEADER:
            return SECTION_OF_HEADER[name]
        column = line.text.index("[") + 1
        expected = ", ".join(f"[{h}]" for h in HEADERS)
        raise self.error(line.number, column, f"unknown section [{name}]; expected one of {expected}")

    def _declare(self, section: str, line: Line) -> None:
        text = line.text.strip()
        column = line.first_column()
        m = _INTEGER_DECLARATION.match(text)
        if m and max(len(m["low"]), len(m["high"])) > 19:  # a sign and 18 digits
            raise self.error(line.number, column, f"integer '{m['name']}' has a bound of more than 18 digits")
        if m:
            name, low, high = m["name"], int(m["low"]), int(m["high"])
            self._check_name(name, line, column)
            if low > high:
                raise self.error(line.number, column,
                                 f"integer '{name}' has an empty range {low}...{high} (lower bound above upper)")
            var = integer_variable(name, low, high)
            where = f"a bit of integer {name} at line {line.number}"
            self._claim(name, line, column)
            self._integer_at[name] = f"integer at line {line.number}"
            for bit in var.bits:
                self._add(section, bit, line, column, where)
            self._declared_integers.append((var, section, line))
            return
        if ":" in text:
            raise self.error(line.number, column + text.index(":"),
                             f"expected an integer range such as '{text.split(':')[0]}:0...7' after ':'")
        parts = text.split()
        if len(parts) > 1:
            extra = column + text.index(parts[1], len(parts[0]))
            raise self.error(line.number, extra,
                             f"one proposition per line in [{section}]; unexpected '{parts[1]}'")
        self._check_name(text, line, column)
        self._add(section, text, line, column, f"proposition at line {line.number}")

    def _claim(self, name: str, line: Line, column: int) -> None:
        """Refuse a name already used by a proposition or an integer."""
        first = self._integer_at.get(name) or self.declared_at.get(name)
        if first is not None:
            raise self.error(line.number, column, f"'{name}' is declared twice (first as {first})")

    def _check_name(self, name: str, line: Line, column: int) -> None:
        if "'" in name:
            raise self.error(line.number, column,
                             f"a declared name cannot contain a prime: '{name}' (write x' only in clauses)")
        if not self._valid_name(name):
            raise self.error(line.number, column, f"invalid proposition name '{name}': {self._name_rule}")

    def _add(self, section: str, name: str, line: Line, column: int, where: str) -> None:
        self._claim(name, line, column)
        self.declared_at[name] = where
        (self.inputs if section == "INPUT" else self.outputs).append(name)

    # -- pass 2: clauses -------------------------------------------------------------------

    def names(self, section: str, line: Line) -> Names:
        return Names(self, section, line)

    def add_clause(self, section: str, formula: Formula, line: Line) -> None:
        self.sections[section].append(Clause(formula, line.text.strip(), self.file, line.number))

    def finish(self) -> Spec:
        """The spec, with slugs' range constraints for integers declared as ``name:lo...hi``."""
        for var, section, line in self._declared_integers:
            if not needs_range_constraint(var):
                continue
            init, trans = ("env_init", "env_safety") if section == "INPUT" else ("sys_init", "sys_safety")
            self.sections[init].append(
                Clause(range_constraint(var), range_text(var), self.file, line.number))
            self.sections[trans].append(
                Clause(range_constraint(var, primed=True), range_text(var, True), self.file, line.number))
        return Spec(inputs=list(self.inputs), outputs=list(self.outputs), integers=list(self.integers.values()),
                    source=self.file, **self.sections)


class Names:
    """Name lookups for one clause line; every problem becomes a ``SpecError`` at a column."""

    def __init__(self, builder: SpecBuilder, section: str, line: Line):
        self.builder = builder
        self.section = section
        self.line = line
        self.init = section in INIT_SECTIONS

    def error(self, column: int, message: str) -> SpecError:
        return self.builder.error(self.line.number, column, message)

    def is_integer(self, name: str) -> bool:
        return name in self.builder.integers and name not in self.builder.declared_at

    def integer(self, name: str) -> IntegerVariable:
        return self.builder.integers[name]

    def check_prime(self, name: str, primed: bool, column: int) -> None:
        if primed and self.init:
            header = SLUGSIN_SECTIONS[self.section]
            raise self.error(column, f"next-state variable {name}' in an init clause ([{header}] "
                                     "describes only the first state)")

    def known_variables(self) -> dict[str, Var]:
        """Words (``x``, ``x'``) this section may use that a reader has already looked up, with
        their variables: a reader may fill it with what ``boolean`` returned and skip the checks."""
        return self.builder._words[0 if self.init else 1]

    def allowed(self, name: str, primed: bool) -> bool:
        """True when ``boolean(name, primed, ...)`` returns without an error."""
        return name in self.builder.declared_at and not (primed and self.init)

    def boolean(self, name: str, primed: bool, column: int) -> Var:
        """The variable ``name`` (primed or not), checked against the declarations."""
        if name not in self.builder.declared_at:
            if self.is_integer(name):
                raise self.error(column, f"integer variable '{name}' needs a comparison, such as {name} = 0")
            raise self.error(column, f"undeclared proposition '{name}' (declare it in [INPUT] or [OUTPUT])")
        self.check_prime(name, primed, column)
        key = (name, primed)
        var = self.builder.vars.get(key)
        if var is None:
            var = self.builder.vars[key] = Var(name, primed)
        return var
