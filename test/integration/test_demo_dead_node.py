"""The demo reports a scenario node that died, naming it, and exits 1 at once instead of waiting out
its --timeout. The story node of thesis Example 11 is given a story whose user liveness
does not parse: it ends with one [FATAL] line (exit 2) right after it starts."""
from __future__ import annotations

import subprocess
import sys

import pytest
from helpers import REPO_ROOT

from ltl_stack.errors import Exit

pytestmark = pytest.mark.ros

STORY = (REPO_ROOT / "config" / "alice" / "story.yaml").read_text()


def test_a_dead_story_node_ends_the_demo_naming_it(tmp_path):
    story = tmp_path / "story.yaml"
    assert 'user: "doorOpen | doorBroken"' in STORY
    story.write_text(STORY.replace('user: "doorOpen | doorBroken"', 'user: "doorOpen |"'))
    timeout = 240  # the story would never complete: only the node's death ends the run before this
    proc = subprocess.run([sys.executable, "-m", "ltl_stack.sim.demo", "--scenario", "alice_ec",
                           "--launch-arg", f"story:={story}", "--timeout", str(timeout)],
                          capture_output=True, text=True, timeout=timeout + 120, cwd=REPO_ROOT)
    assert proc.returncode == Exit.NEGATIVE, proc.stdout[-2000:] + proc.stderr[-3000:]
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("demo: error: node alice/story died (exit code 2) after "), proc.stderr[-3000:]
    assert "'user': 'doorOpen |' does not parse" in proc.stderr, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr
