#!/usr/bin/env python3
"""The vision_monitor node, automatic vision-loss detection, alone in its process
(launch/paper.launch). The role's class: blind_navigation/ros/vision_monitor.py."""
from blind_navigation.ros.vision_monitor import VisionMonitor
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('vision_monitor', VisionMonitor)
