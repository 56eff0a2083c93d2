#!/usr/bin/env python3
"""The heading_correction node, the gyro heading correction of the return, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/heading_correction.py."""
from blind_navigation.ros.heading_correction import HeadingCorrectionRole
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('heading_correction', HeadingCorrectionRole)
