"""What a node of ours imports at start-up (issue 16): genpy's optional numpy import is skipped (~80 ms
CPU per node), while numpy stays importable afterwards and numpy floats still go into float fields."""
from __future__ import annotations

import subprocess
import sys

CODE = """
import sys
import ltl_stack.ros.executor
print('numpy' in sys.modules)
import io
import numpy
from std_msgs.msg import Float64
buf = io.BytesIO()
Float64(numpy.float64(1.5)).serialize(buf)
msg = Float64()
msg.deserialize(buf.getvalue())
print(msg.data, numpy.__name__)
"""


def test_executor_start_up_does_not_import_numpy_which_stays_usable():
    proc = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "1.5", "numpy"], proc.stdout
