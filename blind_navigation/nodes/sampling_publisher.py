#!/usr/bin/env python3
"""The sampling_publisher node (class: blind_navigation/ros/sampling_publisher.py)."""
import rospy

from blind_navigation.ros.common import start_node
from blind_navigation.ros.sampling_publisher import SamplingPublisher


def main():
    start_node('sampling_publisher', SamplingPublisher).run()
    rospy.spin()


if __name__ == '__main__':
    main()
