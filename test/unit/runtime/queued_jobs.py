"""A resynthesis runner for ``BackgroundResilience`` in tests: it keeps the jobs until the test runs
them (as the worker thread would, later), so a test decides when a resynthesis finishes."""
from __future__ import annotations


class Jobs:
    def __init__(self) -> None:
        self.queue: list = []

    def __call__(self, job) -> None:
        self.queue.append(job)

    def run_all(self) -> None:
        while self.queue:
            self.queue.pop(0)()
