#!/usr/bin/env python3
"""The back_travel_server node (class: blind_navigation/ros/back_travel_server.py)."""
import rospy

from blind_navigation.ros.back_travel_server import BackTravelServer
from blind_navigation.ros.common import start_node


def main():
    start_node('back_travel_server', BackTravelServer)
    rospy.spin()


if __name__ == '__main__':
    main()
