#!/usr/bin/env python3
"""The rotate_pi node, the pi turn after vision loss, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/rotate_pi.py."""
import rospy

from blind_navigation.ros.rotate_pi import RotatePi
from blind_navigation.ros.layer import run_roles, start_roles


def main():
    rospy.init_node('rotate_pi')
    run_roles(start_roles([RotatePi]))


if __name__ == '__main__':
    main()
