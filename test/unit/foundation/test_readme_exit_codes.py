"""The README's exit-code table is ``ltl_stack.errors.EXIT_TABLE``, and the tool rows use only its codes."""
from __future__ import annotations

import re
from pathlib import Path

from ltl_stack.errors import EXIT_TABLE

ROOT = Path(__file__).resolve().parents[3]


def _table(lines: list[str], header: str) -> list[list[str]]:
    start = lines.index(header)
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in re.split(r"(?<!\\)\|", line.strip())[1:-1]])
    return rows


def test_readme_exit_code_table_is_the_one_in_errors():
    lines = (ROOT / "README.md").read_text().splitlines()
    rows = _table(lines, "| code | meaning |")
    assert rows == [[str(int(code)), text] for code, text in EXIT_TABLE], rows


def test_every_script_has_a_tools_row_whose_codes_are_in_the_table():
    lines = (ROOT / "README.md").read_text().splitlines()
    rows = _table(lines, "| tool | what it does | exit codes | docs |")
    known = {int(code) for code, _ in EXIT_TABLE}
    for tool, _, codes, _ in rows:
        used = {int(c) for c in re.findall(r"(?<![\w-])(\d+)(?![\w.])", re.sub(r"\([^)]*\)", "", codes))}
        assert used and used <= known and 0 in used, (tool, codes)
    named = " ".join(row[0] for row in rows)
    scripts = sorted(p.name for p in (ROOT / "scripts").iterdir())
    missing = [s for s in scripts if f"`{s}" not in named and f"{s}`" not in named]
    assert not missing, f"scripts without a row in the README's Tools table: {missing}"
    bad_input = " ".join(row[0] for row in _table(lines, "| tool | bad input caught (besides the file checks above) | how |"))
    for tool in ("synthesize", "controller_executor", "generate_launch", "analyze_graph", "controller_trace",
                 "set_propositions", "proposition_monitor", "send_proposition_goal", "timed_proposition_server",
                 "ros_code_transfer", "mine_channels", "proposition nodes", "simulation nodes", "demo"):
        assert tool in bad_input, f"{tool} has no row in the README's bad-input table"
