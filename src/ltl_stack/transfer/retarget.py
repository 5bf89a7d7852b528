"""B.3: retarget joint trajectories from one arm to another (thesis §2.5.2, after its reference [81]).

Both kinematic chains come from the URDFs. Points are spaced evenly by arc length along each chain;
for every trajectory point the target joint angles minimise

    J(q) = |e_t(q) - e_s|^2 / L_s^2  +  w * mean_k |p_t,k(q) / L_t - p_s,k / L_s|^2

(end-effector distance, plus the shape distance of the length-normalised chains), within the target's
joint limits (``scipy.optimize.minimize``, L-BFGS-B). The weight w is chosen automatically by
continuation: it starts at 1 (shape matters as much as the end effector) and is divided by ten,
warm-starting each time, until the end effector is within ``EE_TOLERANCE``, or until a lower weight
no longer brings the end effector ``MIN_GAIN`` closer (a smaller target cannot reach, so the shape is
kept) — and never below ``W_MIN``, so the shape term cannot vanish. Successive trajectory points warm-start from the previous
solution, so the motion stays continuous.

Target chain rule: the source's own joints when the target has them all; otherwise the SRDF's
serial-chain groups (those ending at an SRDF end effector first, then the most actuated joints, then
the name most like "arm"); without an SRDF, the longest root-to-leaf chain of the URDF.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from .commands import JointTrajectoryUse
from .errors import TransferError
from .profiles import RobotProfile
from .report import ParameterChange, TransferReport, Unresolved
from .rewrite import Edit
from .source_ast import SourceFile, format_angle, format_list, format_string
from .srdf import load_srdf, similarity
from .urdf import ChainJoint, UrdfModel, actuated, chain_frames, chain_frames_jacobian, load_urdf

SAMPLES = 12
EE_TOLERANCE = 0.002   # metres
WEIGHTS = (1.0, 0.1, 0.01)
W_MIN = WEIGHTS[-1]
MIN_GAIN = 0.1         # a lower weight must bring the end effector at least 10 % closer
TOOL_NAMES = ("ee_link", "tool0", "end_effector", "tool")


@dataclass
class Chain:
    """A serial chain with its sampling along arc length precomputed."""

    joints: list[ChainJoint]
    base: str
    tip: str

    def __post_init__(self):
        self.moving = actuated(self.joints)
        self.bounds = [(j.lower, j.upper) for j in self.moving]
        rest = chain_frames(self.joints, np.zeros(len(self.moving)))
        seg = np.linalg.norm(np.diff(rest, axis=0), axis=1)   # constant: links are rigid
        self.length = float(seg.sum())
        if self.length <= 0:
            raise TransferError(f"the chain {self.base} -> {self.tip} has zero length")
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        targets = np.linspace(0.0, self.length, SAMPLES)
        self._index = np.clip(np.searchsorted(cum, targets, side="right") - 1, 0, len(seg) - 1)
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = (targets - cum[self._index]) / seg[self._index]
        self._frac = np.nan_to_num(frac, nan=0.0)[:, None]

    def sample(self, q) -> tuple[np.ndarray, np.ndarray]:
        """(samples K x 3, end-effector position) for joint values ``q``."""
        frames = chain_frames(self.joints, q)
        a, b = frames[self._index], frames[self._index + 1]
        return a + self._frac * (b - a), frames[-1]

    def sample_jacobian(self, q):
        """Samples and end effector as :meth:`sample`, with their derivatives by the joint values."""
        frames, jac = chain_frames_jacobian(self.joints, q)
        a, b = frames[self._index], frames[self._index + 1]
        ja, jb = jac[self._index], jac[self._index + 1]
        frac = self._frac[:, :, None]
        return a + self._frac * (b - a), frames[-1], ja + frac * (jb - ja), jac[-1]

    @property
    def names(self) -> list[str]:
        return [j.name for j in self.moving]


def _extend_to_tool(urdf: UrdfModel, tip: str) -> str:
    """Follow fixed joints below the last moving link to the tool frame, when that is unambiguous."""
    while True:
        fixed = [j for j in urdf.children.get(tip, []) if j.type == "fixed"]
        if len(fixed) == 1 and not urdf.children.get(fixed[0].child):
            return fixed[0].child
        for name in TOOL_NAMES:
            match = [j for j in fixed if name in j.child]
            if match:
                return match[0].child
        return tip


def source_chain(urdf: UrdfModel, joint_names: list[str]) -> Chain:
    """The chain that the program's joints lie on, from the first one's parent to the tool frame."""
    missing = [n for n in joint_names if not urdf.has_joint(n)]
    if missing:
        raise TransferError(f"joints {missing} of the program are not in the source URDF", urdf.file)
    tip = urdf.deepest_child(joint_names)
    path = [j.name for j in urdf.path_to(tip)]
    first = min(joint_names, key=path.index)
    base = urdf.joint(first).parent
    tip = _extend_to_tool(urdf, tip)
    return Chain(urdf.chain(base, tip), base, tip)


def _chain_from_joints(urdf: UrdfModel, names: list[str], tool: bool = True) -> Chain | None:
    try:
        tip = urdf.deepest_child(names)
    except TransferError:
        return None
    path = [j.name for j in urdf.path_to(tip)]
    base = urdf.joint(min(names, key=path.index)).parent
    return Chain(urdf.chain(base, _extend_to_tool(urdf, tip) if tool else tip), base, tip)


def target_chain(urdf: UrdfModel, srdf, source_joints: list[str], group: str | None = None) -> tuple[Chain, str]:
    """The target chain and the rule that chose it (see the module docstring); with ``group`` (joints
    commanded through a MoveIt group), that SRDF group's single chain."""
    if group is not None and srdf is not None and group in srdf.groups:
        chains = srdf.all_chains(group)
        if len(chains) == 1:
            base, tip = chains[0]
            return Chain(urdf.chain(base, tip), base, tip), f"the MoveIt group '{group}' the program commands"
    if all(urdf.has_joint(n) for n in source_joints):
        chain = _chain_from_joints(urdf, source_joints)
        if chain is not None:
            return chain, "the target has the program's joints"
    if srdf is not None:
        eef_links = {e.parent_link for e in srdf.end_effectors}
        options = []
        for name in srdf.groups:
            chains = srdf.all_chains(name)
            chain = None
            if len(chains) == 1 and not srdf.all_joints(name):
                base, tip = chains[0]
                chain = Chain(urdf.chain(base, tip), base, tip)
            elif not chains and srdf.all_joints(name):
                joints = [j for j in srdf.all_joints(name) if urdf.has_joint(j)]
                chain = _chain_from_joints(urdf, joints, tool=False) if joints else None
            if chain is not None and len(chain.moving) >= 2:
                options.append((chain.tip in eef_links, len(chain.moving), similarity("arm", name), name, chain))
        if options:
            options.sort(key=lambda o: (not o[0], -o[1], -o[2], o[3]))
            best = options[0]
            return best[4], (f"SRDF group '{best[3]}' ({best[1]} joints"
                             + (", ends at an SRDF end effector" if best[0] else "") + "), chosen among "
                             + ", ".join(f"'{o[3]}'" for o in options))
    best = None
    for path in urdf.leaf_chains():
        moving = [j.name for j in path if j.type in ("revolute", "continuous", "prismatic")]
        if len(moving) >= 2 and (best is None or len(moving) > len(best)):
            best = moving
    if best is None:
        raise TransferError("the target URDF has no chain of two or more moving joints", urdf.file)
    return _chain_from_joints(urdf, best, tool=False), "the longest chain of the target URDF (no SRDF)"


@dataclass
class PointResult:
    q: np.ndarray
    ee_error: float
    shape: float
    weight: float


def _terms(source: Chain, target: Chain, q_s: np.ndarray):
    """(ee, shape, d_ee, d_shape) of the objective at q, for the source configuration ``q_s``."""
    samples_s, ee_s = source.sample(q_s)
    shape_s = samples_s / source.length

    def terms(q):
        samples_t, ee_t, d_samples, d_ee_t = target.sample_jacobian(q)
        ee_diff = (ee_t - ee_s) / source.length
        shape_diff = samples_t / target.length - shape_s
        ee = float(ee_diff @ ee_diff)
        shape = float(np.mean(np.sum(shape_diff ** 2, axis=1)))
        d_ee = 2 * ee_diff @ d_ee_t / source.length
        d_shape = 2 / len(shape_diff) * np.einsum("kc,kcn->n", shape_diff, d_samples) / target.length
        return ee, shape, d_ee, d_shape

    return terms


def retarget_points(source: Chain, target: Chain, points: list[np.ndarray], progress=None) -> list[PointResult]:
    """Target joint values for each source configuration, warm-starting each from the previous one."""
    lo = np.array([b[0] for b in target.bounds])
    hi = np.array([b[1] for b in target.bounds])
    results: list[PointResult] = []
    previous = None
    for number, q_s in enumerate(points, 1):
        terms = _terms(source, target, q_s)

        def objective(q, w, terms=terms):
            ee, shape, d_ee, d_shape = terms(q)
            return ee + w * shape, d_ee + w * d_shape

        def solve(start, w, objective=objective):
            res = minimize(objective, start, args=(w,), jac=True, method="SLSQP", bounds=target.bounds,
                           options={"maxiter": 500, "ftol": 1e-14})
            return np.clip(res.x, lo, hi)

        if previous is None:
            starts = [np.clip(np.zeros(len(lo)), lo, hi), (lo + hi) / 2]
            if len(q_s) == len(lo):
                starts.insert(0, np.clip(q_s, lo, hi))
            candidates = [solve(s, WEIGHTS[0]) for s in starts]
            current = min(candidates, key=lambda q: objective(q, WEIGHTS[0])[0])
        elif len(q_s) == len(lo):
            # same joint count: the source's own angles compete with the warm start, so one far-off
            # point (an arm lowered after waving) does not stay in the previous point's basin
            candidates = [solve(previous, WEIGHTS[0]), solve(np.clip(q_s, lo, hi), WEIGHTS[0])]
            current = min(candidates, key=lambda q: objective(q, WEIGHTS[0])[0])
        else:
            current = previous
        best = None
        for w in WEIGHTS:
            q = solve(best.q if best else current, w)
            ee, shape, _, _ = terms(q)
            result = PointResult(q, float(np.sqrt(ee)) * source.length, shape, w)
            if best is not None and result.ee_error > (1 - MIN_GAIN) * best.ee_error:
                break  # giving up shape no longer brings the end effector closer: keep the better shape
            best = result
            if best.ee_error <= EE_TOLERANCE:
                break
        if progress:
            progress(f"point {number}/{len(points)}: end-effector error {best.ee_error * 1000:.1f} mm")
        results.append(best)
        previous = best.q
    return results


def transfer_joint_commands(src: SourceFile, use: JointTrajectoryUse, source: RobotProfile,
                            target: RobotProfile, report: TransferReport, edits: list[Edit],
                            progress=None, group: str | None = None) -> None:
    """B.3 on the program's JointTrajectory: new joint names and positions, and the report's figures.
    ``group``: the target MoveIt group the joints are commanded through (its chain is the target chain)."""
    if not use.names:
        report.unresolved.append(Unresolved("positions", use.points[0].line,
                                            "joint positions without joint names; cannot tell which joints"))
        return
    names = use.names[0].values
    if any(n.values != names for n in use.names):
        report.unresolved.append(Unresolved("joint_names", use.names[1].line,
                                            "the program commands different joint lists; only the first is "
                                            "retargeted"))
    if source.urdf is None and target.urdf is not None:
        target_urdf = load_urdf(target.urdf)
        if all(target_urdf.has_joint(n) for n in names):
            _check_joint_limits(src, use, names, target_urdf, target, report, edits)
            return
    if source.urdf is None or target.urdf is None:
        which = source.name if source.urdf is None else target.name
        report.unresolved.append(Unresolved("joint trajectory", use.names[0].line,
                                            f"B.3 needs both URDFs; {which} has none"))
        return
    source_urdf, target_urdf = load_urdf(source.urdf), load_urdf(target.urdf)
    srdf = None
    if target.srdf is not None:
        srdf = load_srdf(target.srdf)
    chain_s = source_chain(source_urdf, names)
    chain_t, rule = target_chain(target_urdf, srdf, names, group)
    index = {n: i for i, n in enumerate(names)}
    ignored = [n for n in names if n not in chain_s.names]
    if ignored:
        report.unresolved.append(Unresolved("joint_names", use.names[0].line,
                                            f"joints {ignored} are not on the arm's chain; dropped"))
    held = [n for n in chain_s.names if n not in index]
    if held:
        report.notes.append(f"source joints {held} are on the chain but not commanded; taken as 0")
    good_points = []
    for point in use.points:
        if len(point.values) != len(names):
            report.unresolved.append(Unresolved("positions", point.line,
                                                f"{len(point.values)} positions for {len(names)} joints"))
            continue
        good_points.append(point)
    q_source = [np.array([p.values[index[n]] if n in index else 0.0 for n in chain_s.names]) for p in good_points]
    if progress:
        progress(f"retargeting {len(q_source)} trajectory point(s): {len(chain_s.names)} -> "
                 f"{len(chain_t.names)} joints")
    results = retarget_points(chain_s, chain_t, q_source, progress)
    for joint_list in use.names:
        text = src.data[joint_list.span.start:joint_list.span.end].decode("utf-8")
        quote = next((e for e in ("'", '"') if e in text), "'")
        new = format_list([format_string(n, quote) for n in chain_t.names], text)
        edits.append(Edit(joint_list.span, new))
        report.parameters.append(ParameterChange(
            "joint_names" + (f" (variable {joint_list.via})" if joint_list.via else ""), joint_list.line,
            text, new, "B.3 retargeted chain"))
    for point, result in zip(good_points, results):
        text = src.data[point.span.start:point.span.end].decode("utf-8")
        new = format_list([format_angle(v) for v in result.q], text)
        within = all(lo - 1e-9 <= v <= hi + 1e-9 for v, (lo, hi) in zip(result.q, chain_t.bounds))
        edits.append(Edit(point.span, new))
        report.parameters.append(ParameterChange(
            "positions" + (f" (variable {point.via})" if point.via else ""), point.line, text, new,
            "B.3 retargeted", within, f"end-effector error {result.ee_error * 1000:.1f} mm"))
    _scale_rates(src, use, names, chain_s, chain_t, source_urdf, target_urdf, target, report, edits)
    for span, kind, line in use.zero_lists:
        text = src.data[span.start:span.end].decode("utf-8")
        new = f"[0] * {len(chain_t.names)}" if "*" in text else "[" + ", ".join(["0"] * len(chain_t.names)) + "]"
        if new.replace(" ", "") != text.replace(" ", ""):
            edits.append(Edit(span, new))
            report.parameters.append(ParameterChange(kind, line, text, new, "B.3 resized to the target's joints"))
    report.retargeting = {
        "source_joints": chain_s.names, "source_tip": chain_s.tip, "source_length_m": round(chain_s.length, 4),
        "target_joints": chain_t.names, "target_tip": chain_t.tip, "target_length_m": round(chain_t.length, 4),
        "target_rule": rule,
        "points": [{"line": p.line, "source": list(p.values), "target": [round(float(v), 4) for v in r.q],
                    "ee_error_m": round(r.ee_error, 5), "shape_distance": round(r.shape, 5), "weight": r.weight}
                   for p, r in zip(good_points, results)]}
    far = [i + 1 for i, r in enumerate(results) if r.ee_error > 10 * EE_TOLERANCE]
    if far:
        report.notes.append(f"trajectory point(s) {far}: the target's end effector cannot get within "
                            f"{10 * EE_TOLERANCE * 1000:.0f} mm of the source's (see the errors above)")


def joint_correspondence(source: Chain, target: Chain) -> tuple[list[int], str]:
    """For each target joint, the source joint whose motion it takes over: the same joint when the
    names match, else the source joint at the same relative place from base to tip (first <- first,
    last <- last, the ones between spread evenly)."""
    if target.names == source.names:
        return list(range(len(source.names))), "the same joints"
    n_s, n_t = len(source.names), len(target.names)
    match = [int(np.floor(j * (n_s - 1) / max(n_t - 1, 1) + 0.5)) for j in range(n_t)]
    return match, "the source joint at the same relative place from base to tip"


def _rate_text(values: list[float]) -> list[str]:
    return [format_angle(v) for v in values]


def _scale_rates(src: SourceFile, use: JointTrajectoryUse, names: list[str], chain_s: Chain, chain_t: Chain,
                 source_urdf: UrdfModel, target_urdf: UrdfModel, target: RobotProfile, report: TransferReport,
                 edits: list[Edit]) -> None:
    """B.2 for joint rates: each target joint's velocity is its source joint's velocity scaled from the
    source joint's velocity limit to the target joint's (Eqs. 2.1/2.2 with limits ±v_max, no deadband);
    accelerations take the same factor, so the motion keeps its timing (v_t = r v_s gives a_t = r a_s)."""
    if not use.rates:
        return
    match, rule = joint_correspondence(chain_s, chain_t)
    index = {n: i for i, n in enumerate(names)}
    limits_s = [source_urdf.velocity_limit(n) for n in chain_s.names]
    limits_t = [target_urdf.velocity_limit(n) for n in chain_t.names]
    missing = [n for n, v in zip(chain_s.names, limits_s) if v is None] + \
              [n for n, v in zip(chain_t.names, limits_t) if v is None]
    for kind, rates in use.rates:
        text = src.data[rates.span.start:rates.span.end].decode("utf-8")
        if len(rates.values) != len(names):
            report.unresolved.append(Unresolved(kind, rates.line, f"{len(rates.values)} {kind} for {len(names)} "
                                                                  "joints"))
            continue
        if missing:
            report.unresolved.append(Unresolved(kind, rates.line, f"no velocity limit in the URDF for joint(s) "
                                                                  f"{missing}; cannot scale {text}"))
            continue
        per_source = [rates.values[index[n]] if n in index else 0.0 for n in chain_s.names]
        new_values, clamped = [], []
        for j, i in enumerate(match):
            ratio = limits_t[j] / limits_s[i]
            value = per_source[i] * ratio
            if kind == "velocities" and abs(value) > limits_t[j]:
                clamped.append(chain_t.names[j])
                value = float(np.clip(value, -limits_t[j], limits_t[j]))
            new_values.append(value)
        new = format_list(_rate_text(new_values), text)
        note = f"v_max ratio per target joint ({rule}): " + ", ".join(
            f"{chain_t.names[j]} <- {chain_s.names[i]} x{limits_t[j] / limits_s[i]:.3g}" for j, i in enumerate(match))
        if clamped:
            note += f"; clamped to the velocity limits of {clamped}"
        edits.append(Edit(rates.span, new))
        report.parameters.append(ParameterChange(kind + (f" (variable {rates.via})" if rates.via else ""),
                                                 rates.line, text, new, "B.2 scaled (joint velocity limits)",
                                                 True, note))


def _check_joint_limits(src: SourceFile, use: JointTrajectoryUse, names: list[str], urdf: UrdfModel,
                        target: RobotProfile, report: TransferReport, edits: list[Edit]) -> None:
    """B.1 only (no source URDF, same joint names on the target): clamp positions into the limits."""
    report.notes.append(f"no source URDF: joint positions only checked against {target.name}'s limits (B.1)")
    for point in use.points:
        if len(point.values) != len(names):
            report.unresolved.append(Unresolved("positions", point.line,
                                                f"{len(point.values)} positions for {len(names)} joints"))
            continue
        clamped, outside = [], []
        for name, value in zip(names, point.values):
            lower, upper = urdf.limits(name)
            clamped.append(min(max(value, lower), upper))
            if clamped[-1] != value:
                outside.append(f"{name} {value:g} outside [{lower:g}, {upper:g}]")
        text = src.data[point.span.start:point.span.end].decode("utf-8")
        if outside:
            new = format_list([format_angle(v) for v in clamped], text)
            edits.append(Edit(point.span, new))
            report.parameters.append(ParameterChange("positions", point.line, text, new, "B.1 clamped",
                                                     True, "; ".join(outside)))
        else:
            report.parameters.append(ParameterChange("positions", point.line, text, text, "B.1 checked"))
    for kind, rates in use.rates:
        if kind != "velocities" or len(rates.values) != len(names):
            continue  # accelerations have no URDF limit to check against
        text = src.data[rates.span.start:rates.span.end].decode("utf-8")
        vmax = [urdf.velocity_limit(n) for n in names]
        clamped = [v if m is None else float(np.clip(v, -m, m)) for v, m in zip(rates.values, vmax)]
        if clamped != rates.values:
            new = format_list(_rate_text(clamped), text)
            edits.append(Edit(rates.span, new))
            report.parameters.append(ParameterChange(kind, rates.line, text, new, "B.1 clamped", True,
                                                     "clamped to the target's joint velocity limits"))
        else:
            report.parameters.append(ParameterChange(kind, rates.line, text, text, "B.1 checked"))
