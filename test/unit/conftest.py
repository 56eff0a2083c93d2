"""Make the repo's Python package importable for unit tests run without catkin."""
import os
import sys

sys.path.insert(0, os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))
