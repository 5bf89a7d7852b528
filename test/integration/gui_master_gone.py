"""Helper of test_gui_view_truth (not a test): a controller view, offscreen, in a process of its own
(rospy binds a process to one master, and this one's master is killed). Attaches to STATE_TOPIC, says
"attached", waits for the master to go away (the test kills it), prints what the view shows as one
JSON line and exits 0 when it shows the executor as not heard from, 1 otherwise."""
from __future__ import annotations

import json
import os
import sys
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")


def main(state_topic: str, timeout: float = 90.0) -> int:
    from python_qt_binding.QtWidgets import QApplication

    from ltl_stack.gui.controller_view import ControllerView

    app = QApplication([])
    view = ControllerView()

    def wait(condition) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            app.processEvents()
            if condition():
                return True
            time.sleep(0.02)
        return False
    view.topic_combo_box.setEditText(state_topic)
    view.attach_push_button.click()
    if not wait(lambda: view.model is not None and view.alive and view.run_pause_push_button.isEnabled()):
        print(json.dumps({"error": "not attached", "status": view.status_label.text()}), flush=True)
        return 1
    print("attached", flush=True)
    sys.stdin.readline()  # the test killed the master
    greyed = wait(lambda: not view.alive)
    print(json.dumps({"alive": view.alive, "pause_enabled": view.run_pause_push_button.isEnabled(),
                      "liveness": view.liveness_label.text(), "mode": view.mode_label.text(),
                      "opacity": view.graph_opacity.opacity()}), flush=True)
    view.shutdown()
    return 0 if greyed else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
