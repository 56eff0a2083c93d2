#!/usr/bin/env python3
"""The calibrate_gyro node (class: blind_navigation/ros/calibrate_gyro.py)."""
import sys
import time

import rospy

from blind_navigation.ros.calibrate_gyro import CalibrateGyro
from blind_navigation.ros.common import start_node


def main():
    node = start_node('calibrate_gyro', CalibrateGyro)
    ok = node.run()
    time.sleep(0.3)   # wall: let the zero command and the last log line leave before exiting
    rospy.signal_shutdown('calibration finished' if ok else 'calibration failed')
    sys.exit(0 if ok else 1)


if __name__ == '__main__':
    main()
