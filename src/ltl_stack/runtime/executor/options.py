"""The controller executor's options, each declared once. ROS-free.

Every option is one field of ``Options`` made with ``option(...)``: its default, its meaning, the
values that make sense (``Bound``, choices, a ROS name) and the placeholder of its flag. Everything
else is derived from these fields, so the copies cannot drift:

* ``EXECUTOR_PARAMS``, the ``Param`` schema that checks every value (``runtime.config.node_params``);
* the flags of ``controller_executor`` and their ``--help`` (``add_option_arguments``);
* the ``~param`` of each option, which the node reads (``setup.merge_options``);
* the effective values the node publishes as ``~effective_options`` (``effective_params``), which
  the controller view reads;
* the options table of docs/executor.md (``options_table``; a unit test keeps them equal and
  ``tools/write_options_table.py`` rewrites it).
"""
from __future__ import annotations

import argparse
from dataclasses import MISSING, Field, dataclass, field, fields
from enum import Enum
from typing import Any

from ltl_stack.runtime.config.node_params import Bound, Param
from ltl_stack.runtime.executor.controller import VIOLATION_POLICIES, ViolationPolicy
from ltl_stack.synthesis.options import options_from

#: The explicit automaton is extracted (and its ids used) up to this many states by default.
MAX_EXPLICIT_STATES = 20000
#: The private parameter (a dict) where the node publishes the options it runs with.
EFFECTIVE_OPTIONS = "effective_options"


@dataclass(frozen=True)
class OptionText:
    """How one option is described: ``doc`` (help, docs table), the flag's ``metavar``, and the
    checks of its ``Param``; ``default_text``/``range_text`` replace the derived table cells."""

    doc: str
    metavar: str = ""
    kind: Any = None
    bound: Bound = Bound.ANY
    choices: tuple[str, ...] = ()
    ros_name: bool = False
    default_text: str = ""
    range_text: str = ""


def option(default: Any, doc: str, **text: Any) -> Any:
    """A field of ``Options``: its default and its ``OptionText`` (keyword arguments of it)."""
    return field(default=default, metadata={"option": OptionText(doc, **text)})


@dataclass
class Options:
    """Settings of the node; None means "the library's default"."""

    namespace: str = option(
        "", "scenario namespace of the proposition topics `<ns>/inputs/<p>`, `<ns>/outputs/<p>` (a relative one "
        "resolves in the node's namespace)", metavar="NS", ros_name=True,
        default_text="the node's namespace when it is not /, else the mapping's, else the spec's file name")
    robotics_semantics: bool | None = option(
        None, "init semantics of the synthesis: every position satisfying env_init & sys_init must be winning; "
        "off: slugs' initial-state semantics", kind=bool)
    cooperative: bool | None = option(
        None, "cooperative strategy: prefer moves that help the environment meet its goals", kind=bool)
    strategy: str = option("", "run this saved strategy JSON instead of synthesizing", metavar="FILE")
    init_props: str = option(
        "", "initial values: inputs are assumed readings until their topic reports, outputs constrain the initial "
        "state; true *and* false values", metavar="a=1,b=0", kind=(str, dict))
    rate: float = option(0.0, "also step at this rate (for specs that progress without input changes; 0: only on "
                              "input changes)", metavar="HZ", bound=Bound.RATE_OR_ZERO)
    ready_timeout: float = option(
        10.0, "report the inputs that never published, every S seconds, until they do (0: never)", metavar="S",
        bound=Bound.PERIOD_OR_ZERO)
    freshness: float = option(
        0.0, "for inputs whose bound neither the mapping's `freshness:` nor their node's rate gives: a reading older "
        "than S seconds makes the input unknown, and the outputs are those safe for every value of it (0: never; "
        "docs/several_machines.md)", metavar="S", bound=Bound.NON_NEGATIVE)
    heartbeat: float = option(
        0.25, "republish every output topic that was silent this long (0: only on change): the heartbeat of the "
        "output nodes' deadman (`~deadman`, default 1 s, docs/nodes.md)", metavar="S", bound=Bound.PERIOD_OR_ZERO)
    on_violation: ViolationPolicy = option(
        ViolationPolicy.HOLD, "outputs after an environment-assumption violation that is not recovered "
        "(`--no-recovery`, or no move keeps the guarantees): the last outputs, or the fewest true, each made to keep "
        "`[SYS_TRANS]` when some valuation does", choices=VIOLATION_POLICIES)
    recovery: bool = option(
        True, "answer an environment-assumption violation with a recovery step (thesis §4.6) instead of holding; "
        "off with a saved `--strategy`")
    characterize: bool | None = option(
        None, "environment characterization (thesis §4.7): when the environment breaks its assumptions, learn the "
        "observed behaviour and resynthesize, keeping the robot safe meanwhile (docs/resilience.md)", kind=bool,
        default_text="on exactly when `~characterized_spec` is given")
    characterize_after_transitions: int = option(
        0, "with recovery: characterize once a violation lasted more than N transitions (thesis §4.10.2; 0: not "
        "used; with no limit at all: at once)", metavar="N", bound=Bound.NON_NEGATIVE, kind=int)
    characterize_after_seconds: float = option(
        0.0, "with recovery: characterize once a violation lasted more than T seconds (0: not used)", metavar="T",
        bound=Bound.NON_NEGATIVE)
    characterized_spec: str = option(
        "", "write the characterized spec to FILE (atomically) after each resynthesis; .slugsin: slugsin, else the "
        "structured format (English sentences for a .spec spec); turns characterization on", metavar="FILE",
        range_text="a file, not an input")
    start_paused: bool = option(False, "start paused")
    publisher_check_period: float = option(
        2.0, "how often to look for extra publishers on input topics (0: never)", metavar="S",
        bound=Bound.PERIOD_OR_ZERO)
    violation_grace: float = option(
        0.2, "report a violation only if the inputs stay inadmissible this long: one sensor change often arrives as "
        "several messages; the output policy applies at once either way", metavar="S", bound=Bound.NON_NEGATIVE)
    settle_steps: int = option(
        16, "after a step, keep stepping with unchanged inputs while the state changes, at most N times, so the robot "
        "starts its next move without waiting for an input change (0: one step per input change)", metavar="N",
        bound=Bound.NON_NEGATIVE)
    input_window: float = option(
        0.0, "after an input change wait S seconds for more, then step once with all of them (0: step on every "
        "message); one sensor change often arrives as several messages (leaving a region, entering the next), and a "
        "step between them sees inputs the environment assumptions forbid, which characterization would learn",
        metavar="S", bound=Bound.NON_NEGATIVE)
    timeout: float = option(0.0, "give up synthesizing after S seconds, exit 5 (0: no limit)", metavar="S",
                            bound=Bound.NON_NEGATIVE)
    negotiation_timeout: float = option(
        5.0, "integrative negotiation with the robots of the mapping's `negotiation:` key (thesis §4.8, "
        "docs/negotiation.md; needs characterization): seconds one message exchange may take", metavar="S",
        bound=Bound.POSITIVE)
    max_explicit_states: int = option(
        MAX_EXPLICIT_STATES, "run the explicit automaton (ids and goals of `synthesize --strategy-json/--dot`) up to "
        "this many states (0: always the symbolic strategy)", metavar="N", bound=Bound.NON_NEGATIVE)
    #: where each value came from: "--flag", "~param" or "default"
    sources: dict[str, str] = field(default_factory=dict)


def _option_fields() -> list[Field]:
    return [f for f in fields(Options) if "option" in f.metadata]


def _plain(value: Any) -> Any:
    return value.value if isinstance(value, Enum) else value


def _param(f: Field) -> Param:
    text: OptionText = f.metadata["option"]
    assert f.default is not MISSING, f.name
    return Param(f.name, _plain(f.default), text.doc, kind=text.kind, bound=text.bound, choices=text.choices,
                 ros_name=text.ros_name)


#: The schema every value is checked against, in the order of ``Options``.
EXECUTOR_PARAMS = [_param(f) for f in _option_fields()]
PARAMS_BY_NAME = {p.name: p for p in EXECUTOR_PARAMS}
TEXTS = {f.name: f.metadata["option"] for f in _option_fields()}


def flag_of(name: str) -> str:
    """``max_explicit_states`` -> ``--max-explicit-states``."""
    return "--" + name.replace("_", "-")


def _is_switch(param: Param) -> bool:
    return param.type is bool


def _default_text(param: Param) -> str:
    text = TEXTS[param.name]
    if text.default_text:
        return text.default_text
    if param.default is None:
        return "the library's"
    if isinstance(param.default, bool):
        return "on" if param.default else "off"
    if param.default == "":
        return "—"
    if isinstance(param.default, str):
        return f"`{param.default}`"
    return f"{param.default:g}"


def _range_text(param: Param) -> str:
    text = TEXTS[param.name]
    if text.range_text:
        return text.range_text
    if param.choices:
        return "one of " + ", ".join(param.choices)
    if param.ros_name:
        return "a ROS name"
    if param.type is bool:
        return "bool"
    if isinstance(param.type, tuple):
        return " or ".join({"str": "string"}.get(t.__name__, t.__name__) for t in param.type)
    ranges = {Bound.NON_NEGATIVE: "≥ 0", Bound.POSITIVE: "> 0", Bound.RATE_OR_ZERO: "≥ 0 and ≤ 1000",
              Bound.PERIOD_OR_ZERO: "0 or ≥ 0.001", Bound.ANY: ""}
    bound = ranges[param.bound]
    return f"integer {bound}".strip() if param.type is int else bound


def _flag_cell(param: Param) -> str:
    flag = flag_of(param.name)
    if _is_switch(param):
        return f"`{flag}`" + ("" if param.default is False else f" / `--no-{flag[2:]}`")
    metavar = "\\|".join(param.choices) if param.choices else TEXTS[param.name].metavar
    return f"`{flag} {metavar}`"


def add_option_arguments(parser: argparse.ArgumentParser) -> None:
    """One flag per option (a switch: ``--x`` and, unless it is off by default, ``--no-x``); each
    defaults to None, so that ``merge_options`` tells a given flag from an absent one."""
    for param in EXECUTOR_PARAMS:
        flag = flag_of(param.name)
        tail = f" (default: {_default_text(param).replace('`', '').replace('—', 'none')}"
        tail += f"; {_range_text(param)})" if _range_text(param) and not _is_switch(param) else ")"
        help_text = (param.doc.replace("`", "") + tail).replace("%", "%%")
        if _is_switch(param):
            parser.add_argument(flag, dest=param.name, action="store_true", default=None, help=help_text)
            if param.default is not False:
                parser.add_argument(f"--no-{flag[2:]}", dest=param.name, action="store_false",
                                    help=f"turn {flag} off")
            continue
        kind = param.type if param.type in (int, float) else None
        parser.add_argument(flag, dest=param.name, type=kind, default=None, help=help_text,
                            metavar=None if param.choices else TEXTS[param.name].metavar,
                            choices=list(param.choices) or None)


#: The lines around the generated table in docs/executor.md.
TABLE_START = "<!-- options table: generated from runtime/executor/options.py by tools/write_options_table.py -->"
TABLE_END = "<!-- end of the options table -->"


def options_table() -> str:
    """The options table of docs/executor.md (markdown): flag, ``~param``, default, range, meaning."""
    rows = ["| flag | `~param` | default | range | meaning |", "| --- | --- | --- | --- | --- |"]
    for param in EXECUTOR_PARAMS:
        rows.append(f"| {_flag_cell(param)} | `~{param.name}` | {_default_text(param)} | {_range_text(param)} | "
                    f"{param.doc} |")
    return "\n".join(rows) + "\n"


def with_options_table(text: str) -> str:
    """``text`` (docs/executor.md) with the lines between ``TABLE_START`` and ``TABLE_END`` replaced by
    ``options_table()``; ValueError when the markers are missing."""
    start, end = text.index(TABLE_START) + len(TABLE_START), text.index(TABLE_END)
    return text[:start] + "\n" + options_table() + text[end:]


def effective_params(options: Options) -> dict[str, Any]:
    """The values the node runs with, as a parameter server holds them: every option, the library's
    defaults filled in for the unset ones (None), enums as their names."""
    synthesis = options_from(options.robotics_semantics, options.cooperative)
    values = {p.name: _plain(getattr(options, p.name)) for p in EXECUTOR_PARAMS}
    values["robotics_semantics"] = synthesis.robotics_semantics
    values["cooperative"] = synthesis.cooperative
    values["characterize"] = characterization_on(options)
    return values


def characterization_on(options: Options) -> bool:
    """``~characterize`` if given, else on exactly when ``~characterized_spec`` names a file."""
    return bool(options.characterized_spec) if options.characterize is None else options.characterize


__all__ = ["EFFECTIVE_OPTIONS", "EXECUTOR_PARAMS", "MAX_EXPLICIT_STATES", "PARAMS_BY_NAME", "TABLE_END", "TABLE_START", "Options", "OptionText",
           "add_option_arguments", "characterization_on", "effective_params", "flag_of", "option", "options_table",
           "with_options_table"]
