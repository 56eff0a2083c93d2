#!/usr/bin/env python3
"""The layer in one process, blind_navigation.launch's default (node blind_navigation).

ros/mission_owner.MissionOwner, with the vision monitor when ``~auto_detect``; node params
``recorder`` (``topic``|``service``), ``auto_detect``, ``correct_heading``.
"""
import rospy

from blind_navigation.ros.layer import run_roles, start_roles
from blind_navigation.ros.mission_owner import MissionOwner
from blind_navigation.ros.vision_monitor import VisionMonitor


def main():
    rospy.init_node('blind_navigation')
    roles = [MissionOwner] + ([VisionMonitor] if rospy.get_param('~auto_detect', True) else [])
    run_roles(start_roles(roles, compact=True))


if __name__ == '__main__':
    main()
