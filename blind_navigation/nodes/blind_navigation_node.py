#!/usr/bin/env python3
"""The whole layer in one process (the default, launch/blind_navigation.launch).

Every role of the paper's nodes in the paper's order, sharing one registration, one
odometry subscription and one interpreter; params ``~<role>/<name>`` (shared ones
``~<name>``). Node params: ``recorder`` (``topic``|``service``), ``auto_detect``,
``correct_heading``.
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
