"""``synthesize``: GR(1) realizability and strategy export from the command line.

The defaults are every tool's defaults (``options.SynthesisOptions``: robotics init semantics,
cooperative strategy); the text and ``--json`` output say which were used. ``--json`` prints the
summary on stdout; the strategy files are written with ``--strategy-json``, ``--slugs-json``,
``--dot``, ``--png`` and ``--counterstrategy``: all of them or none (each is rendered first, then
every file is written through a temporary file and renamed at the end), never over an input.
Without an export only the verdict is computed (``synthesize(strategy=False)``: no strategy, and
the fixpoint stops as soon as the answer is "unrealizable"; ``z_iterations`` is then the number of
Z iterations that took).
``--recovery`` exports the strategy with recovery transitions (thesis §4.6, Alg. 1 lines 19-25;
``SymbolicStrategy.explicit(recovery=True)``) and reports the state counts with and without them.

A realizable spec whose environment assumptions no play can meet (with the robot keeping its
safety requirements), or that has no guarantees, is vacuous: a warning line says so and ``--json``
has ``"vacuity"`` (the warnings, empty when the spec means something) and
``"assumptions_satisfiable"`` (``synthesis.vacuity``); the exit code stays 0. The check obeys
``--timeout`` and ``--max-memory`` like the solve: a limit reached during it is one error line that
also gives the verdict (exit 5). It also has a budget of its own, half the solve's CPU time (at
least 2 s): past it a warning line says the check was not completed (``"vacuity_complete"`` false,
``"assumptions_satisfiable"`` null unless already found "no") and that ``--full-vacuity-check``
runs it to its end; the verdict and exit code are unchanged. Warnings of the spec's reader (a map's isolated region) are printed
too and listed in ``"warnings"``.

Exit codes (``ltl_stack.errors.Exit``): 0 realizable, 10 unrealizable, 2 bad input, 4 an export
could not be written, 5 a limit was reached (``--timeout``, ``--max-memory``, ``--max-states``).
"""
from __future__ import annotations

import argparse
import json
import os
import threading
import time
from typing import TYPE_CHECKING, NoReturn

from ltl_stack import cli
from ltl_stack.errors import Exit, OutputError
from ltl_stack.spec.load import load_spec
from ltl_stack.spec.model import Spec
from ltl_stack.synthesis import LimitReached, synthesize
from ltl_stack.synthesis.game import BACKEND, backend_line
from ltl_stack.synthesis.options import (
    DEFAULT_MAX_MEMORY,
    Deadline,
    add_option_flags,
    options_from,
    parse_size,
)

if TYPE_CHECKING:  # pragma: no cover - the automaton module is only needed when a strategy is exported
    from ltl_stack.synthesis.automaton import Automaton

PROG = "synthesize"
EXIT_CODES = (Exit.OK, Exit.UNREALIZABLE, Exit.BAD_INPUT, Exit.WRITE_FAILED, Exit.LIMIT)
#: how long after ``--timeout`` a BDD operation that does not return in time is cut off hard
HARD_STOP_GRACE = 2.0


def _size(text: str) -> int:
    try:
        return parse_size(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def build_parser() -> cli.ToolParser:
    p = cli.ToolParser(
        PROG, "Check a GR(1) specification (.slugsin or structured) for realizability and export its strategy.",
        exit_codes=EXIT_CODES)
    p.add_argument("spec", help="specification file (.slugsin, .structuredslugs, .ltl)")
    add_option_flags(p)
    p.add_json("the summary (verdict, options, times, sizes, explanation)")
    p.add_argument("--json-summary", dest="json", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--strategy-json", metavar="OUT",
                   help="write the explicit strategy in our JSON schema (docs/strategy_json.md)")
    p.add_argument("--slugs-json", metavar="OUT",
                   help="write the explicit strategy in slugs' --explicitStrategy --jsonOutput layout")
    p.add_argument("--dot", metavar="OUT", help="write the explicit strategy as Graphviz DOT")
    p.add_argument("--png", metavar="OUT", help="render the explicit strategy to PNG (needs Graphviz)")
    p.add_argument("--recovery", action="store_true",
                   help="export the strategy with recovery transitions (thesis §4.6: answers to inputs that "
                        "break the environment assumptions, marked in every format) and report the state "
                        "counts with and without them")
    p.add_argument("--max-states", type=cli.positive_int, default=200_000, metavar="N",
                   help="give up the explicit strategy beyond N states (default 200000; exit 5)")
    p.add_argument("--timeout", type=cli.positive_float, metavar="S",
                   help="give up after S seconds of work (exit 5); default: no limit")
    p.add_argument("--max-memory", type=_size, metavar="SIZE", default=None,
                   help=f"cap the BDD manager's memory, e.g. 512M or 8G (default {DEFAULT_MAX_MEMORY // 2**30}G, "
                        "lowered to fit an address-space limit such as ulimit -v; exit 5 when reached)")
    p.add_argument("--full-vacuity-check", action="store_true",
                   help="after a realizable verdict, run the vacuity check to its end however long it takes "
                        "(default: it stops after half the solve's CPU time, at least 2 s, and says so; it "
                        "takes a few per cent of the solve on the benchmark games)")
    p.add_argument("--explain", action="store_true", help="when unrealizable, explain why")
    p.add_argument("--counterstrategy", metavar="OUT",
                   help="when unrealizable, write the environment's counterstrategy "
                        "(JSON; Graphviz DOT when OUT ends in .dot)")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors (and the --json summary)")
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return cli.run(PROG, lambda: _synthesize(args))


def script() -> NoReturn:
    """``synthesize`` as a process (``scripts/synthesize``, ``python -m``): ``main``, then the
    process ends without Python's teardown (``cli.imports_done``, ``cli.exit_now``: ~13 ms of a
    run on a small spec)."""
    cli.imports_done()
    cli.exit_now(main())


def _synthesize(args: argparse.Namespace) -> int:
    outputs = [args.strategy_json, args.slugs_json, args.dot, args.png, args.counterstrategy]
    cli.check_outputs([args.spec], outputs)
    start = time.perf_counter()
    deadline = Deadline(args.timeout)
    stop = _hard_stop(args.timeout)

    def progress(message: str) -> None:
        if not args.quiet and time.perf_counter() - start > 1.0:
            cli.say(PROG, message)

    try:
        spec = load_spec(args.spec)
        parsed = time.perf_counter()
        if not args.quiet:
            for warning in spec.warnings:
                cli.warn(PROG, warning)
        options = options_from(args.robotics_semantics, args.cooperative)
        exports = args.recovery or any([args.strategy_json, args.slugs_json, args.dot, args.png])
        # without an export only the verdict is printed: no strategy, and an early exit when unrealizable
        solve_cpu = time.process_time()
        result = synthesize(spec, robotics_semantics=options.robotics_semantics, cooperative=options.cooperative,
                            progress=progress, deadline=deadline, max_memory=args.max_memory, strategy=exports)
        solve_cpu = time.process_time() - solve_cpu
        summary = {
            "spec": args.spec,
            "realizable": result.realizable,
            **options.to_dict(),
            "options": options.describe(),
            "inputs": len(spec.inputs),
            "outputs": len(spec.outputs),
            "parse_seconds": round(parsed - start, 6),
            "synthesis_seconds": round(result.seconds, 6),
            "z_iterations": result.solution.z_iterations,
            "warnings": list(spec.warnings),
            "bdd_backend": BACKEND,
            "kernel": result.solution.kernel,
        }
        if result.realizable:
            from ltl_stack.synthesis.game import memory_guard
            from ltl_stack.synthesis.vacuity import budget_for, check  # only a realizable spec can be vacuous

            budget = None if args.full_vacuity_check else budget_for(solve_cpu)
            try:
                with memory_guard(result.game.max_memory):
                    vacuity = check(result.game, result.solution.winning, progress=progress,
                                    cpre_winning=result.solution.cpre_winning, budget=budget)
            except LimitReached as e:  # the verdict stands; say it on the one line
                raise type(e)(f"{e}, in the vacuity check after the verdict REALIZABLE") from None
            summary["vacuity"] = list(vacuity.warnings)
            summary["assumptions_satisfiable"] = vacuity.assumptions_satisfiable
            summary["vacuity_complete"] = vacuity.complete
            if not args.quiet:
                for warning in vacuity.warnings:
                    cli.warn(PROG, f"vacuous: {warning}")
                if not vacuity.complete:
                    cli.warn(PROG, f"the vacuity check was not completed within its budget ({budget:.1f} s CPU, "
                                   "half the solve's); run it in full with --full-vacuity-check")
        files: list[tuple[str, str | bytes, str]] = []
        if result.realizable and exports:
            t = time.perf_counter()
            automaton = result.strategy.explicit(max_states=args.max_states, progress=progress,
                                                 recovery=args.recovery)
            summary["explicit_seconds"] = round(time.perf_counter() - t, 6)
            summary["states"] = len(automaton)
            if args.recovery:
                summary["states_without_recovery"] = automaton.metadata["states_without_recovery"]
                summary["edges"] = sum(len(s.successors) for s in automaton.states)
                summary["recovery_edges"] = sum(len(s.recovery) for s in automaton.states)
            files = _strategy_files(automaton, args, deadline)
        elif not result.realizable and exports:
            if not args.quiet:
                cli.warn(PROG, "unrealizable, no strategy to export")
        text = None
        if not result.realizable and (args.explain or args.counterstrategy):
            text, files = _explain(spec, args, summary, deadline)
        elif args.counterstrategy and not args.quiet:
            cli.warn(PROG, "no counterstrategy: the spec is realizable")
    finally:
        stop.cancel()
    cli.write_outputs(files)
    if args.json:
        cli.print_json(summary)
    elif not args.quiet:
        verdict = "REALIZABLE" if result.realizable else "UNREALIZABLE"
        extra = f", {summary['states']} states" if "states" in summary else ""
        if "states_without_recovery" in summary:
            extra = (f", {summary['states']} states with recovery transitions, "
                     f"{summary['states_without_recovery']} without")
        print(f"{verdict} ({result.seconds:.3f} s{extra}; {options.describe()})")
        if text:
            print(text, end="")
        if BACKEND != "cudd":
            cli.warn(PROG, backend_line())
    return Exit.OK if result.realizable else Exit.UNREALIZABLE


def _strategy_files(automaton: Automaton, args: argparse.Namespace,
                    deadline: Deadline) -> list[tuple[str, str | bytes, str]]:
    """The export files, rendered in memory (nothing is written yet)."""
    files: list[tuple[str, str | bytes, str]] = []
    if args.strategy_json:
        files.append((args.strategy_json, json.dumps(automaton.to_json(), indent=1) + "\n", "strategy JSON"))
    if args.slugs_json:
        files.append((args.slugs_json, json.dumps(automaton.to_slugs_json(), indent=1) + "\n", "slugs JSON"))
    if args.dot:
        files.append((args.dot, automaton.to_dot(), "DOT file"))
    if args.png:
        remaining = deadline.remaining()
        try:
            png = automaton.to_png(timeout=120.0 if remaining is None else max(remaining, 0.1))
        except RuntimeError as e:
            raise OutputError(f"{args.png}: cannot render the PNG: {e}", Exit.WRITE_FAILED) from None
        files.append((args.png, png, "PNG"))
    return files


def _explain(spec: Spec, args: argparse.Namespace, summary: dict,
             deadline: Deadline) -> tuple[str | None, list[tuple[str, str | bytes, str]]]:
    """Explain why the spec is unrealizable (``summary["explanation"]``, the text) and render the
    environment's counterstrategy file when asked (JSON; DOT when OUT ends in .dot).

    The explanation modules are imported here: a verdict alone does not need them (~3 ms of
    every run's start-up)."""
    from ltl_stack.synthesis.explain import explain
    from ltl_stack.synthesis.explain_render import (
        counterstrategy_dot,
        counterstrategy_json,
        explanation_dict,
        explanation_text,
    )

    def progress(text: str) -> None:
        if not args.quiet:
            cli.say(PROG, text)

    explanation = explain(spec, robotics_semantics=summary["robotics_semantics"],
                          counterstrategy=bool(args.counterstrategy), progress=progress,
                          deadline=deadline, max_memory=args.max_memory)
    text = None
    if args.explain:
        summary["explanation"] = explanation_dict(explanation)
        text = explanation_text(explanation)
    files: list[tuple[str, str | bytes, str]] = []
    counter = explanation.counterstrategy
    if args.counterstrategy and counter is not None:
        data = counterstrategy_dot(counter) if args.counterstrategy.endswith(".dot") else \
            json.dumps(counterstrategy_json(counter), indent=1) + "\n"
        files.append((args.counterstrategy, data, "counterstrategy"))
    return text, files


class _NoStop:
    def cancel(self) -> None:
        pass


def _hard_stop(timeout: float | None) -> threading.Timer | _NoStop:
    """Cut the process off when one BDD operation runs far past ``--timeout`` (the deadline is
    only checked between operations): the same one line and exit code, no output written."""
    if timeout is None:
        return _NoStop()

    def stop() -> None:
        cli.error(PROG, f"gave up after {timeout:g} s (the time limit, --timeout)")
        os._exit(int(Exit.LIMIT))

    timer = threading.Timer(timeout + max(HARD_STOP_GRACE, timeout / 4), stop)
    timer.daemon = True
    timer.start()
    return timer


if __name__ == "__main__":  # pragma: no cover
    script()
