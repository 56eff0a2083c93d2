"""Evaluation (`make bench`): the paper's tables re-measured on the fake TurtleBot,
control modes compared, storage, latency, reconstruction; plain Python over the
core harness (sim/harness.py) plus a few ROS runs (launch/bench.launch)."""
