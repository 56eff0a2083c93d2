"""The one polling wait of the rostest nodes: wall-clock bounded, so a stalled sim
clock fails the test with a message instead of hanging it."""
import time

import rospy

from blind_navigation.ros.common import exit_promptly

# every test node imports this module: it ends as soon as its results are written
exit_promptly()


def wait_for(condition, what, timeout=30.0, poll=0.01):
    """Poll ``condition()`` until true; AssertionError naming ``what`` after ``timeout`` s wall
    (``what`` may be a callable, asked only then, to say what was seen instead)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline or rospy.is_shutdown():
            raise AssertionError('gave up after %.0f s (wall): %s'
                                 % (timeout, what() if callable(what) else what))
        time.sleep(poll)
