#!/usr/bin/env python3
"""The vision_monitor node (class: blind_navigation/ros/vision_monitor.py)."""
import rospy

from blind_navigation.ros.common import start_node
from blind_navigation.ros.vision_monitor import VisionMonitorNode


def main():
    start_node('vision_monitor', VisionMonitorNode)
    rospy.spin()


if __name__ == '__main__':
    main()
