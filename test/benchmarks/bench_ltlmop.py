"""Differential against LTLMoP itself (on demand, not in CI).

Runs LTLMoP's own compiler (``specCompiler.SpecCompiler(...).compile()``: its structured-English
parser, its decomposition, JTLV's GR(1) synthesis) and ``synthesize`` on every example project of an
LTLMoP checkout, each on a fresh copy of the examples (LTLMoP writes its .ltl/.smv/.aut next to the
project), and prints both verdicts.

Set-up (outside the repository; see docs/benchmarks/ltlmop.md):

    git --git-dir=<fetched LTLMoP>/.git archive HEAD src | tar x -C ../ltlmop
    (cd ../ltlmop/src/etc/jtlv && sh build.sh)                      # JTLV's GROne, with javac
    PYENV_VERSION=2.7.18 python -m pip install --target ../ltlmop/py2lib numpy==1.16.6 Polygon2

    python test/benchmarks/bench_ltlmop.py --ltlmop ../ltlmop \
        --python2 $(PYENV_VERSION=2.7.18 pyenv which python) --py2lib ../ltlmop/py2lib
"""
from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

LTLMOP_RUN = r'''
import json, sys
import specCompiler
try:
    result = specCompiler.SpecCompiler(sys.argv[1]).compile()
except Exception as e:
    print("RESULT " + json.dumps({"error": "%s: %s" % (type(e).__name__, e)}))
else:
    if result is None or result[0] is None:
        print("RESULT " + json.dumps({"error": "did not compile"}))
    else:
        print("RESULT " + json.dumps({"realizable": bool(result[0])}))
'''


def ltlmop_verdict(spec: Path, root: Path, python2: str, py2lib: str, timeout: float) -> str:
    lib = root / "src" / "lib"
    env = {"PYTHONPATH": f"{py2lib}:{lib}", "PATH": "/usr/bin:/bin", "HOME": tempfile.gettempdir()}
    try:
        done = subprocess.run([python2, "-c", LTLMOP_RUN, spec.name], cwd=spec.parent, env=env, capture_output=True,
                              text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout"
    lines = [line for line in done.stdout.splitlines() if line.startswith("RESULT ")]
    if not lines:
        return "error: " + (done.stderr.strip().splitlines() or ["no result"])[-1][:120]
    result = json.loads(lines[-1][7:])
    if "error" in result:
        return "error: " + result["error"][:120]
    return "realizable" if result["realizable"] else "unrealizable"


def our_verdict(spec: Path, timeout: float) -> tuple[str, str]:
    try:
        done = subprocess.run([sys.executable, "-m", "ltl_stack.synthesis.cli", str(spec), "--json"],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout", ""
    if done.returncode in (0, 10):
        summary = json.loads(done.stdout)
        note = "; ".join(summary.get("vacuity", []) + summary.get("warnings", []))
        return ("realizable" if summary["realizable"] else "unrealizable"), note
    return "refused", done.stderr.strip().splitlines()[-1].split(": error: ", 1)[-1][:160]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--ltlmop", type=Path, required=True, help="LTLMoP checkout (with src/lib, src/examples)")
    parser.add_argument("--python2", required=True, help="a Python 2.7 interpreter")
    parser.add_argument("--py2lib", required=True, help="folder with numpy 1.16.6 and Polygon2 for Python 2.7")
    parser.add_argument("--timeout", type=float, default=300)
    parser.add_argument("--only", nargs="*", help="only the projects whose path contains one of these")
    args = parser.parse_args()
    examples = sorted((args.ltlmop / "src" / "examples").rglob("*.spec"))
    if args.only:
        examples = [e for e in examples if any(word in str(e) for word in args.only)]
    print("| project | LTLMoP | ltl_stack | agree | note |")
    print("|---|---|---|---|---|")
    agree = total = 0
    for spec in examples:
        name = spec.relative_to(args.ltlmop / "src" / "examples")
        with tempfile.TemporaryDirectory() as folder:  # the whole tree: some projects use ../firefighting's map
            copy = Path(folder) / "examples"
            shutil.copytree(args.ltlmop / "src" / "examples", copy)
            ours, note = our_verdict(copy / name, args.timeout)
            theirs = ltlmop_verdict(copy / name, args.ltlmop, args.python2, args.py2lib, args.timeout)
        same = theirs == ours
        both = theirs in ("realizable", "unrealizable")
        total += both
        agree += both and same
        mark = "yes" if same else ("—" if not both else "**no**")
        print(f"| {name} | {theirs} | {ours} | {mark} | {note.replace('|', '/')} |", flush=True)
    print(f"\nLTLMoP gave a verdict on {total} of {len(examples)} projects; ltl_stack agrees on {agree}.")


if __name__ == "__main__":
    main()
