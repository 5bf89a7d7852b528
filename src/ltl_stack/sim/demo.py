"""The README's demo: real ROS nodes of this package exchanging its messages on a private master.

Starts a rosmaster on a free port, a ``proposition_monitor`` listening for valuations, a
``timed_proposition_server`` behind an actionlib action, then publishes a valuation with
``set_propositions`` and drives the action with ``send_proposition_goal``, printing what each
node reports. Exit code 0 only when the valuation arrived and the action completed.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

from ltl_stack.sim.session import RosSession


def _wait_line(proc, timeout: float) -> str | None:
    """The next output line of ``proc`` or None when it ends or ``timeout`` passes."""
    import select

    end = time.monotonic() + timeout
    while time.monotonic() < end:
        ready, _, _ = select.select([proc.stdout], [], [], 0.1)
        if ready:
            line = proc.stdout.readline()
            return line.decode(errors="replace").rstrip() if line else None
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="tools/demo", description=__doc__.splitlines()[0])
    parser.parse_args(argv)
    with RosSession() as ros:
        print(f"[demo] private rosmaster at {ros.uri}", flush=True)
        monitor = ros.start(["rosrun", "ltl_stack", "proposition_monitor", "/demo/valuation", "--json",
                             "--count", "1"])
        ros.start(["rosrun", "ltl_stack", "timed_proposition_server", "_action:=/demo/pickup",
                   "_duration:=1.0"], stdout=open(ros.workdir / "server.log", "wb"))  # noqa: SIM115
        sender = ros.start(["rosrun", "ltl_stack", "set_propositions", "/demo/valuation",
                            "object=1,pickup=0", "--wait-subscribers", "1"])
        print(f"[demo] set_propositions: {sender.communicate(timeout=60)[0].decode().strip()}", flush=True)
        line = None
        while True:
            line = _wait_line(monitor, 30)
            if line is None or line.startswith("{"):
                break
        if line is None:
            print("[demo] FAILED: the monitor received no valuation", file=sys.stderr)
            return 1
        received = json.loads(line)
        print(f"[demo] proposition_monitor received on {received['topic']}: {received['valuation']}", flush=True)
        client = ros.start(["rosrun", "ltl_stack", "send_proposition_goal", "/demo/pickup", "--json"])
        events = []
        for raw in client.communicate(timeout=60)[0].decode().splitlines():
            if raw.startswith("{"):
                events.append(json.loads(raw))
                print(f"[demo] action /demo/pickup {events[-1]}", flush=True)
        if not events or not events[-1].get("completed"):
            print("[demo] FAILED: the action did not complete", file=sys.stderr)
            return 1
    print("[demo] done: a valuation crossed the master and a proposition action completed", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
