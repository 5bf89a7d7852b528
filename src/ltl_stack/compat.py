"""What the standard library gained after Python 3.8, for the one place it is needed (ROS Noetic runs 3.8).

``StrEnum``: an ``Enum`` whose members are ``str`` and print as their value (``enum.StrEnum`` from 3.11);
``str()``, ``format()`` and f-strings give ``"hold"``, not ``"ViolationPolicy.HOLD"``, on every Python.
"""
from __future__ import annotations

from enum import Enum


class StrEnum(str, Enum):
    """String-valued enum members that compare, serialise and format as their value."""

    def __str__(self) -> str:
        return str(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)
