#!/usr/bin/env python3
"""The record_server node (class: blind_navigation/ros/record_server.py)."""
import rospy

from blind_navigation.ros.common import start_node
from blind_navigation.ros.record_server import RecordServer


def main():
    start_node('record_server', RecordServer)
    rospy.spin()


if __name__ == '__main__':
    main()
