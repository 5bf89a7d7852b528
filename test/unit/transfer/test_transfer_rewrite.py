"""Invariants of the rewriting: bytes outside the edits never change; every command becomes its scaled value."""
import ast

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ltl_stack.transfer.limits import AxisLimit, VelocityLimits, scale_command
from ltl_stack.transfer.profiles import RobotProfile
from ltl_stack.transfer.rewrite import Edit, apply_edits
from ltl_stack.transfer.source_ast import Span
from ltl_stack.transfer.transfer import transfer_program


@st.composite
def data_and_edits(draw):
    data = draw(st.binary(min_size=1, max_size=200))
    cuts = sorted(draw(st.sets(st.integers(0, len(data)), min_size=0, max_size=8)))
    pairs = list(zip(cuts[::2], cuts[1::2]))
    edits = [Edit(Span(a, b, 1), draw(st.text(max_size=5))) for a, b in pairs]
    return data, edits


@settings(suppress_health_check=[HealthCheck.too_slow])  # a busy machine draws slowly
@given(data_and_edits())
def test_bytes_outside_the_edits_are_kept(case):
    data, edits = case
    out = apply_edits(data, edits)
    pos, rebuilt = 0, b""
    for edit in sorted(edits, key=lambda e: e.span.start):
        rebuilt += data[pos:edit.span.start] + edit.text.encode()
        pos = edit.span.end
    assert out == rebuilt + data[pos:]


def robot(name, x, z):
    limits = VelocityLimits({"linear.x": x, "angular.z": z})
    return RobotProfile(name, "differential", limits)


SOURCE = robot("a", AxisLimit(-2.0, 3.0, 0.1), AxisLimit(-4.0, 4.0))
TARGET = robot("b", AxisLimit(-0.5, 0.8), AxisLimit(-5.4, 5.0, 0.2))
values = st.floats(-2.0, 3.0, allow_nan=False).map(lambda v: round(v, 3))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(values, st.floats(-4.0, 4.0).map(lambda v: round(v, 3))), min_size=1, max_size=5))
def test_every_twist_literal_becomes_its_scaled_value(commands):
    lines = ["from geometry_msgs.msg import Twist, Vector3", "x = 1.5  # not a command"]
    lines += [f"t{i} = Twist(Vector3({vx!r}, 0, 0), Vector3(0, 0, {wz!r}))" for i, (vx, wz) in enumerate(commands)]
    text = "\n".join(lines) + "\n"
    result = transfer_program(text, SOURCE, TARGET)
    tree = ast.parse(result.text)
    assert ast.literal_eval(tree.body[1].value) == 1.5
    for (vx, wz), node in zip(commands, tree.body[2:]):
        linear, angular = node.value.args
        got_x, got_z = ast.literal_eval(linear.args[0]), ast.literal_eval(angular.args[2])
        want_x = scale_command(vx, SOURCE.limits["linear.x"], TARGET.limits["linear.x"]) if vx else 0.0
        want_z = scale_command(wz, SOURCE.limits["angular.z"], TARGET.limits["angular.z"]) if wz else 0.0
        assert abs(got_x - want_x) < 1e-6 and abs(got_z - want_z) < 1e-6, (vx, wz, got_x, got_z)
        assert TARGET.limits["linear.x"].allows(got_x) and TARGET.limits["angular.z"].allows(got_z)
