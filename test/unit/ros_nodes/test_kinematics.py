"""Planar kinematics and the go-to-point controller of the simulation (ROS-free)."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.sim.kinematics import (
    DIFF,
    HOLONOMIC,
    Pose2D,
    go_to_point,
    integrate,
    limit_command,
    wrap_angle,
)

speeds = st.floats(-2, 2)
turns = st.floats(-3, 3)


def close(a: Pose2D, b: Pose2D, tol: float = 1e-6) -> bool:
    return (abs(a.x - b.x) < tol and abs(a.y - b.y) < tol
            and abs(wrap_angle(a.theta - b.theta)) < tol)


def test_straight_line_and_quarter_circle_by_hand():
    assert close(integrate(Pose2D(1, 2, math.pi / 2), 0.5, 0, 0, 2.0), Pose2D(1, 3, math.pi / 2))
    # v = 1, w = pi/2 for 1 s: a quarter of the circle of radius 2/pi centred at (0, 2/pi).
    r = 2 / math.pi
    assert close(integrate(Pose2D(), 1.0, 0.0, math.pi / 2, 1.0), Pose2D(r, r, math.pi / 2))
    # Holonomic sideways motion while facing +y moves along -x.
    assert close(integrate(Pose2D(0, 0, math.pi / 2), 0.0, 1.0, 0.0, 1.0), Pose2D(-1, 0, math.pi / 2))


@given(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi), speeds, speeds, turns,
       st.floats(0, 1), st.floats(0, 1))
def test_integrating_in_two_steps_equals_one_step(x, y, th, vx, vy, wz, dt1, dt2):
    pose = Pose2D(x, y, th)
    two = integrate(integrate(pose, vx, vy, wz, dt1), vx, vy, wz, dt2)
    assert close(two, integrate(pose, vx, vy, wz, dt1 + dt2), 1e-6), two


@given(speeds, speeds, turns, st.floats(0.1, 3), st.floats(0.1, 3))
def test_limit_command(vx, vy, wz, max_linear, max_angular):
    lx, ly, lw = limit_command(vx, vy, wz, DIFF, max_linear, max_angular)
    assert ly == 0.0 and abs(lx) <= max_linear + 1e-12 and abs(lw) <= max_angular + 1e-12
    hx, hy, hw = limit_command(vx, vy, wz, HOLONOMIC, max_linear, max_angular)
    assert math.hypot(hx, hy) <= max_linear + 1e-9
    if math.hypot(vx, vy) > 1e-9:  # the direction is kept
        assert abs(hx * vy - hy * vx) < 1e-9


def test_unknown_mode_is_rejected():
    with pytest.raises(ValueError, match="unknown drive mode 'tank'"):
        limit_command(1, 0, 0, "tank", 1, 1)


@settings(max_examples=50, deadline=None)
@given(st.sampled_from([DIFF, HOLONOMIC]), st.floats(-3, 3), st.floats(-3, 3), st.floats(-math.pi, math.pi),
       st.floats(-3, 3), st.floats(-3, 3))
def test_go_to_point_reaches_any_target(mode, x, y, th, tx, ty):
    pose, dt = Pose2D(x, y, th), 0.05
    for _ in range(2000):
        if math.hypot(tx - pose.x, ty - pose.y) < 0.05:
            break
        cmd = limit_command(*go_to_point(pose, (tx, ty), mode, 0.5, 1.5), mode, 0.5, 1.5)
        pose = integrate(pose, *cmd, dt)
    assert math.hypot(tx - pose.x, ty - pose.y) < 0.05, (pose, tx, ty)


def test_moving_time_stops_at_the_command_timeout_even_for_late_steps():
    from ltl_stack.sim.kinematics import moving_time

    assert moving_time(0.1, now=10.0, command_time=9.95, timeout=0.5) == 0.1
    assert moving_time(1.0, now=10.0, command_time=9.0, timeout=0.3) == pytest.approx(0.3)  # late step
    assert moving_time(0.1, now=10.0, command_time=5.0, timeout=0.5) == 0.0
    assert moving_time(0.1, now=10.0, command_time=0.0, timeout=0.0) == 0.1  # no timeout
