#!/usr/bin/env python3
"""The layer as one mission object in one process (blind_navigation.launch ``owner:=mission``).

ros/mission_owner.MissionOwner, with the vision monitor when ``~auto_detect``; the node
params are blind_navigation_node.py's.
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
