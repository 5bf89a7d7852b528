#!/usr/bin/env python3
"""Record every Twist received on ~topic as one JSON line in ~out (for tests)."""
import json

import rospy
from geometry_msgs.msg import Twist


def main():
    rospy.init_node("twist_recorder")
    out = open(rospy.get_param("~out"), "a")  # noqa: SIM115 - open for the node's lifetime

    def record(msg):
        fields = {f"{g}.{a}": getattr(getattr(msg, g), a) for g in ("linear", "angular") for a in "xyz"}
        out.write(json.dumps(fields) + "\n")
        out.flush()

    rospy.Subscriber(rospy.get_param("~topic"), Twist, record, queue_size=100)
    rospy.loginfo("recording")
    rospy.spin()


if __name__ == "__main__":
    main()
