#!/usr/bin/env python3
"""The back_travel_client node, the paper's action client (Figure 6) and the mission state's
owner, alone in its process (the paper's node layout, launch/paper.launch). The role's class:
blind_navigation/ros/paper_owner.py."""
import rospy

from blind_navigation.ros.paper_owner import PaperOwner
from blind_navigation.ros.layer import run_roles, start_roles


def main():
    rospy.init_node('back_travel_client')
    run_roles(start_roles([PaperOwner]))


if __name__ == '__main__':
    main()
