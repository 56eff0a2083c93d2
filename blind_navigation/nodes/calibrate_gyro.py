#!/usr/bin/env python3
"""The calibrate_gyro node (launch/calibrate_gyro.launch, ros/calibrate_gyro.py): exits 0 when the
calibration is written, 1 when it failed."""
import sys
import time

import rospy

from blind_navigation.ros.calibrate_gyro import CalibrateGyro
from blind_navigation.ros.layer import start_roles


def main():
    rospy.init_node('calibrate_gyro')
    calibration, = start_roles([CalibrateGyro])
    ok = calibration.guard(calibration.run)()   # None: it failed
    time.sleep(0.3)   # wall: let the zero command and the last log line leave before exiting
    rospy.signal_shutdown('calibration finished' if ok else 'calibration failed')
    sys.exit(0 if ok else 1)


if __name__ == '__main__':
    main()
