"""Spec reading speed (on demand): python -m pytest test/benchmarks/test_spec_parsing.py -q -s

The peer is splitting the same text into words (``str.split``), the least any reader must do; the
ratio says how much the parser adds. Figures go to docs/benchmarks/spec.md.
"""
from __future__ import annotations

import statistics
import time
from pathlib import Path

import pytest

from ltl_stack.spec import load_spec, parse_slugsin, parse_structured

ROOT = Path(__file__).resolve().parents[2]
SPECS = ROOT.parent / "shared" / "specs"
OUT = ROOT / "docs" / "benchmarks" / "spec.md"


def median_seconds(action, repeats: int = 5) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def scaled(text: str, copies: int) -> str:
    """The spec with each clause line repeated ``copies`` times (same propositions)."""
    out: list[str] = []
    declaring = False
    for line in text.splitlines():
        if line.startswith("["):
            declaring = line.strip() in ("[INPUT]", "[OUTPUT]")
            out.append(line)
        elif declaring or not line.strip() or line.lstrip().startswith("#"):
            out.append(line)
        else:
            out.extend([line] * copies)
    return "\n".join(out) + "\n"


@pytest.mark.skipif(not SPECS.is_dir(), reason="../shared/specs is absent")
def test_spec_parsing_speed():
    files = sorted(SPECS.glob("**/*.slugsin"))
    largest = max(files, key=lambda p: p.stat().st_size)
    text = largest.read_text()
    rows = []

    def row(what: str, size: int, parse, peer_text: str) -> None:
        seconds = median_seconds(parse)
        peer = median_seconds(lambda: peer_text.split())
        rows.append(f"| {what} | {size / 1024:.0f} KiB | {seconds * 1000:.1f} ms | "
                    f"{size / 1024 / 1024 / seconds:.2f} MiB/s | {seconds / peer:.0f}x |")

    row(f"largest shared spec `{largest.name}`", len(text), lambda: parse_slugsin(text), text)
    all_text = "".join(p.read_text() for p in files)
    row(f"all {len(files)} shared .slugsin files", len(all_text), lambda: [load_spec(p) for p in files], all_text)
    structured = sorted(SPECS.glob("**/*.structuredslugs"))
    s_text = "".join(p.read_text() for p in structured)
    row(f"all {len(structured)} shared .structuredslugs (bit-blasting included)", len(s_text),
        lambda: [parse_structured(p.read_text(), str(p)) for p in structured], s_text)
    for copies in (10, 40):
        big = scaled(text, copies)
        row(f"largest spec, clauses x{copies}", len(big), lambda big=big: parse_slugsin(big), big)
    n = 100_000
    chain = "[INPUT]\n" + "\n".join(f"v{i}" for i in range(n + 1)) + "\n[OUTPUT]\n[ENV_INIT]\n" \
        + " ".join(["&"] * n + [f"v{i}" for i in range(n + 1)]) + "\n"
    row(f"one clause `& & … v0 … v{n}` ({n} operators)", len(chain), lambda: parse_slugsin(chain), chain)

    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(
        "# Spec reading speed\n\n"
        "Command: `python -m pytest test/benchmarks/test_spec_parsing.py -q -s` (median of 5 runs; "
        "taken on the shared 2-core machine while other developers were working, so under load).\n"
        "The peer is `str.split()` of the same text, the least any reader has to do; the last column is "
        "parse time / split time.\n\n"
        "| input | size | parse | throughput | vs split |\n|---|---|---|---|---|\n"
        + "\n".join(rows) + "\n")
    print("\n".join(rows))
