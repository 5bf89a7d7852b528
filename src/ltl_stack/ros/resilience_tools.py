"""``add_env_liveness``: give a running controller executor an environment liveness assumption, or abort it.

    rosrun ltl_stack add_env_liveness "doorOpen | doorBroken"       # thesis Alg. 3 line 6
    rosrun ltl_stack add_env_liveness --node /alice/controller_executor --abort

Calls the executor's ``~add_env_liveness`` (``ltl_stack/AddEnvLiveness``) or ``~abort``
(``std_srvs/Trigger``) service (docs/resilience.md). The exit code is the executor's verdict from the
one table (``ltl_stack.errors.Exit``): 0 realizable and running (or aborted), 1 not done
(characterization off, not ready, not waiting for the user, a resynthesis running, already aborted,
also ``--abort`` on an aborted node), 2 a formula the executor refused
(its message names the column and proposition; nothing changed) or bad arguments, 3 no master or no
such executor within ``--timeout``, 10 still unrealizable (the executor aborted: every output false).
"""
from __future__ import annotations

import sys

import rospy
from std_srvs.srv import Trigger

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.ros.master import init_node, master_uri, ros_name, wait_for_master
from ltl_stack.ros.proposition_tools import add_master_options
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.srv import AddEnvLiveness

PROG = "add_env_liveness"


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        PROG, "Add an environment liveness assumption to a running controller executor (thesis Alg. 3 line 6: "
              "after environment characterization found no realizable specification), or abort it.",
        exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT, Exit.NO_ROS, Exit.UNREALIZABLE),
        epilog="The formula is in the structured syntax over the spec's propositions (current inputs and "
               "outputs, next inputs primed), e.g. 'doorOpen | doorBroken' or '!spill'. --abort drives every "
               "output false; the executor stays up and reports ERROR on /diagnostics.")
    parser.add_argument("formula", nargs="?", help="the environment liveness formula (one, quoted)")
    parser.add_argument("--abort", action="store_true", help="abort the execution instead (every output false)")
    parser.add_argument("--node", type=ros_name, default="controller_executor",
                        help="the executor node (default: %(default)s, relative to the namespace)")
    add_master_options(parser, what="the master and the executor's service")
    parser.add_json("the executor's answer")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    return cli.run(PROG, lambda: _call(args))


def _call(args) -> int:
    if args.abort == (args.formula is not None):
        raise UserError("give either a formula or --abort (not both, not neither)")
    if args.formula is not None and not args.formula.strip():
        raise UserError("the formula is empty; write one like: doorOpen | doorBroken")
    wait_for_master(master_uri(args.master_uri), args.timeout)
    init_node(PROG, anonymous=True, disable_signals=True)
    node = rospy.resolve_name(args.node)
    service = node + ("/abort" if args.abort else "/add_env_liveness")
    try:
        rospy.wait_for_service(service, args.timeout)
    except rospy.ROSException:
        raise UserError(f"no service {service} after {args.timeout:g} s: is the executor {node} running "
                        "(rosnode list)?", Exit.NO_ROS) from None
    try:
        if args.abort:
            answer = rospy.ServiceProxy(service, Trigger)()
            code, mode = (Exit.OK if answer.success else Exit.NEGATIVE), Mode.ABORTED.value
        else:
            answer = rospy.ServiceProxy(service, AddEnvLiveness)(args.formula)
            code, mode = Exit(answer.code) if answer.code in set(Exit) else Exit.NEGATIVE, answer.mode
    except rospy.ServiceException as err:
        raise UserError(f"{service}: the call failed: {err}", Exit.NO_ROS) from None
    if args.json:
        cli.print_json({"node": node, "service": service, "success": bool(answer.success), "mode": mode,
                        "message": answer.message, "code": int(code)})
    elif answer.success:
        print(f"{node}: {answer.message}", flush=True)
    else:
        cli.error(PROG, f"{node}: {answer.message}")
    return code


__all__ = ["build_parser", "main"]

