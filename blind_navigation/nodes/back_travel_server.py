#!/usr/bin/env python3
"""The back_travel_server node (launch/paper.launch): ros/back_travel_server.py alone."""
from blind_navigation.ros.back_travel_server import BackTravelServer
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('back_travel_server', BackTravelServer)
