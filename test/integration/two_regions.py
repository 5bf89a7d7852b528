"""A robot between two regions a and b, as the region-change tests use it: the spec (exactly one
region at a time, x while in a), and the mapping that gives both inputs to one localization node
(so that it owns them, and its ``~valuation`` carries a change of both at once)."""

SPEC = """[INPUT]
a_rc
b_rc

[OUTPUT]
x

[ENV_INIT]
a_rc
!b_rc

[ENV_TRANS]
a_rc' <-> !b_rc'

[SYS_TRANS]
x' <-> a_rc'
"""
MAPPING = """namespace: loc
inputs:
  a_rc: {node: localization, node_publish_topic: a_rc}
  b_rc: {node: localization, node_publish_topic: b_rc}
outputs:
  x: {node: x_node, node_subscribe_topic: x}
"""
