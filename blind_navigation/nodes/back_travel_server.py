#!/usr/bin/env python3
"""The back_travel_server node, the paper's action server: one landmark per goal, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/back_travel_server.py."""
import rospy

from blind_navigation.ros.back_travel_server import BackTravelServer
from blind_navigation.ros.layer import run_roles, start_roles


def main():
    rospy.init_node('back_travel_server')
    run_roles(start_roles([BackTravelServer]))


if __name__ == '__main__':
    main()
