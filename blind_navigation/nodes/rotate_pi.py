#!/usr/bin/env python3
"""The rotate_pi node (class: blind_navigation/ros/rotate_pi.py)."""
from blind_navigation.ros.common import start_node
from blind_navigation.ros.rotate_pi import RotatePi


def main():
    start_node('rotate_pi', RotatePi).spin()


if __name__ == '__main__':
    main()
