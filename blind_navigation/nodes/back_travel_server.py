#!/usr/bin/env python3
"""The back_travel_server node, the paper's action server: one landmark per goal, alone in its
process (launch/paper.launch). The role's class: blind_navigation/ros/back_travel_server.py."""
from blind_navigation.ros.back_travel_server import BackTravelServer
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('back_travel_server', BackTravelServer)
