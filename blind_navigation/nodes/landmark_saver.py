#!/usr/bin/env python3
"""The landmark_saver node (class: blind_navigation/ros/landmark_saver.py)."""
import rospy

from blind_navigation.ros.common import start_node
from blind_navigation.ros.landmark_saver import LandmarkSaver


def main():
    start_node('landmark_saver', LandmarkSaver)
    rospy.spin()


if __name__ == '__main__':
    main()
