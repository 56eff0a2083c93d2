#!/usr/bin/env python3
"""The back_travel_client node, the paper's action client (Figure 6) and the mission state's
owner, alone in its process (launch/paper.launch). The role's class: blind_navigation/ros/paper_owner.py."""
from blind_navigation.ros.paper_owner import PaperOwner
from blind_navigation.ros.layer import run_node

if __name__ == '__main__':
    run_node('back_travel_client', PaperOwner)
