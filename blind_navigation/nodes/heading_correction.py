#!/usr/bin/env python3
"""The heading_correction node (class: blind_navigation/ros/heading_correction.py)."""
import rospy

from blind_navigation.ros.common import start_node
from blind_navigation.ros.heading_correction import HeadingCorrectionNode


def main():
    start_node('heading_correction', HeadingCorrectionNode)
    rospy.spin()


if __name__ == '__main__':
    main()
