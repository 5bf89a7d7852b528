"""What the standard library gained after Python 3.8, for the one place it is needed (ROS Noetic runs 3.8).

``StrEnum``: an ``Enum`` whose members are ``str`` and print as their value (``enum.StrEnum`` from 3.11);
``str()``, ``format()`` and f-strings give ``"hold"``, not ``"ViolationPolicy.HOLD"``, on every Python.

``slotted``: what ``dataclass(slots=True)`` (3.10) does to a frozen dataclass: the same class rebuilt with
``__slots__`` for its fields and no per-instance ``__dict__``, so that large formulas stay small.
"""
from __future__ import annotations

import dataclasses
from enum import Enum
from typing import TypeVar

T = TypeVar("T")


class StrEnum(str, Enum):
    """String-valued enum members that compare, serialise and format as their value."""

    def __str__(self) -> str:
        return str(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)


def slotted(cls: type[T]) -> type[T]:
    """``cls`` (a frozen dataclass) rebuilt with ``__slots__`` for its fields; pickling and copying keep
    working (they set the fields with ``object.__setattr__``, as a frozen class requires)."""
    names = tuple(f.name for f in dataclasses.fields(cls))
    body = dict(cls.__dict__)
    for name in (*names, "__dict__", "__weakref__"):
        body.pop(name, None)  # a field's default stays in the generated __init__
    body["__slots__"] = names
    body["__getstate__"] = _slotted_getstate
    body["__setstate__"] = _slotted_setstate
    new = type(cls)(cls.__name__, cls.__bases__, body)
    new.__qualname__ = cls.__qualname__
    return new


def _slotted_getstate(self: object) -> tuple:
    return tuple(getattr(self, f.name) for f in dataclasses.fields(self))


def _slotted_setstate(self: object, state: tuple) -> None:
    for f, value in zip(dataclasses.fields(self), state):
        object.__setattr__(self, f.name, value)
