"""Everything the controller executor does before ROS: options, spec and mapping, topics, strategy.

ROS-free, so ``controller_executor --check`` and the unit tests run it without a master; the node
(``ltl_stack.ros.executor``) only adds the wiring. The executor's options are declared once
(``runtime.executor.options``): a command-line flag wins over the ``~param`` of the same name, which
wins over the default, and every value is checked (type, range, choices) before anything starts.

Strategy ids: when the explicit automaton of the synthesized strategy has at most
``max_explicit_states`` states, it is extracted exactly as ``synthesize --strategy-json/--dot`` does and
stepped (``AutomatonStrategy``), so the state ids and goal numbers on ``~state`` are those of the
exported picture. Beyond the bound the symbolic strategy runs, and its ids are its own
(valuation bits and goal), not those of an export.

Recovery (``--recovery``, default on; thesis §4.6): the synthesized strategy is wrapped in a
``RecoveringStrategy``, whose ``recover`` is the Controller's hook, so an environment-assumption
violation is answered by a recovery-mode step instead of holding forever. A saved ``--strategy``
has no symbolic strategy to recover with: recovery is off then.

Environment characterization (``--characterize``; thesis §4.7, Alg. 2-3, §4.10.2; docs/resilience.md):
the strategy is a ``runtime.resilience.resilient_executor.BackgroundResilience`` (monitor, recovery moves,
resynthesis in a worker thread, the user's env liveness, abort). Off by default; on when
``~characterized_spec`` names the file that keeps what was learned (``characterization_on``): a
resynthesis the user cannot see afterwards would be a surprise. The threshold (more than
``characterize_after_transitions`` violating transitions or ``characterize_after_seconds`` seconds;
0 = that limit unused, both 0 = at once) applies only with recovery on; without recovery the
controller characterizes at the first violation.
"""
from __future__ import annotations

import os
import posixpath
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Tuple

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.runtime.config.mapping import Mapping as PropositionMapping
from ltl_stack.runtime.config.mapping import (
    MappingError,
    check_mapping,
    load_mapping,
    misfit,
    resolve_topics,
    valuation_topics,
)
from ltl_stack.runtime.config.node_params import NodeConfigError, coerce_param
from ltl_stack.runtime.config.ros_names import check_proposition_names, is_legal_name, load_spec_for_ros
from ltl_stack.runtime.executor.controller import Controller, ViolationPolicy
from ltl_stack.runtime.executor.explicit import AutomatonStrategy
from ltl_stack.runtime.executor.options import (
    EXECUTOR_PARAMS,
    MAX_EXPLICIT_STATES,
    PARAMS_BY_NAME,
    Options,
    characterization_on,
    flag_of,
)
from ltl_stack.runtime.executor.output_guard import OutputGuard
from ltl_stack.runtime.executor.recovery import RecoveringStrategy
from ltl_stack.runtime.resilience.characterize import Threshold
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience
from ltl_stack.spec.valuation import parse_valuation
from ltl_stack.synthesis import Automaton, synthesize
from ltl_stack.synthesis.errors import LimitReached, SynthesisError
from ltl_stack.synthesis.explicit import TooManyStates
from ltl_stack.synthesis.game import backend_line

NODE_NAME = "controller_executor"


class ExecutorError(UserError):
    """A problem the user can fix (bad file, argument or parameter); ``code`` is the exit code."""


#: Looks up a private parameter: (is it set, its value).
ParamLookup = Callable[[str], Tuple[bool, Any]]


def no_params(_name: str) -> tuple[bool, Any]:
    """The lookup of a run without a parameter server (``--check``)."""
    return False, None


def params_lookup(params: Mapping[str, Any]) -> ParamLookup:
    """The lookup in the node's private parameters fetched at once (the node asks the master for the
    whole ``~`` namespace in one call instead of a ``has_param`` per parameter, 21 round trips at
    start-up, each slow when the master is busy)."""
    def lookup(name: str) -> tuple[bool, Any]:
        return (True, params[name]) if name in params else (False, None)

    return lookup


def merge_options(given: Mapping[str, Any], lookup: ParamLookup = no_params) -> Options:
    """The command line's value if given (not None), else the ``~param`` if set, else the default;
    each checked against its ``Param``. Raises ``ExecutorError`` naming the flag or parameter (also for a
    command-line value that is no option: a flag the parser has but no ``Options`` field)."""
    unknown = sorted(set(given) - set(PARAMS_BY_NAME))
    if unknown:
        raise ExecutorError(f"{NODE_NAME}: {flag_of(unknown[0])} is not an option of the executor")
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for param in EXECUTOR_PARAMS:
        flag = flag_of(param.name)
        if given.get(param.name) is not None:
            raw, source = given[param.name], flag
        else:
            found, raw = lookup(param.name)
            source = f"~{param.name}" if found else "default"
            if not found:
                raw = param.default
        label = flag if source == flag else f"parameter ~{param.name}"
        try:
            values[param.name] = coerce_param(param, raw, NODE_NAME, label=label)
        except NodeConfigError as err:
            raise ExecutorError(str(err)) from None
        sources[param.name] = source
    if isinstance(values["init_props"], Mapping):
        items = values["init_props"].items()
        bad = [k for k, v in items if not isinstance(v, (bool, int)) or not isinstance(k, str)]
        if bad:
            raise ExecutorError(f"{NODE_NAME}: parameter ~init_props: {bad[0]!r} needs a true/false value")
        values["init_props"] = ",".join(f"{k}={int(bool(v))}" for k, v in items)
    values["on_violation"] = ViolationPolicy(values["on_violation"])
    options = Options(**values, sources=sources)
    if characterization_on(options) and options.strategy:
        raise ExecutorError(f"{NODE_NAME}: {_label(options, 'characterize')} needs the synthesized strategy; "
                            f"it cannot be used with {_label(options, 'strategy')} (a saved strategy)")
    if options.characterized_spec and Path(options.characterized_spec).is_dir():
        raise ExecutorError(f"{NODE_NAME}: {_label(options, 'characterized_spec')} {options.characterized_spec!r} "
                            "is a folder; name the file to write")
    if options.characterized_spec and not Path(options.characterized_spec).resolve().parent.is_dir():
        raise ExecutorError(f"{NODE_NAME}: {_label(options, 'characterized_spec')} {options.characterized_spec!r}: "
                            "its folder does not exist")
    return options


def _label(options: Options, name: str) -> str:
    source = options.sources.get(name, "default")
    return source if source.startswith("--") else f"parameter ~{name}"


def threshold_of(options: Options) -> Threshold:
    """The §4.10.2 threshold: the limits that are > 0 (neither: characterize at once)."""
    return Threshold(transitions=options.characterize_after_transitions or None,
                     seconds=options.characterize_after_seconds or None)


def check_characterized_spec(options: Options, inputs: list[str | None]) -> None:
    """Refuse a ``~characterized_spec`` that is one of the node's input files, a FIFO or a device
    (before anything runs: the atomic write would replace it)."""
    if options.characterized_spec:
        try:
            cli.check_outputs(inputs, [options.characterized_spec])
        except UserError as err:
            raise ExecutorError(f"{NODE_NAME}: {_label(options, 'characterized_spec')}: {err}") from None
        refusal = folder_refusal(options.characterized_spec)
        if refusal:
            raise ExecutorError(f"{NODE_NAME}: {_label(options, 'characterized_spec')} "
                                f"{options.characterized_spec!r}: {refusal}")


def folder_refusal(path: str) -> str | None:
    """Why no file can be written next to ``path`` (its folder is read-only, ``/proc``, full …), or
    None: a file is created there and removed again, so the first resynthesis does not find out."""
    folder = os.path.dirname(os.path.abspath(path))
    try:
        fd, probe = tempfile.mkstemp(prefix=".ltl_stack_probe.", dir=folder)
    except OSError as err:
        return f"cannot write in its folder {folder}: {err.strerror or err}"
    os.close(fd)
    try:
        os.unlink(probe)
    except OSError:
        pass
    return None


@dataclass
class Prepared:
    """A loaded and cross-checked spec and mapping, and the executor's topics."""

    spec: Any
    mapping: PropositionMapping | None
    namespace: str
    input_topics: dict[str, str]
    output_topics: dict[str, list[str]]
    warnings: list[str] = field(default_factory=list)
    #: the spec file as given ("" when it was not read from a file)
    spec_path: str = ""
    #: ``<node>/valuation`` -> the inputs that node owns (``runtime.config.mapping.valuation_topics``)
    valuation_topics: dict[str, list[str]] = field(default_factory=dict)


def load_inputs(spec_path: str, mapping_path: str | None) -> tuple[Any, PropositionMapping | None, list[str]]:
    """Load the spec and mapping and check them against each other and against ROS naming rules."""
    spec = load_spec_for_ros(spec_path, ExecutorError)
    mapping = None
    warnings: list[str] = []
    if mapping_path:
        try:
            mapping = load_mapping(mapping_path)
        except MappingError as err:
            raise ExecutorError(str(err)) from None
        check_proposition_names([*mapping.inputs, *mapping.outputs], mapping_path)
        issues = check_mapping(mapping, spec.inputs, spec.outputs)
        error = misfit(issues)
        if error is not None:
            raise ExecutorError(str(error))
        warnings = [str(i) for i in issues if i.severity != "error"]
    return spec, mapping, warnings


def scenario_namespace(option: str, node_namespace: str, mapping: PropositionMapping | None, spec_path: str) -> str:
    """The absolute namespace the proposition topics live in (``/<ns>/inputs/<p>``, ``/<ns>/outputs/<p>``).

    ``option`` (``--namespace``/``~namespace``) if given, resolved like a ROS name in the node's
    namespace; else the node's namespace when it is not ``/`` (a launch file's group, ``ROS_NAMESPACE``);
    else the mapping's namespace, else the spec's file name, under ``/``.
    """
    node_ns = "/" + node_namespace.strip("/")
    if option:
        if not is_legal_name(option) or option.startswith("~"):
            raise ExecutorError(f"{NODE_NAME}: namespace {option!r} is not a legal ROS namespace")
        return posixpath.normpath(option if option.startswith("/") else posixpath.join(node_ns, option))
    if node_ns != "/":
        return node_ns
    name = (mapping.scenario_namespace() if mapping else None) or Path(spec_path).stem
    return posixpath.normpath(posixpath.join("/", name))


def prepare(spec_path: str, mapping_path: str | None, namespace: str = "", node_namespace: str = "/") -> Prepared:
    """Load and cross-check the spec and mapping and resolve the topics; raises ``ExecutorError``."""
    spec, mapping, warnings = load_inputs(spec_path, mapping_path)
    ns = scenario_namespace(namespace, node_namespace, mapping, spec_path)
    in_topics, out_topics = resolve_topics(mapping, spec.inputs, spec.outputs, ns.strip("/"))
    return Prepared(spec, mapping, ns, in_topics, out_topics, warnings, spec_path,
                    valuation_topics(mapping, spec.inputs, ns.strip("/")))


def parse_init_props(text: str, spec: Any) -> dict[str, bool]:
    try:
        return parse_valuation(text or "", known=list(spec.propositions))
    except ValueError as err:
        raise ExecutorError(f"--init-props: {err}") from None


def build_strategy(spec: Any, options: Options, log: Callable[[str], None] = print) -> Any:
    """The strategy the controller steps: a saved one, else the synthesized one (see the module doc)."""
    if options.strategy:
        try:
            automaton = Automaton.load(options.strategy, inputs=list(spec.inputs))
        except (OSError, ValueError, KeyError, TypeError) as err:
            raise ExecutorError(f"{options.strategy}: cannot load strategy: {err}") from None
        if set(automaton.inputs) != set(spec.inputs) or set(automaton.outputs) != set(spec.outputs):
            raise ExecutorError(f"{options.strategy}: the strategy's propositions (inputs {automaton.inputs}, "
                                f"outputs {automaton.outputs}) differ from the spec's (inputs {spec.inputs}, "
                                f"outputs {spec.outputs})")
        log(f"loaded strategy {options.strategy}: {len(automaton.states)} states"
            f"{'; no recovery (it needs the synthesized strategy)' if options.recovery else ''}")
        return AutomatonStrategy(automaton, spec)
    chosen = {name: getattr(options, name) for name in ("robotics_semantics", "cooperative")
              if getattr(options, name) is not None}
    if characterization_on(options):
        return _resilient(spec, options, chosen, log)
    log(f"synthesizing {spec.source} ({backend_line()}) ...")
    result = synthesize(spec, **chosen, timeout=options.timeout or None)
    semantics = result.solution.robotics_semantics if result.solution is not None else chosen.get(
        "robotics_semantics")
    if not result.realizable:
        raise ExecutorError(f"{spec.source}: the specification is unrealizable"
                            f"{' with robotics semantics' if semantics else ''}; nothing to execute "
                            f"(synthesize {spec.source} --explain tells why)", Exit.UNREALIZABLE)
    strategy = result.strategy
    log(f"synthesized in {result.seconds:.3f} s (robotics semantics: {semantics}, "
        f"cooperative: {strategy.cooperative})")
    primary = _primary(strategy, spec, options, log)
    if not options.recovery:
        return primary
    log("recovery on: a violation of the environment assumptions is answered by a recovery step (thesis §4.6)")
    return RecoveringStrategy(primary, strategy)


def _resilient(spec: Any, options: Options, chosen: dict[str, Any], log: Callable[[str], None]) -> BackgroundResilience:
    threshold = threshold_of(options)
    log(f"synthesizing {spec.source} ({backend_line()}) ...")
    try:
        strategy = BackgroundResilience(
            spec, lock=None, recovery=options.recovery, characterize=True, threshold=threshold,
            path=options.characterized_spec or None,
            synthesis_options={**chosen, "timeout": options.timeout or None})
    except LimitReached:
        raise
    except SynthesisError:
        raise ExecutorError(f"{spec.source}: the specification is unrealizable; nothing to execute "
                            f"(synthesize {spec.source} --explain tells why)", Exit.UNREALIZABLE) from None
    when = "at the first violating transition" if not options.recovery or (
        threshold.transitions is None and threshold.seconds is None) else "once a violation lasted more than " + \
        " or ".join(x for x in (f"{threshold.transitions} transitions" if threshold.transitions else "",
                                f"{threshold.seconds:g} s" if threshold.seconds else "") if x)
    kept = f"kept in {options.characterized_spec}" if options.characterized_spec else \
        "NOT kept in a file (no ~characterized_spec)"
    log(f"environment characterization on (thesis §4.7): resynthesizing {when}, "
        f"{'with' if options.recovery else 'without'} recovery moves meanwhile; what is learned is {kept}; "
        "running the symbolic strategy (its state ids are not those of an export)")
    return strategy


def _primary(strategy: Any, spec: Any, options: Options, log: Callable[[str], None]) -> Any:
    if options.max_explicit_states > 0:
        try:
            automaton = strategy.explicit(max_states=options.max_explicit_states)
        except TooManyStates:
            log(f"the explicit strategy has more than {options.max_explicit_states} states: running the symbolic "
                "strategy; its state ids are not those of synthesize --strategy-json/--dot")
            return strategy
        log(f"running the explicit strategy ({len(automaton.states)} states; ids and goals as in "
            "synthesize --strategy-json/--dot)")
        return AutomatonStrategy(automaton, spec)
    log("running the symbolic strategy (~max_explicit_states is 0); its state ids are not those of an export")
    return strategy


def make_controller(strategy: Any, options: Options, init: Mapping[str, bool]) -> Controller:
    """The Controller for ``strategy``; a ``RecoveringStrategy`` also becomes its recovery hook, and the
    ``OutputGuard`` keeps the policy's outputs safe (Lemma 1(a), ``runtime.executor.output_guard``)."""
    recovery = strategy.recover if isinstance(strategy, RecoveringStrategy) else None
    try:
        controller = Controller(strategy, on_violation=options.on_violation, init_props=init,
                                running=True, settle_steps=options.settle_steps, recovery=recovery,
                                guard=OutputGuard(strategy))
    except ValueError as err:
        raise ExecutorError(str(err)) from None
    if isinstance(strategy, BackgroundResilience):
        strategy.lock = controller.lock
    return controller


def check_summary(spec_path: str, mapping_path: str | None, prepared: Prepared, options: Options,
                  log: Callable[[str], None]) -> dict[str, Any]:
    """``--check``: everything up to the initial state, no ROS. Raises ``ExecutorError``."""
    init = parse_init_props(options.init_props, prepared.spec)
    strategy = build_strategy(prepared.spec, options, log=log)
    controller = make_controller(strategy, options, init)
    primary = strategy.primary if isinstance(strategy, RecoveringStrategy) else strategy
    if isinstance(strategy, BackgroundResilience):
        primary = strategy.strategy
    summary: dict[str, Any] = {
        "spec": str(spec_path), "mapping": mapping_path, "namespace": prepared.namespace,
        "inputs": prepared.input_topics, "outputs": prepared.output_topics, "warnings": prepared.warnings,
        "init_props": init, "ready": controller.ready,
        "strategy": "explicit" if isinstance(primary, AutomatonStrategy) else "symbolic",
        "recovery": isinstance(strategy, RecoveringStrategy) or (
            isinstance(strategy, BackgroundResilience) and strategy.recovery),
        "characterize": isinstance(strategy, BackgroundResilience),
        "characterized_spec": options.characterized_spec or None}
    if controller.ready:
        update = controller.advance()
        summary["initial_state"] = None if update.state is None else {
            "id": update.state.id, "goal": update.state.goal, "inputs": dict(update.state.inputs),
            "outputs": dict(update.state.outputs)}
        if update.error:
            summary["error"] = update.error
    return summary


__all__ = ["EXECUTOR_PARAMS", "ExecutorError", "MAX_EXPLICIT_STATES", "Options", "Prepared", "build_strategy",
           "characterization_on", "check_characterized_spec", "check_summary", "threshold_of", "load_inputs", "make_controller", "merge_options", "parse_init_props", "prepare",
           "scenario_namespace"]
