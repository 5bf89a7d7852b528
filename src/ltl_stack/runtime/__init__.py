"""Running a strategy, ROS-free (rank 3 of docs/architecture.md), in one group per audience:

- ``config``: the mapping format and the ROS conventions (mapping YAML, node parameters, ROS names,
  launch files);
- ``executor``: the controller executor's core (stepping, the output guard, the node's reports,
  options and setup);
- ``propositions``: the cores of the proposition nodes (edges, sensing, predicates, regions,
  localization);
- ``resilience``: thesis ch. 4 (characterization, resynthesis, stories, negotiation);
- ``runs``: a run of the controller (traces, conformance, what RViz shows).

Each group declares its public API in its ``__all__``.
"""

__all__ = ["config", "executor", "propositions", "resilience", "runs"]
