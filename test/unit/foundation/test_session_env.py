"""The demo's ROS session: with a master on another host (``--master-uri``) the nodes keep the
caller's ROS_IP/ROS_HOSTNAME, since that master reaches them at the caller's address; a private
master stays on loopback."""
from __future__ import annotations

from ltl_stack.sim.session import RosSession


def test_a_remote_master_keeps_the_callers_address(monkeypatch, tmp_path):
    monkeypatch.setenv("ROS_IP", "10.232.0.7")
    monkeypatch.delenv("ROS_HOSTNAME", raising=False)
    remote = RosSession(workdir=tmp_path, port=11999, master_uri="http://10.232.0.1:11400/")
    assert remote.env["ROS_IP"] == "10.232.0.7" and "ROS_HOSTNAME" not in remote.env
    assert remote.env["ROS_MASTER_URI"] == "http://10.232.0.1:11400/" and not remote.own_master
    monkeypatch.delenv("ROS_IP")
    monkeypatch.setenv("ROS_HOSTNAME", "robot2.local")
    named = RosSession(workdir=tmp_path, port=11999, master_uri="http://10.232.0.1:11400/")
    assert named.env["ROS_HOSTNAME"] == "robot2.local" and "ROS_IP" not in named.env
    private = RosSession(workdir=tmp_path, port=11999)
    assert private.env["ROS_IP"] == "127.0.0.1" and "ROS_HOSTNAME" not in private.env
