#!/usr/bin/env python3
"""The vision_monitor node (launch/paper.launch): ros/vision_monitor.VisionMonitor alone."""
from blind_navigation.ros.vision_monitor import VisionMonitor
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('vision_monitor', VisionMonitor)
