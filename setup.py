"""Python package setup for catkin (catkin_python_setup reads this)."""
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(
    packages=[
        "ltl_stack",
        "ltl_stack.spec",
        "ltl_stack.synthesis",
        "ltl_stack.runtime",
        "ltl_stack.analysis",
        "ltl_stack.transfer",
        "ltl_stack.ros",
        "ltl_stack.sim",
        "ltl_stack.gui",
    ],
    package_dir={"": "src"},
))
