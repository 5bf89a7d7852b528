"""The GR(1) specification model shared by every layer.

A spec has input (environment) and output (system) Boolean propositions and six sections
of clauses (thesis Def. 3.4.2):

    env_init, sys_init        formulas over unprimed variables
    env_safety, sys_safety    formulas over unprimed and primed variables (``G phi``)
    env_liveness, sys_liveness  formulas over unprimed and primed variables (``G F phi``)

Each clause remembers where it was written, so every message about it can name file and line.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

from ltl_stack.spec.formula import Formula

SECTIONS = ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness")

# Section names in the .slugsin format, in the order slugs documents them.
SLUGSIN_SECTIONS = {
    "env_init": "ENV_INIT",
    "sys_init": "SYS_INIT",
    "env_safety": "ENV_TRANS",
    "sys_safety": "SYS_TRANS",
    "env_liveness": "ENV_LIVENESS",
    "sys_liveness": "SYS_LIVENESS",
}


@dataclass(frozen=True)
class Clause:
    """One clause of a section: its formula and where (and how) it was written."""

    formula: Formula
    text: str = ""
    file: str = "<memory>"
    line: int = 0

    @property
    def location(self) -> str:
        """``file:line`` for messages."""
        return f"{self.file}:{self.line}"


@dataclass(frozen=True)
class IntegerVariable:
    """An integer proposition ``name:lo...hi``, bit-blasted into ``bits`` (least significant first).

    The bits are ordinary Boolean propositions of the spec (in ``inputs`` or ``outputs``).
    """

    name: str
    low: int
    high: int
    bits: tuple[str, ...]


@dataclass
class Spec:
    """A GR(1) specification over Boolean propositions."""

    inputs: list[str] = field(default_factory=list)
    outputs: list[str] = field(default_factory=list)
    env_init: list[Clause] = field(default_factory=list)
    sys_init: list[Clause] = field(default_factory=list)
    env_safety: list[Clause] = field(default_factory=list)
    sys_safety: list[Clause] = field(default_factory=list)
    env_liveness: list[Clause] = field(default_factory=list)
    sys_liveness: list[Clause] = field(default_factory=list)
    integers: list[IntegerVariable] = field(default_factory=list)
    source: str = "<memory>"
    #: what the reader wants a user to hear (an isolated region of a map), one line each
    warnings: list[str] = field(default_factory=list)

    def section(self, name: str) -> list[Clause]:
        """The clauses of section ``name`` (one of ``SECTIONS``)."""
        if name not in SECTIONS:
            raise ValueError(f"unknown section {name!r}; expected one of {', '.join(SECTIONS)}")
        return getattr(self, name)

    def with_section(self, name: str, clauses: list[Clause]) -> Spec:
        """A copy of this spec with section ``name`` replaced."""
        self.section(name)
        return replace(self, **{name: list(clauses)})

    @property
    def propositions(self) -> list[str]:
        """Inputs then outputs."""
        return [*self.inputs, *self.outputs]
