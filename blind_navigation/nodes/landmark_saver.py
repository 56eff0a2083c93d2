#!/usr/bin/env python3
"""The landmark_saver node, the paper's subscriber: one landmark per sample, alone in its process (the paper's node
layout, launch/paper.launch). The role's class: blind_navigation/ros/landmark_saving.py."""
import rospy

from blind_navigation.ros.landmark_saving import LandmarkSaver
from blind_navigation.ros.layer import run_roles, start_roles


def main():
    rospy.init_node('landmark_saver')
    run_roles(start_roles([LandmarkSaver]))


if __name__ == '__main__':
    main()
