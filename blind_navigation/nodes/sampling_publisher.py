#!/usr/bin/env python3
"""The sampling_publisher node, the paper's two-rate sampling publisher, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/sampling_publisher.py."""
from blind_navigation.ros.sampling_publisher import SamplingPublisher
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('sampling_publisher', SamplingPublisher)
