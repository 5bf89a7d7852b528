#!/usr/bin/env python3
"""Rewrite the controller executor's options table in docs/executor.md from its one declaration.

    python tools/write_options_table.py

The table is generated from ``Options`` in src/ltl_stack/runtime/executor/options.py;
test/unit/runtime/test_executor_options.py fails while the docs differ from it.
"""
from __future__ import annotations

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from ltl_stack.runtime.executor.options import with_options_table  # noqa: E402

DOC = REPO / "docs" / "executor.md"

if __name__ == "__main__":
    DOC.write_text(with_options_table(DOC.read_text(encoding="utf-8")), encoding="utf-8")
    print(f"wrote the options table of {DOC.relative_to(REPO)}")
