#!/usr/bin/env python3
"""The vision_monitor node, automatic vision-loss detection, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/vision_monitor.py."""
import rospy

from blind_navigation.ros.vision_monitor import VisionMonitor
from blind_navigation.ros.layer import run_roles, start_roles


def main():
    rospy.init_node('vision_monitor')
    run_roles(start_roles([VisionMonitor]))


if __name__ == '__main__':
    main()
