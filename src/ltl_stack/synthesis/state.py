"""A position of the game with the system goal being pursued: what ``SymbolicStrategy.step`` returns."""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True, eq=False)
class State:
    """A position of the game with the index of the system goal being pursued.

    ``id`` is stable across runs: the valuation bits (inputs then outputs, spec order, first
    proposition is the least significant bit) plus ``goal`` times 2^(number of propositions).
    """

    inputs: dict[str, bool]
    outputs: dict[str, bool]
    goal: int
    id: int = field(default=-1)

    def __post_init__(self) -> None:
        if self.id < 0:
            bits = 0
            for k, v in enumerate([*self.inputs.values(), *self.outputs.values()]):
                bits |= int(bool(v)) << k
            n = len(self.inputs) + len(self.outputs)
            object.__setattr__(self, "id", bits + (self.goal << n))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, State) and other.id == self.id and \
            other.inputs == self.inputs and other.outputs == self.outputs

    def __hash__(self) -> int:
        return hash(self.id)

    @property
    def valuation(self) -> dict[str, bool]:
        return {**self.inputs, **self.outputs}
