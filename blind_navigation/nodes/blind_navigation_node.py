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
import sys

# genpy imports numpy only for optional type checks and runs without it; no role of
# this process needs numpy unless the vision monitor's dark detector is on (it lifts
# this block: core/vision.numpy_module), and not loading it saves about 15 MB.
sys.modules.setdefault('numpy', None)

import rospy  # noqa: E402

from blind_navigation.ros.back_travel_client import BackTravelClient  # noqa: E402
from blind_navigation.ros.common import REQUIRED, load_params  # noqa: E402
from blind_navigation.ros.back_travel_server import BackTravelServer  # noqa: E402
from blind_navigation.ros.heading_correction import HeadingCorrectionRole  # noqa: E402
from blind_navigation.ros.landmark_saver import LandmarkSaver  # noqa: E402
from blind_navigation.ros.layer import run_roles, start_roles  # noqa: E402
from blind_navigation.ros.record_client import RecordClient  # noqa: E402
from blind_navigation.ros.record_server import RecordServer  # noqa: E402
from blind_navigation.ros.rotate_pi import RotatePi  # noqa: E402
from blind_navigation.ros.sampling_publisher import SamplingPublisher  # noqa: E402
from blind_navigation.ros.vision_monitor import VisionMonitor  # noqa: E402

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
