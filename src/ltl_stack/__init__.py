"""ltl_stack: GR(1) specifications to safe, resilient ROS robot behaviour.

Layers (a lower layer never imports a higher one), see DESIGN.md:
spec -> synthesis -> runtime -> analysis / transfer -> ros -> sim -> gui.
"""

from ltl_stack import missing as _missing

__version__ = "0.1.0"

_missing.install()  # a script that lacks a PyPI package says which, in one line (exit 2)
