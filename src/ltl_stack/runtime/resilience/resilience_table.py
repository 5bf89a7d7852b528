"""The thesis' §4.10.4 comparison, reproduced: Examples 10-12 under four approaches.

For each example (a spec and its story, ``config/<example>/story.yaml``, the same file the
``roslaunch`` scenario's ``story_environment`` plays) and each approach — base (the plain strategy:
a violation stops it), recovery (§4.6), EC (environment characterization, §4.7) and recovery + EC
with the story's threshold (§4.10.2) — the story is played in process through ``runtime.Controller``
and ``ResilientStrategy``: the robot arrives where it heads at the next transition (unless the
story's ``stop`` output holds it), the beats change the inputs, and the scripted user answers when
the controller asks (Alg. 3). Reported: whether the mission completes (every beat of the story
fired), resyntheses (EC1, EC2, after the user's liveness), times the spec was unrealizable, and
the transitions taken while the original environment assumptions were violated; next to the
figures the thesis gives. ROS-free and deterministic::

    python -m ltl_stack.runtime.resilience.resilience_table [--example alice] [--json] [--trace]
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.resilience.characterize import Mode, ResilientStrategy, Threshold
from ltl_stack.runtime.resilience.story import Story, StoryPlayer, load_story, region_of
from ltl_stack.spec import load_spec
from ltl_stack.spec.formula import evaluate
from ltl_stack.spec.model import Spec
from ltl_stack.synthesis.errors import AssumptionViolation

APPROACHES = ("base", "recovery", "ec", "recovery+ec")
#: (recovery, characterize) of each approach
SETTINGS = {"base": (False, False), "recovery": (True, False), "ec": (False, True), "recovery+ec": (True, True)}


@dataclass(frozen=True)
class Example:
    name: str
    title: str
    spec: str    # relative to config/
    story: str
    #: what the thesis reports per approach (None: the thesis does not run it)
    thesis: dict[str, str | None]
    #: the thesis' figures as numbers, per approach: Run fields (or first_episode,
    #: ec1_before_unrealizable, ec2_before_unrealizable) and their values
    figures: dict[str, dict[str, int | bool]] = field(default_factory=dict)
    max_ticks: int = 400


EXAMPLES = {
    "block_cutting": Example(
        "block_cutting", "Example 10 (Spec. 4): a pickup task without a block",
        "block_cutting/block_cutting.structuredslugs", "block_cutting/story.yaml",
        {"base": "the hand goes into the saw", "recovery": "waits, then picks up",
         "ec": "resynthesizes, stands by", "recovery+ec": None},
        {"base": {"complete": False}, "recovery": {"complete": True, "resyntheses": 0},
         "ec": {"complete": True, "resyntheses": 1}}),
    "alice": Example(
        "alice", "Example 11 (Spec. 6): Alice, the broken door and the closed door",
        "alice/alice.structuredslugs", "alice/story.yaml",
        {"base": "fails at once (door broken)",
         "recovery": "0 resyntheses, 6 moves with the door broken",
         "ec": "2 x EC1 + 1 x EC2, unrealizable, user",
         "recovery+ec": None},
        {"base": {"complete": False}, "recovery": {"resyntheses": 0, "first_episode": 6},
         "ec": {"ec1_before_unrealizable": 2, "ec2_before_unrealizable": 1, "user": 1}}),
    "patrol_recycling": Example(
        "patrol_recycling", "Example 12: patrol and recycling, three assumptions, threshold 150 transitions",
        "patrol_recycling/patrol_recycling.structuredslugs", "patrol_recycling/story.yaml",
        {"base": None, "recovery": None, "ec": "3 resyntheses",
         "recovery+ec": "1 resynthesis (spill: unrealizable, user)"},
        {"ec": {"resyntheses": 3}, "recovery+ec": {"resyntheses": 1, "user": 1}}),
}


@dataclass
class Run:
    """The outcome of one story under one approach."""

    example: str
    approach: str
    complete: bool
    beats: int
    beats_fired: int
    ticks: int
    resyntheses: int
    ec1: int
    ec2: int
    user: int
    unrealizable: int
    violated_transitions: int   # transitions taken while the original env assumptions were broken
    episodes: list[int]         # lengths of the runs of consecutive violating transitions
    recovery_steps: int
    failed_at: int | None       # the first transition whose violation the controller did not handle
    aborted: bool
    threshold: int | None
    thesis: str | None
    ec1_before_unrealizable: int | None = None  # EC1 / EC2 resyntheses before the first unrealizable one
    ec2_before_unrealizable: int | None = None
    verdict: str = ""                            # "as in the thesis", "differs: ...", or "" (no figure)
    narrative: list[str] = field(default_factory=list)

    @property
    def first_episode(self) -> int:
        return self.episodes[0] if self.episodes else 0


def package_dir() -> Path:
    """The ltl_stack package folder (where config/ is)."""
    return Path(__file__).resolve().parents[4]


def violates(spec: Spec, current: dict[str, bool], incoming: dict[str, bool]) -> bool:
    """Whether (current valuation, incoming inputs) breaks one of ``spec``'s env-safety clauses."""
    return not all(evaluate(c.formula, current, incoming) for c in spec.env_safety)


def play(spec: Spec, story: Story, approach: str, *, threshold: int | None = None, max_ticks: int = 400,
         say: Callable[[str], None] | None = None, example: str = "", thesis: str | None = None) -> Run:
    """Play ``story`` on ``spec`` with ``approach`` (one of ``APPROACHES``) in process."""
    recovery, characterize = SETTINGS[approach]
    narrative: list[str] = []

    def note(tick: int, text: str) -> None:
        line = f"[{tick:4d}] {text}"
        narrative.append(line)
        if say is not None:
            say(line)

    ticks = [0]
    rs = ResilientStrategy(spec, recovery=recovery, characterize=characterize,
                           threshold=Threshold(transitions=threshold) if recovery and characterize else None,
                           on_event=lambda e: note(ticks[0], f"controller: {e.message}"))
    story.check(spec)
    controller = Controller(rs)
    player = StoryPlayer(story)
    where = story.regions[0] if story.regions else None
    for region in story.regions:  # start where the spec's init puts the robot
        if any(evaluate(c.formula, {**dict.fromkeys(spec.inputs, False), f"{region}_c": True, **story.inputs})
               for c in spec.env_init):
            where = region
            break
    controller.report_many(_inputs(story, where, player.values))
    state = controller.state
    violated_transitions = 0
    episodes: list[int] = []
    was_broken = False
    before = None
    failed_at = None
    mode = rs.mode
    for tick in range(1, max_ticks + 1):
        ticks[0] = tick
        if not (story.stop and state.outputs.get(story.stop)):
            where = region_of(state.outputs, story.regions) or where
        beat = player.tick(where, state.outputs)
        if beat is not None:
            note(tick, f"story: {beat.name}")
        incoming = _inputs(story, where, player.values)
        broken = violates(rs.characterizer.original, {**state.inputs, **state.outputs}, incoming)
        update = controller.report_many(incoming)
        if not update.stepped and update.violation is None:
            update = controller.tick()
        player.read()
        raised = update.violation if not update.recovered else None
        if raised is not None and failed_at is None:
            failed_at = tick
            note(tick, f"controller: stopped by the violation ({_why(raised)})")
        if broken and raised is None:
            violated_transitions += 1
        if broken:
            if was_broken:
                episodes[-1] += 1
            else:
                episodes.append(1)
        was_broken = broken
        state = controller.state
        if rs.counters.unrealizable and before is None:
            before = (rs.counters.ec1, rs.counters.ec2)
        if rs.mode is not mode:
            note(tick, f"mode {mode.value} -> {rs.mode.value}")
            mode = rs.mode
        if rs.mode is Mode.WAITING_FOR_USER and story.user:
            note(tick, f"user: adds the env liveness GF({story.user})")
            try:
                rs.add_env_liveness(story.user)
            except AssumptionViolation:
                pass
            if rs.mode is not mode:
                note(tick, f"mode {mode.value} -> {rs.mode.value}")
                mode = rs.mode
        if rs.mode is Mode.ABORTED or player.complete:
            break
        if failed_at is not None and approach == "base":
            break  # the plain strategy has no way on (the thesis' base case "fails")
    c = rs.counters
    complete = player.complete and rs.mode is not Mode.ABORTED
    note(ticks[0], "mission complete" if complete else
         f"mission not complete: {len(player.fired)} of {len(story.beats)} beats")
    return Run(example, approach, complete, len(story.beats), len(player.fired), ticks[0], c.resyntheses, c.ec1,
               c.ec2, c.user, c.unrealizable, violated_transitions, episodes, c.recovery_steps, failed_at,
               rs.mode is Mode.ABORTED, threshold if recovery and characterize else None, thesis,
               *(before or (None, None)), narrative=narrative)


def verdict(run: Run, figures: Mapping[str, int | bool]) -> str:
    """Compare a run with the thesis' figures: "as in the thesis", "differs: what (ours vs thesis)", or ""
    when the thesis gives none."""
    if not figures:
        return ""
    off = [f"{key} {getattr(run, key)} vs {want}" for key, want in figures.items() if getattr(run, key) != want]
    return "differs: " + ", ".join(off) if off else "as in the thesis"


def _inputs(story: Story, where: str | None, values: dict[str, bool]) -> dict[str, bool]:
    return {**{f"{r}_c": r == where for r in story.regions}, **values}


def _why(violation: AssumptionViolation) -> str:
    clauses = getattr(violation, "clauses", None) or []
    return "; ".join(getattr(c, "location", str(c)) for c in clauses) or str(violation)


def run_example(name: str, approaches: tuple[str, ...] = APPROACHES, *, say: Callable[[str], None] | None = None,
                config: Path | None = None) -> list[Run]:
    """Play one example of ``EXAMPLES`` under each approach."""
    example = EXAMPLES[name]
    config = config or package_dir() / "config"
    spec = load_spec(config / example.spec)
    story = load_story(config / example.story)
    runs = []
    for approach in approaches:
        if say is not None:
            say(f"--- {example.title}: {approach} ---")
        run = play(spec, story, approach, threshold=story.threshold, max_ticks=example.max_ticks, say=say,
                   example=name, thesis=example.thesis.get(approach))
        run.verdict = verdict(run, example.figures.get(approach, {}))
        runs.append(run)
    return runs


def resyntheses_text(run: Run) -> str:
    parts = [f"{n} x {k}" for n, k in ((run.ec1, "EC1"), (run.ec2, "EC2"), (run.user, "user")) if n]
    text = f"{run.resyntheses}" + (f" ({' + '.join(parts)})" if parts else "")
    if run.unrealizable:
        text += f", unrealizable {run.unrealizable} x"
    return text


def table(runs: list[Run]) -> str:
    """The comparison as a plain-text table."""
    head = ("example", "approach", "complete", "resyntheses", "moves while violated", "recovery steps", "thesis",
            "vs thesis")
    rows = [head]
    for r in runs:
        done = "yes" if r.complete else ("aborted" if r.aborted else
                                         f"no (stopped at {r.failed_at})" if r.failed_at else "no")
        rows.append((r.example, r.approach + (f" (>{r.threshold})" if r.threshold is not None else ""), done,
                     resyntheses_text(r), f"{r.violated_transitions} in {len(r.episodes)} episode(s)",
                     str(r.recovery_steps), r.thesis or "-", r.verdict or "-"))
    widths = [max(len(row[i]) for row in rows) for i in range(len(head))]
    lines = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    lines.insert(1, "-" * max(len(line) for line in lines))
    lines.append("Differences from the thesis and why: docs/resilience.md, \"The §4.10.4 comparison\".")
    return "\n".join(lines)


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "resilience_table", __doc__.splitlines()[0], exit_codes=(Exit.OK, Exit.BAD_INPUT),
        epilog="Examples: " + "; ".join(f"{k}: {e.title}" for k, e in EXAMPLES.items()))
    parser.add_argument("--example", action="append", choices=sorted(EXAMPLES),
                        help="only this example (repeatable; default: all)")
    parser.add_argument("--approach", action="append", choices=APPROACHES,
                        help="only this approach (repeatable; default: all four)")
    parser.add_argument("--trace", action="store_true", help="narrate each run on stderr")
    parser.add_json("the runs, with their narratives,")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return cli.run("resilience_table", lambda: _main(args))


def _main(args: argparse.Namespace) -> int:
    say = (lambda text: cli.say("resilience_table", text)) if args.trace else None
    runs: list[Run] = []
    for name in args.example or list(EXAMPLES):
        runs += run_example(name, tuple(args.approach or APPROACHES), say=say)
    if args.json:
        cli.print_json([asdict(r) for r in runs])
    else:
        print(table(runs))
    return Exit.OK


if __name__ == "__main__":
    try:
        sys.exit(main())
    except UserError as error:  # pragma: no cover - cli.run handles it
        sys.exit(error.code)
