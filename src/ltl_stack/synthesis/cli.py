"""``synthesize``: GR(1) realizability and strategy export from the command line.

Exit codes: 0 realizable, 10 unrealizable, 2 bad input (spec error, unreadable file, bad option),
3 the explicit strategy exceeds ``--max-states``, 4 an export failed (e.g. no Graphviz for --png).
"""
from __future__ import annotations

import argparse
import json
import sys
import time

EXIT_REALIZABLE = 0
EXIT_UNREALIZABLE = 10
EXIT_BAD_INPUT = 2
EXIT_TOO_LARGE = 3
EXIT_EXPORT_FAILED = 4


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="synthesize",
        description="Check a GR(1) specification (.slugsin or structured) for realizability and "
                    "export its strategy.",
        epilog="exit codes: 0 realizable, 10 unrealizable, 2 bad input, 3 explicit strategy larger "
               "than --max-states, 4 export failed")
    p.add_argument("spec", help="specification file (.slugsin, .structuredslugs, .ltl)")
    p.add_argument("--robotics-semantics", action="store_true",
                   help="every position satisfying env_init and sys_init must be winning "
                        "(slugs' --sysInitRoboticsSemantics); default: slugs' default semantics")
    p.add_argument("--cooperative", action="store_true",
                   help="never force the environment to violate its assumptions and help it reach its "
                        "liveness goals (slugs' --cooperativeGR1Strategy)")
    p.add_argument("--json", metavar="OUT", help="write the explicit strategy in our JSON schema")
    p.add_argument("--slugs-json", metavar="OUT",
                   help="write the explicit strategy in slugs' --explicitStrategy --jsonOutput layout")
    p.add_argument("--dot", metavar="OUT", help="write the explicit strategy as Graphviz DOT")
    p.add_argument("--png", metavar="OUT", help="render the explicit strategy to PNG (needs Graphviz)")
    p.add_argument("--max-states", type=int, default=200_000, metavar="N",
                   help="give up the explicit strategy beyond N states (default 200000)")
    p.add_argument("--explain", action="store_true",
                   help="when unrealizable, explain why (ltl_stack.synthesis.explain)")
    p.add_argument("--counterstrategy", metavar="OUT",
                   help="when unrealizable, write the environment's counterstrategy (JSON; Graphviz DOT when OUT ends in .dot)")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    p.add_argument("--json-summary", action="store_true",
                   help="print a JSON summary (verdict, times, sizes) on stdout instead of text")
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    from ltl_stack.fileio import write_atomic
    from ltl_stack.spec import SpecError, load_spec
    from ltl_stack.synthesis import synthesize
    from ltl_stack.synthesis.explicit import TooManyStates

    start = time.perf_counter()

    def progress(message: str) -> None:
        if not args.quiet and time.perf_counter() - start > 1.0:
            print(f"synthesize: {message}", file=sys.stderr, flush=True)

    try:
        spec = load_spec(args.spec)
    except SpecError as e:
        print(str(e), file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as e:
        print(f"{args.spec}: {e.strerror or e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    parsed = time.perf_counter()
    result = synthesize(spec, robotics_semantics=args.robotics_semantics, cooperative=args.cooperative,
                        progress=progress)
    summary = {
        "spec": args.spec,
        "realizable": result.realizable,
        "robotics_semantics": args.robotics_semantics,
        "cooperative": args.cooperative,
        "inputs": len(spec.inputs),
        "outputs": len(spec.outputs),
        "parse_seconds": round(parsed - start, 6),
        "synthesis_seconds": round(result.seconds, 6),
        "z_iterations": result.solution.z_iterations,
    }
    code = EXIT_REALIZABLE if result.realizable else EXIT_UNREALIZABLE
    wants_explicit = any([args.json, args.slugs_json, args.dot, args.png])
    if result.realizable and wants_explicit:
        t = time.perf_counter()
        try:
            automaton = result.strategy.explicit(max_states=args.max_states, progress=progress)
        except TooManyStates as e:
            print(f"synthesize: {e}; raise --max-states or use the symbolic strategy", file=sys.stderr)
            return EXIT_TOO_LARGE
        summary["explicit_seconds"] = round(time.perf_counter() - t, 6)
        summary["states"] = len(automaton)
        try:
            if args.json:
                write_atomic(args.json, json.dumps(automaton.to_json(), indent=1) + "\n")
            if args.slugs_json:
                write_atomic(args.slugs_json, json.dumps(automaton.to_slugs_json(), indent=1) + "\n")
            if args.dot:
                write_atomic(args.dot, automaton.to_dot())
            if args.png:
                automaton.write_png(args.png)
        except (OSError, RuntimeError) as e:
            print(f"synthesize: export failed: {e}", file=sys.stderr)
            return EXIT_EXPORT_FAILED
    elif wants_explicit and not args.quiet:
        print("synthesize: unrealizable, no strategy to export", file=sys.stderr)
    if not result.realizable and (args.explain or args.counterstrategy):
        explained = _explain(spec, args, summary)
        if explained is not None:
            return explained
    explanation_text = summary.pop("explanation_text", None)
    if args.json_summary:
        print(json.dumps(summary, indent=1))
    elif not args.quiet:
        verdict = "REALIZABLE" if result.realizable else "UNREALIZABLE"
        extra = f", {summary['states']} states" if "states" in summary else ""
        print(f"{verdict} ({result.seconds:.3f} s{extra})")
        if explanation_text:
            print(explanation_text)
    return code


def _explain(spec, args, summary: dict) -> int | None:
    """Explain why the spec is unrealizable and, with --counterstrategy, write the environment's
    counterstrategy (JSON; DOT too when OUT ends in .dot). Returns an exit code only when writing failed."""
    from ltl_stack.fileio import write_atomic
    from ltl_stack.synthesis.explain import explain

    def progress(text: str) -> None:
        if not args.quiet:
            print(f"synthesize: {text}", file=sys.stderr, flush=True)

    explanation = explain(spec, robotics_semantics=args.robotics_semantics,
                          counterstrategy=bool(args.counterstrategy), progress=progress)
    if args.explain:
        summary["explanation"] = explanation.to_dict()
        summary["explanation_text"] = explanation.to_text()
    if args.counterstrategy:
        counter = explanation.counterstrategy
        if counter is None:
            print("synthesize: no counterstrategy: the spec is realizable", file=sys.stderr)
            return None
        text = counter.to_dot() if args.counterstrategy.endswith(".dot") else json.dumps(counter.to_json(), indent=1) + "\n"
        try:
            write_atomic(args.counterstrategy, text)
        except OSError as e:
            print(f"synthesize: cannot write {args.counterstrategy}: {e}", file=sys.stderr)
            return EXIT_EXPORT_FAILED
    return None


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
