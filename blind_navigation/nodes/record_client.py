#!/usr/bin/env python3
"""The record_client node, the paper's service client (service recorder), alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/landmark_saving.py."""
from blind_navigation.ros.landmark_saving import RecordClient
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('record_client', RecordClient)
