#!/usr/bin/env python3
"""The record_client node (class: blind_navigation/ros/record_client.py)."""
import rospy

from blind_navigation.ros.common import start_node
from blind_navigation.ros.record_client import RecordClient


def main():
    client = start_node('record_client', RecordClient)
    client.wait_for_server()
    rospy.spin()


if __name__ == '__main__':
    main()
