"""Shared fixtures. Test file names must be unique across test/ (pytest's default import mode)."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from helpers import RosMaster  # noqa: E402


@pytest.fixture
def ros_master(tmp_path, monkeypatch):
    """A real rosmaster on a free loopback port; ROS_MASTER_URI points at it during the test.

    Every process started with ``ros_master.run(...)`` is stopped afterwards, even when the test fails.
    """
    master = RosMaster(tmp_path)
    for key in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME"):
        monkeypatch.setenv(key, master.env[key])
    monkeypatch.delenv("ROS_HOSTNAME", raising=False)
    try:
        yield master
    finally:
        master.shutdown()
