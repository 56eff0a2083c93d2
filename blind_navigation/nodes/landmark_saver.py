#!/usr/bin/env python3
"""The landmark_saver node, the paper's subscriber: one landmark per sample, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/landmark_saving.py."""
from blind_navigation.ros.landmark_saving import LandmarkSaver
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('landmark_saver', LandmarkSaver)
