"""URDF kinematics with yourdfpy (no meshes): joint limits, kinematic chains and forward kinematics.

The chain forward kinematics multiplies each joint's origin by its motion (rotation about the axis for
revolute/continuous joints, translation along it for prismatic ones), as URDF defines; the unit tests
check it against yourdfpy's own scene-graph forward kinematics.
"""
from __future__ import annotations

import functools
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yourdfpy

from .errors import TransferError
from .robot_data import is_robot_data
from .urdf_tree import ACTUATED, JointInfo, UrdfTree, cached_data_tree, cached_tree, modification_time


@dataclass(frozen=True)
class ChainJoint:
    name: str
    type: str
    origin: np.ndarray      # 4x4, parent link -> joint frame
    axis: np.ndarray        # unit vector in the joint frame
    lower: float
    upper: float


@dataclass(frozen=True)
class JointKinematics:
    """What a URDF says about one joint's motion: ``<origin>`` (4x4), ``<axis>``, ``<limit>`` (or None)."""

    origin: np.ndarray | None
    axis: np.ndarray | None
    limit: tuple[float | None, float | None, float | None] | None   # lower, upper, velocity


class UrdfModel(UrdfTree):
    """A robot's tree plus joint origins, axes and limits for kinematics (from a URDF or our profile data)."""

    def __init__(self, joints: list[JointInfo], links: set[str], name: str, file: str,
                 kinematics: dict[str, JointKinematics]):
        super().__init__(joints, links, name, file)
        self.kinematics = kinematics

    def limits(self, name: str) -> tuple[float, float]:
        """Position limits of a joint; continuous joints without limits get one full turn each way."""
        j = self.joint(name)
        lower, upper, _ = self.kinematics[name].limit or (None, None, None)
        if j.type == "continuous" and (lower is None or upper is None or lower >= upper):
            return -np.pi, np.pi
        if lower is None or upper is None:
            raise TransferError("actuated joint without position limits", self.file, f"joint {name!r}")
        if lower > upper:
            raise TransferError(f"lower limit {lower} is above upper limit {upper}", self.file,
                                f"joint {name!r}")
        return float(lower), float(upper)

    def velocity_limit(self, name: str) -> float | None:
        """The joint's velocity limit (``<limit velocity=…>``, rad/s or m/s); None when absent or not positive."""
        self.joint(name)
        velocity = (self.kinematics[name].limit or (None, None, None))[2]
        return float(velocity) if velocity is not None and velocity > 0 else None

    def chain(self, base: str, tip: str) -> list[ChainJoint]:
        """The serial chain of joints (fixed ones included) from link ``base`` down to link ``tip``."""
        if base not in self.links or tip not in self.links:
            missing = base if base not in self.links else tip
            raise TransferError(f"no link {missing!r}", self.file)
        path = self.path_to(tip)
        names = [j.parent for j in path]
        if base != tip and base not in names:
            raise TransferError(f"link {tip!r} is not below link {base!r}", self.file)
        start = names.index(base) if base != tip else len(path)
        result = []
        for j in path[start:]:
            k = self.kinematics[j.name]
            lower, upper = self.limits(j.name) if j.type in ACTUATED else (0.0, 0.0)
            origin = np.array(k.origin, dtype=float) if k.origin is not None else np.eye(4)
            axis = np.array(k.axis if k.axis is not None else (1.0, 0.0, 0.0), dtype=float)
            norm = np.linalg.norm(axis)
            if j.type in ACTUATED and norm == 0:
                raise TransferError("joint axis is zero", self.file, f"joint {j.name!r}")
            result.append(ChainJoint(j.name, j.type, origin, axis / (norm or 1.0), lower, upper))
        return result


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    x, y, z = axis
    c, s = np.cos(angle), np.sin(angle)
    t = 1 - c
    return np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, t * z * z + c]])


def chain_frames(chain: list[ChainJoint], q) -> np.ndarray:
    """Positions (n+1 x 3) of the chain base and of every joint's child frame, for actuated values ``q``."""
    transform = np.eye(4)
    points = [transform[:3, 3].copy()]
    i = 0
    for joint in chain:
        transform = transform @ joint.origin
        if joint.type in ("revolute", "continuous"):
            motion = np.eye(4)
            motion[:3, :3] = _rotation(joint.axis, q[i])
            transform = transform @ motion
            i += 1
        elif joint.type == "prismatic":
            motion = np.eye(4)
            motion[:3, 3] = joint.axis * q[i]
            transform = transform @ motion
            i += 1
        points.append(transform[:3, 3].copy())
    return np.array(points)


def chain_frames_jacobian(chain: list[ChainJoint], q) -> tuple[np.ndarray, np.ndarray]:
    """Frame positions as :func:`chain_frames`, and their derivatives (n+1 x 3 x len(q)) by each value."""
    transform = np.eye(4)
    points = [transform[:3, 3].copy()]
    axes, origins, kinds, starts = [], [], [], []
    i = 0
    for joint in chain:
        transform = transform @ joint.origin
        if joint.type in ACTUATED:
            axes.append(transform[:3, :3] @ joint.axis)
            origins.append(transform[:3, 3].copy())
            kinds.append(joint.type)
            starts.append(len(points))
            motion = np.eye(4)
            if joint.type == "prismatic":
                motion[:3, 3] = joint.axis * q[i]
            else:
                motion[:3, :3] = _rotation(joint.axis, q[i])
            transform = transform @ motion
            i += 1
        points.append(transform[:3, 3].copy())
    points = np.array(points)
    jac = np.zeros((len(points), 3, len(axes)))
    for m, (axis, origin, kind, start) in enumerate(zip(axes, origins, kinds, starts)):
        if kind == "prismatic":
            jac[start:, :, m] = axis
        else:
            jac[start:, :, m] = np.cross(axis, points[start:] - origin)
    return points, jac


def actuated(chain: list[ChainJoint]) -> list[ChainJoint]:
    return [j for j in chain if j.type in ACTUATED]


@functools.lru_cache(maxsize=32)
def _load_cached(path: str, mtime: float) -> UrdfModel:
    if is_robot_data(path):
        return _from_robot_data(*cached_data_tree(path, mtime))
    text = cached_tree(path, mtime)[1]  # checked: UTF-8 text, well-formed, a consistent <robot> tree
    try:
        urdf = yourdfpy.URDF.load(io.BytesIO(text.encode("utf-8")), build_scene_graph=False, load_meshes=False,
                                  build_collision_scene_graph=False, load_collision_meshes=False)
    except Exception as err:  # yourdfpy/lxml raise many kinds for malformed files
        raise TransferError(f"not a valid URDF: {err}", path) from None
    joints = [JointInfo(j.name, j.type, j.parent, j.child) for j in urdf.robot.joints]
    kinematics = {j.name: JointKinematics(j.origin, j.axis, None if j.limit is None else
                                          (j.limit.lower, j.limit.upper, j.limit.velocity))
                  for j in urdf.robot.joints}
    return UrdfModel(joints, {link.name for link in urdf.robot.links}, urdf.robot.name, path, kinematics)


def _from_robot_data(tree: UrdfTree, data: dict) -> UrdfModel:
    """The model of our joints file; origins become matrices exactly as yourdfpy makes them from a URDF."""
    kinematics = {}
    for name, j in data["joints"].items():
        origin = None if j["xyz"] is None else yourdfpy.urdf.tra.compose_matrix(translate=np.array(j["xyz"]),
                                                                                 angles=np.array(j["rpy"]))
        axis = None if j["axis"] is None else np.array(j["axis"])
        kinematics[name] = JointKinematics(origin, axis, None if j["limit"] is None else tuple(j["limit"]))
    return UrdfModel(list(tree.joints.values()), tree.links, tree.name, tree.file, kinematics)


def load_urdf(path: str | Path) -> UrdfModel:
    """Parse a URDF or our joints file (cached per file and modification time); clear errors name the file
    and element."""
    return _load_cached(str(path), modification_time(path))
