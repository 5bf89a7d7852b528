"""Planar robot kinematics and a go-to-point controller for the simulation. ROS-free.

The robot's velocity command is given in its body frame: ``vx`` forward, ``vy`` to the left, ``wz``
counter-clockwise, as in a ``geometry_msgs/Twist`` on ``cmd_vel``. A differential-drive robot ignores
``vy``; a holonomic one uses it. ``integrate`` solves the motion exactly for a command held constant
over ``dt``: with heading ``theta(t) = theta0 + wz t`` the world velocity is ``R(theta(t)) (vx, vy)``,
whose integral is ``S (vx, vy) + C (-vy, vx)`` with ``S = (sin theta1 - sin theta0) / wz`` and
``C = (cos theta0 - cos theta1) / wz`` (and ``S = dt cos theta0``, ``C = dt sin theta0`` as wz -> 0).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

DIFF = "diff"
HOLONOMIC = "holonomic"
MODES = (DIFF, HOLONOMIC)


@dataclass(frozen=True)
class Pose2D:
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0


def wrap_angle(angle: float) -> float:
    """The same angle in (-pi, pi]."""
    wrapped = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if wrapped == -math.pi else wrapped


def clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


def limit_command(vx: float, vy: float, wz: float, mode: str, max_linear: float,
                  max_angular: float) -> tuple[float, float, float]:
    """The command the robot can follow: no sideways motion in diff mode, speeds within limits."""
    if mode not in MODES:
        raise ValueError(f"unknown drive mode {mode!r} (one of {', '.join(MODES)})")
    if mode == DIFF:
        vy = 0.0
    speed = math.hypot(vx, vy)
    if speed > max_linear > 0:
        vx, vy = vx * max_linear / speed, vy * max_linear / speed
    return vx, vy, clamp(wz, max_angular)


def integrate(pose: Pose2D, vx: float, vy: float, wz: float, dt: float) -> Pose2D:
    """Pose after holding the body-frame command (vx, vy, wz) for ``dt`` seconds (exact)."""
    th0 = pose.theta
    th1 = th0 + wz * dt
    if abs(wz * dt) < 1e-9:
        s, c = dt * math.cos(th0), dt * math.sin(th0)
    else:
        s = (math.sin(th1) - math.sin(th0)) / wz
        c = (math.cos(th0) - math.cos(th1)) / wz
    return Pose2D(pose.x + s * vx - c * vy, pose.y + c * vx + s * vy, wrap_angle(th1))


def go_to_point(pose: Pose2D, target: tuple[float, float], mode: str, max_linear: float,
                max_angular: float, k_linear: float = 1.5, k_angular: float = 3.0) -> tuple[float, float, float]:
    """A proportional command that drives ``pose`` towards ``target``.

    Diff drive turns towards the target and moves forward only as much as it faces it; holonomic
    drive moves straight at it without turning. Speeds fall linearly near the target.
    """
    dx, dy = target[0] - pose.x, target[1] - pose.y
    dist = math.hypot(dx, dy)
    if dist < 1e-9:
        return 0.0, 0.0, 0.0
    speed = min(max_linear, k_linear * dist)
    if mode == HOLONOMIC:
        wx, wy = speed * dx / dist, speed * dy / dist
        cos_t, sin_t = math.cos(pose.theta), math.sin(pose.theta)
        return cos_t * wx + sin_t * wy, -sin_t * wx + cos_t * wy, 0.0
    error = wrap_angle(math.atan2(dy, dx) - pose.theta)
    forward = speed * max(0.0, math.cos(error)) ** 2
    return forward, 0.0, clamp(k_angular * error, max_angular)


def moving_time(dt: float, now: float, command_time: float, timeout: float) -> float:
    """How much of the step (now - dt, now] a command given at ``command_time`` still drives.

    A command expires ``timeout`` seconds after it was given (``timeout <= 0``: never), and the
    robot stops then, even when the step comes late.
    """
    if timeout <= 0:
        return dt
    return max(0.0, min(dt, command_time + timeout - (now - dt)))
