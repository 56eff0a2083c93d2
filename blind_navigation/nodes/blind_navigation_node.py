#!/usr/bin/env python3
"""The whole blind navigation layer in one process (the default deployment,
launch/blind_navigation.launch): every role of the paper's nodes, built in the
paper's order (servers, then clients, then the recorder with the sampling
publisher last), sharing one master registration, one odometry subscription
and one Python interpreter. The roles talk over the same topics, services and
actions as the separate nodes of launch/paper.launch; their params are
``~<role>/<name>`` (e.g. ``~back_travel_server/control``), the few that
several roles read are ``~<name>`` (``straight_rate``, ``standstill_time``).

Node params: ``recorder`` (``topic``: sampling publisher + landmark saver;
``service``: + record server and client), ``auto_detect`` (run the vision
monitor), ``correct_heading`` (run the gyro heading correction).
"""
import rospy

from blind_navigation.ros.back_travel_client import BackTravelClient
from blind_navigation.ros.common import REQUIRED, load_params
from blind_navigation.ros.back_travel_server import BackTravelServer
from blind_navigation.ros.heading_correction import HeadingCorrectionRole
from blind_navigation.ros.landmark_saver import LandmarkSaver
from blind_navigation.ros.layer import run_roles, start_roles
from blind_navigation.ros.record_client import RecordClient
from blind_navigation.ros.record_server import RecordServer
from blind_navigation.ros.rotate_pi import RotatePi
from blind_navigation.ros.sampling_publisher import SamplingPublisher
from blind_navigation.ros.vision_monitor import VisionMonitor

RECORDERS = {'topic': [LandmarkSaver], 'service': [RecordServer, RecordClient]}
#: Set by launch/blind_navigation.launch (its args hold the defaults).
PARAMS = {'recorder': REQUIRED, 'auto_detect': REQUIRED, 'correct_heading': REQUIRED}


def main():
    rospy.init_node('blind_navigation')
    try:
        p = load_params(PARAMS)
        if p.recorder not in RECORDERS:
            raise ValueError('~recorder must be topic or service, got %r' % (p.recorder,))
    except ValueError as error:
        rospy.logfatal('%s: %s', rospy.get_name(), error)
        raise SystemExit(1)
    roles = [HeadingCorrectionRole] if p.correct_heading else []
    roles += [BackTravelServer, RotatePi, BackTravelClient]
    roles += [VisionMonitor] if p.auto_detect else []
    roles += RECORDERS[p.recorder] + [SamplingPublisher]
    run_roles(start_roles(roles, compact=True))


if __name__ == '__main__':
    main()
