#!/usr/bin/env python3
"""The back_travel_client node (class: blind_navigation/ros/back_travel_client.py)."""
from blind_navigation.ros.back_travel_client import BackTravelClient
from blind_navigation.ros.common import start_node


def main():
    start_node('back_travel_client', BackTravelClient).spin()


if __name__ == '__main__':
    main()
