"""ltl_stack: GR(1) specifications to safe, resilient ROS robot behaviour.

Layers (a lower layer never imports a higher one), see DESIGN.md:
spec -> synthesis -> runtime -> analysis / transfer -> ros -> sim -> gui.
"""

__version__ = "0.1.0"
