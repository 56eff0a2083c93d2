#!/usr/bin/env python3
"""The rotate_pi node (launch/paper.launch): ros/rotate_pi.RotatePi alone in its process."""
from blind_navigation.ros.rotate_pi import RotatePi
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('rotate_pi', RotatePi)
