"""A node that calls another robot's ``~negotiate`` with the messages given as JSON lines on the
command line, and prints each reply as one JSON line ``{"reply": …}``, then ``{"done": true}``:
``python negotiation_rogue.py SERVICE MESSAGE_JSON...`` (its node name and namespace come from
``__name:=`` / ``__ns:=``, so it can pose as a peer)."""
from __future__ import annotations

import json
import sys

import rospy

from ltl_stack.ros.negotiation import from_ros, to_ros
from ltl_stack.runtime.resilience.negotiation import Message
from ltl_stack.srv import Negotiate


def main() -> int:
    args = rospy.myargv(sys.argv)[1:]
    rospy.init_node("rogue", disable_signals=True)
    service = args[0]
    rospy.wait_for_service(service, timeout=60)
    call = rospy.ServiceProxy(service, Negotiate)
    for raw in args[1:]:
        data = json.loads(raw)
        if "repeat" in data:  # a large text without a large command line
            data["text"] = data.pop("head", "") + data["repeat"] * int(data.pop("times"))
            del data["repeat"]
        reply = from_ros(call(to_ros(Message.from_dict(data))))
        print(json.dumps({"reply": reply.to_dict()}), flush=True)
    print(json.dumps({"done": True}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
