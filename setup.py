"""Python package set-up for catkin (catkin_python_setup() reads this)."""
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(
    packages=['blind_navigation', 'blind_navigation.core', 'blind_navigation.ros',
              'blind_navigation.sim', 'blind_navigation.evaluation'],
    package_dir={'': '.'},
))
