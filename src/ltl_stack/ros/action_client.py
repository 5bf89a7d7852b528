"""An actionlib ``SimpleActionClient`` that never loses the end of a goal.

python3-actionlib (1.14, Debian's and Noetic's) takes the handle of a new goal only after
``send_goal`` has published it. A server that ends the goal at once (an abort of a goal it cannot
serve, a quick success) can have its status and result handled on actionlib's subscriber threads
before that; the simple client then drops them as transitions "on a goal handle that we're not
tracking", so ``done_cb`` never runs and ``wait_for_result`` waits out its whole timeout. On a busy
machine this happens (seen about once in 20 cancel-then-abort rounds with two cores loaded).
Here the transition and feedback callbacks wait until ``send_goal`` holds the new handle.
"""
from __future__ import annotations

import threading
from typing import Any

import actionlib


class SimpleActionClient(actionlib.SimpleActionClient):
    """``actionlib.SimpleActionClient`` with ``send_goal`` and its callbacks ordered (see above)."""

    def __init__(self, ns: str, action_spec: type) -> None:
        super().__init__(ns, action_spec)
        self._sending = threading.Lock()

    def send_goal(self, goal: Any, done_cb=None, active_cb=None, feedback_cb=None) -> None:
        with self._sending:
            super().send_goal(goal, done_cb, active_cb, feedback_cb)

    # Called on actionlib's threads holding the goal's own lock, which send_goal never takes.
    def _handle_transition(self, gh: Any) -> None:
        with self._sending:
            pass
        super()._handle_transition(gh)

    def _handle_feedback(self, gh: Any, feedback: Any) -> None:
        with self._sending:
            pass
        super()._handle_feedback(gh, feedback)
