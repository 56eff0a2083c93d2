#!/usr/bin/env python3
"""The heading_correction node: the return's gyro heading correction alone in its process (the
paper's layout, launch/paper.launch); the role: blind_navigation/ros/heading_correction.py."""
from blind_navigation.ros.heading_correction import HeadingCorrectionRole
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('heading_correction', HeadingCorrectionRole)
