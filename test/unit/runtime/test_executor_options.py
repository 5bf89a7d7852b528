"""The executor's options, declared once (``runtime.executor.options``): the flags, ``--help``, the
``~param`` schema, the published effective options and the docs table all come from ``Options``."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from ltl_stack import cli
from ltl_stack.runtime.executor.controller import ViolationPolicy
from ltl_stack.runtime.executor.options import (
    EXECUTOR_PARAMS,
    Options,
    add_option_arguments,
    effective_params,
    flag_of,
    options_table,
    with_options_table,
)
from ltl_stack.runtime.executor.setup import ExecutorError, merge_options, params_lookup

DOC = Path(__file__).resolve().parents[3] / "docs" / "executor.md"
#: the fields of ``Options`` that are no option
BOOKKEEPING = {"sources"}


def parser() -> cli.ToolParser:
    made = cli.ToolParser(prog="controller_executor", description="")
    add_option_arguments(made)
    return made


def given(*argv: str) -> dict:
    return {k: v for k, v in vars(parser().parse_args(list(argv))).items()}


def test_the_docs_table_is_the_generated_one():
    text = DOC.read_text(encoding="utf-8")
    assert with_options_table(text) == text, "docs/executor.md's options table differs: run tools/write_options_table.py"
    assert options_table() in text


def test_every_option_is_a_flag_a_param_and_a_row_and_nothing_else():
    names = [f.name for f in dataclasses.fields(Options) if f.name not in BOOKKEEPING]
    assert [p.name for p in EXECUTOR_PARAMS] == names
    assert set(given()) == set(names), set(given()) ^ set(names)
    help_text = parser().format_help()
    table = options_table()
    for name in names:
        assert flag_of(name) in help_text, name
        assert f"`~{name}`" in table, name


def test_defaults_of_the_dataclass_and_the_schema_agree():
    merged = merge_options({})
    for param in EXECUTOR_PARAMS:
        value = getattr(merged, param.name)
        assert (value.value if isinstance(value, ViolationPolicy) else value) == param.default, param.name
        assert merged.sources[param.name] == "default"
    assert dataclasses.replace(merged, sources={}) == Options()


def test_flags_become_options_and_win_over_params():
    options = merge_options(given("--rate", "5", "--no-recovery", "--on-violation", "all-false", "--start-paused"),
                            params_lookup({"rate": 2.0, "settle_steps": 3}))
    assert (options.rate, options.recovery, options.on_violation, options.start_paused, options.settle_steps) == (
        5.0, False, ViolationPolicy.ALL_FALSE, True, 3), options
    assert options.sources["rate"] == "--rate" and options.sources["settle_steps"] == "~settle_steps"
    assert options.sources["heartbeat"] == "default"


def test_a_flag_that_is_no_option_is_refused():
    with pytest.raises(ExecutorError, match="--new-option is not an option of the executor"):
        merge_options({"new_option": 3})


def test_an_unknown_command_line_flag_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exit_:
        parser().parse_args(["--new-option", "3"])
    assert exit_.value.code == 2
    assert "unrecognized arguments: --new-option 3" in capsys.readouterr().err


def test_effective_params_hold_every_option_with_defaults_filled_in(tmp_path):
    effective = effective_params(merge_options({"characterized_spec": str(tmp_path / "x.structuredslugs")}))
    assert set(effective) == {p.name for p in EXECUTOR_PARAMS}
    assert None not in effective.values(), effective  # a parameter server cannot hold None
    assert (effective["robotics_semantics"], effective["cooperative"], effective["characterize"],
            effective["on_violation"]) == (True, True, True, "hold"), effective
    chosen = effective_params(merge_options({"cooperative": False, "characterize": False, "rate": 4}))
    assert (chosen["cooperative"], chosen["characterize"], chosen["rate"]) == (False, False, 4.0), chosen
