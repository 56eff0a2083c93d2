#!/usr/bin/env python3
"""The record_client node, the paper's service client (service recorder), alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/landmark_saving.py."""
import rospy

from blind_navigation.ros.landmark_saving import RecordClient
from blind_navigation.ros.layer import run_roles, start_roles


def main():
    rospy.init_node('record_client')
    run_roles(start_roles([RecordClient]))


if __name__ == '__main__':
    main()
