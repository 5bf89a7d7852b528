"""Python package setup for catkin (catkin_python_setup reads this).

Every package under src/ is installed (a new subpackage cannot be forgotten in a list here).
"""
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import find_packages, setup

setup(**generate_distutils_setup(
    packages=find_packages("src"),
    package_dir={"": "src"},
    # the robot profiles ros_code_transfer reads by default (docs/code_transfer.md)
    package_data={"ltl_stack.transfer": ["robots/*.yaml", "robots/*/*.yaml"]},
))
