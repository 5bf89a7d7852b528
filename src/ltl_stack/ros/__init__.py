"""ROS adapters: executor node, proposition nodes, graph snapshots, transports.

Start-up (issue 16): ``genpy.message``, which every message class and ``rospy`` import, tries
``import numpy`` only to list numpy's scalar types among the values a float field accepts when it
words a serialization error; with the venv's numpy that import costs ~80 ms CPU in every node, and
none of our nodes puts numpy values into messages. So numpy is marked absent while genpy is first
imported here (a ``None`` entry in ``sys.modules`` makes an import fail, documented behaviour, and
genpy catches the ImportError) and the mark is taken out right after: a later ``import numpy``
works as usual, and ``struct`` still packs numpy floats into float fields.
"""
from __future__ import annotations

import sys

_HIDE_NUMPY = "numpy" not in sys.modules and "genpy.message" not in sys.modules
if _HIDE_NUMPY:
    sys.modules["numpy"] = None  # type: ignore[assignment]
try:
    import genpy.message  # noqa: F401 - imported here, before rospy, for the reason above
except ImportError:
    pass  # no ROS here: nothing to speed up (the ROS-free parts of ltl_stack.sim import this package)
finally:
    if _HIDE_NUMPY and sys.modules.get("numpy", False) is None:
        del sys.modules["numpy"]
