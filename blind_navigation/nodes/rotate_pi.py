#!/usr/bin/env python3
"""The rotate_pi node, the pi turn after vision loss, alone in its process (launch/paper.launch).
The role's class: blind_navigation/ros/rotate_pi.py."""
from blind_navigation.ros.rotate_pi import RotatePi
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('rotate_pi', RotatePi)
