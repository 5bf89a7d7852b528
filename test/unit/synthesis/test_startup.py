"""What a ``synthesize`` call loads and computes when it only has to print a verdict.

The realizability-only path (no export asked) must give the verdict of the full path on every
shared spec; the start-up must not import what the common path does not need (networkx through dd,
the Structured English reader and writer), while those modules stay importable on demand.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import pytest
from helpers import needs_cudd, shared_dir

import ltl_stack.errors
import ltl_stack.spec
import ltl_stack.synthesis.cli as synthesis_cli
from ltl_stack.errors import Exit
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.game import BACKEND, backend_line

#: solving it takes ~20 s per run; its verdict is checked by the synthesis benchmark
SLOW = {"basicEvasion"}


def shared_specs() -> list[Path]:
    base = shared_dir()
    if base is None:
        return []
    found = sorted((base / "specs").glob("*/*.slugsin")) + sorted((base / "specs" / "benchmarks" / "slugsin").glob("*.slugsin"))
    return [p for p in found if p.stem not in SLOW]


def run_python(code: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300,
                          check=False)


@pytest.mark.skipif(not shared_specs(), reason="../shared/specs is absent")
@pytest.mark.parametrize("path", shared_specs(), ids=lambda p: f"{p.parent.name}/{p.stem}")
@pytest.mark.parametrize("robotics", [True, False], ids=["robotics", "slugs-init"])
def test_realizability_only_gives_the_verdict_of_the_full_path(path: Path, robotics: bool) -> None:
    spec = load_spec(path)
    full = synthesize(spec, robotics_semantics=robotics)
    quick = synthesize(spec, robotics_semantics=robotics, strategy=False)
    assert quick.realizable == full.realizable
    assert quick.strategy is None
    assert (full.strategy is not None) == full.realizable


def _spec(tmp_path: Path, realizable: bool) -> Path:
    goal = "y" if realizable else "& y ! y"
    path = tmp_path / ("r.slugsin" if realizable else "u.slugsin")
    path.write_text(f"[INPUT]\nx\n\n[OUTPUT]\ny\n\n[SYS_LIVENESS]\n{goal}\n")
    return path


@pytest.mark.parametrize("realizable", [True, False])
def test_cli_without_exports_builds_no_strategy_and_keeps_the_exit_code(tmp_path, monkeypatch, capsys,
                                                                        realizable: bool) -> None:
    spec = _spec(tmp_path, realizable)
    out = tmp_path / "s.json"
    code_full = synthesis_cli.main([str(spec), "--strategy-json", str(out), "--quiet"])
    assert out.exists() == realizable

    def no_strategy(*args, **kwargs):
        raise AssertionError("the strategy was built although no export was asked")

    monkeypatch.setattr("ltl_stack.synthesis.SymbolicStrategy", no_strategy)
    code_verdict = synthesis_cli.main([str(spec), "--json"])
    assert code_verdict == code_full == (Exit.OK if realizable else Exit.UNREALIZABLE)
    assert f'"realizable": {"true" if realizable else "false"}' in capsys.readouterr().out


def test_dd_is_imported_without_networkx_which_stays_importable() -> None:
    proc = run_python("import sys\n"
                      "import ltl_stack.synthesis.game as g\n"
                      "assert 'networkx' not in sys.modules, 'networkx was imported'\n"
                      "b = g.new_manager(2**28); b.declare('x'); assert (b.var('x') & ~b.var('x')) == b.false\n"
                      "import networkx\n"
                      "print(g.BACKEND, networkx.__name__)")
    assert proc.returncode == 0, proc.stderr
    from ltl_stack.synthesis.game import BACKEND

    assert proc.stdout.split() == [BACKEND, "networkx"]  # the manager of this Python's dd (CUDD from 3.9 on)


def test_synthesize_start_up_skips_the_english_reader_and_writer() -> None:
    proc = run_python("import sys\n"
                      "import ltl_stack.synthesis.cli\n"
                      "print(sorted(m for m in sys.modules if m.startswith(('ltl_stack.spec.english_', 'ltl_stack.spec.structured_english'))))")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_every_name_of_the_spec_package_resolves() -> None:
    for name in ltl_stack.spec.__all__:
        assert getattr(ltl_stack.spec, name) is not None
    assert set(dir(ltl_stack.spec)) >= set(ltl_stack.spec.__all__)
    with pytest.raises(AttributeError):
        ltl_stack.spec.no_such_name  # noqa: B018


def test_english_spec_files_still_load(tmp_path) -> None:
    path = tmp_path / "task.spec"
    path.write_text("Sensors: person\nActions: camera\n\nIf you are sensing person then do camera\n")
    spec = load_spec(path)
    assert "person" in spec.inputs and "camera" in spec.outputs


def test_verdict_start_up_skips_strategy_automaton_and_yaml() -> None:
    """A realizability check needs neither the strategy/automaton modules nor PyYAML (~12 ms CPU)."""
    proc = run_python("import sys\n"
                      "import ltl_stack.synthesis.cli\n"
                      "skipped = ['yaml', 'ltl_stack.inputs', 'ltl_stack.synthesis.strategy',\n"
                      "           'ltl_stack.synthesis.automaton', 'ltl_stack.synthesis.explicit']\n"
                      "print([m for m in skipped if m in sys.modules])")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_every_name_of_the_synthesis_package_resolves() -> None:
    import ltl_stack.synthesis as synthesis
    from ltl_stack.synthesis.automaton import Automaton
    from ltl_stack.synthesis.strategy import SymbolicStrategy

    for name in synthesis.__all__:
        assert getattr(synthesis, name) is not None
    assert synthesis.Automaton is Automaton and synthesis.SymbolicStrategy is SymbolicStrategy
    assert set(dir(synthesis)) >= set(synthesis.__all__)
    with pytest.raises(AttributeError):
        synthesis.no_such_name  # noqa: B018


def test_inputs_still_offers_read_text(tmp_path) -> None:
    import ltl_stack.inputs as inputs
    import ltl_stack.textio as textio

    assert inputs.read_text is textio.read_text and inputs.decode_text is textio.decode_text
    (tmp_path / "bin").write_bytes(b"a\n\0")
    with pytest.raises(ltl_stack.errors.InputError, match="NUL byte"):
        inputs.read_text(tmp_path / "bin")


@needs_cudd
def test_manager_creation_writes_no_large_stash() -> None:
    """CUDD writes a stash of 1/128 of the manager's memory estimate on creation (8 MB and ~7 ms per
    process at a 1 GiB estimate); the estimate is small now, the eager-growth limit as before."""
    from ltl_stack.synthesis.game import new_manager
    from ltl_stack.synthesis.options import LOOSE_UP_TO

    bdd = new_manager(2**32)
    with warnings.catch_warnings():  # dd notes that "mem" is in bytes since 0.5.7
        warnings.simplefilter("ignore", UserWarning)
        mem = bdd.statistics()["mem"]
    # 2**28 estimate: a 4 MiB stash, ~4.04 MiB in all (a 1 GiB estimate gives ~10 MiB); smaller
    # estimates slow big fixpoints down (options.MANAGER_ESTIMATE)
    assert mem < 5 * 2**20
    assert bdd.configure()["loose_up_to"] == LOOSE_UP_TO
    assert bdd.configure()["max_memory"] == 2**32


def test_verdict_start_up_skips_the_explanation_modules() -> None:
    """``--explain`` and ``--counterstrategy`` import them when asked (~3 ms of every other run)."""
    proc = run_python("import sys\n"
                      "import ltl_stack.synthesis.cli\n"
                      "print([m for m in sys.modules if m.startswith('ltl_stack.synthesis.explain')])")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


SCRIPT = Path(__file__).resolve().parents[3] / "scripts" / "synthesize"


def _buffered_env() -> dict[str, str]:
    """This environment sets PYTHONUNBUFFERED; without it stdout to a pipe is block-buffered, so
    output that is not flushed before the process ends is lost."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    return env


@pytest.mark.parametrize("realizable", [True, False])
def test_the_script_prints_all_its_output_and_keeps_the_exit_code(tmp_path: Path, realizable: bool) -> None:
    """The script ends without Python's teardown (``cli.exit_now``): its text and ``--json`` output
    still reach a pipe whole, and the exit code is the verdict's."""
    spec = _spec(tmp_path, realizable)
    code = Exit.OK if realizable else Exit.UNREALIZABLE
    text = subprocess.run([sys.executable, str(SCRIPT), str(spec)], capture_output=True, text=True,
                          env=_buffered_env(), timeout=300, check=False)
    assert text.returncode == code, text.stderr
    assert text.stdout.startswith("REALIZABLE (" if realizable else "UNREALIZABLE ("), text.stdout
    assert text.stdout.endswith(")\n")
    # stderr holds at most progress lines (printed once the solve has run a second, as on a busy machine),
    # and without CUDD the one warning that names the backend
    without_cudd = "synthesize: warning: " + backend_line() if BACKEND != "cudd" else None
    assert [line for line in text.stderr.splitlines() if line != without_cudd and (
            not line.startswith("synthesize: ") or "warning" in line or "error" in line.lower())] == [], text.stderr
    out = tmp_path / "s.json"
    summary = subprocess.run([sys.executable, str(SCRIPT), str(spec), "--json", "--strategy-json", str(out)],
                             capture_output=True, text=True, env=_buffered_env(), timeout=300, check=False)
    assert summary.returncode == code, summary.stderr
    assert json.loads(summary.stdout)["realizable"] is realizable
    assert out.exists() == realizable
    if realizable:
        assert json.loads(out.read_text())["states"]


def _exit_now(body: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", "import sys\nfrom ltl_stack import cli\n" + body],
                          capture_output=True, text=True, env=_buffered_env(), timeout=300, check=False)


def test_exit_now_flushes_stdout_and_log_handlers_first() -> None:
    proc = _exit_now("import logging, logging.handlers\n"
                     "log = logging.getLogger('t')\n"
                     "log.addHandler(logging.handlers.MemoryHandler(100, target=logging.StreamHandler(sys.stdout)))\n"
                     "log.warning('logged')\n"
                     "print('x' * 100000, end='')\n"
                     "cli.exit_now(7)")
    assert proc.returncode == 7, proc.stderr
    assert proc.stdout.startswith("logged\n") or proc.stdout.endswith("logged\n"), proc.stdout[-50:]
    assert proc.stdout.count("x") == 100000


def test_exit_now_waits_like_sys_exit_while_another_thread_runs() -> None:
    proc = _exit_now("import threading, time\n"
                     "def late():\n"
                     "    time.sleep(0.3)\n"
                     "    print('thread done', flush=True)\n"
                     "threading.Thread(target=late).start()\n"
                     "cli.exit_now(3)")
    assert proc.returncode == 3, proc.stderr
    assert proc.stdout == "thread done\n"


def test_imports_done_enables_the_collector_and_freezes_what_is_loaded() -> None:
    proc = _exit_now("import gc\n"
                     "gc.disable()\n"
                     "import ltl_stack.synthesis.cli\n"
                     "cli.imports_done()\n"
                     "print(gc.isenabled(), gc.get_freeze_count() > 1000)\n")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["True", "True"]


def test_prime_and_unprime_rename_like_let_with_names() -> None:
    """The renamings are kept as variable BDDs (``Game._next_bdds``); the result is the same BDD."""
    from ltl_stack.spec.slugsin import parse_slugsin
    from ltl_stack.synthesis.game import Game

    game = Game(parse_slugsin("[INPUT]\na\nb\n\n[OUTPUT]\nc\n\n[SYS_TRANS]\n| & a ! c' ^ b c\n"))
    bdd = game.bdd
    current = (bdd.var("a") & ~bdd.var("c")) | bdd.apply("xor", bdd.var("b"), bdd.var("c"))
    nxt = game.prime(current)
    assert nxt == bdd.let({"a": "a'", "b": "b'", "c": "c'"}, current)
    assert bdd.support(nxt) == {"a'", "b'", "c'"}
    assert game.unprime(nxt) == current
    assert game.prime(bdd.true) == bdd.true
