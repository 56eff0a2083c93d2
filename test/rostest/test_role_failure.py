#!/usr/bin/env python3
"""rostest (role_failure_server.test, role_failure_paper_rotate.test): a role that fails
ends the mission safely.

The layer runs in its default layout (one process, the mission loop) through
faulty_layer.py, which makes one method of the core raise (``~fault``): the route
building after vision loss (``client``: issue 21's Python 3.8 TypeError), the return's
control step mid-return (``server``), or the pi turn's step mid-turn (``rotate``). In the paper's layout
(``~replace``: a node, e.g. rotate_pi) this test replaces that node, before the
recording starts, by faulty_layer.py running the node's script under the same
name (the launch's params stay on the master), so the failure crosses processes
to the owner, back_travel_client. A short mission is recorded on the
ideal fake TurtleBot and vision is lost. Asserted: the state ends ``aborted`` with
the role and the exception (type and message) in the reason; zero velocity
reaches the mux input (teleop) within ZERO_WITHIN of the abort and nothing moves
after it; the base, moving when the fault hit (server, rotate), stops and stays
put (ground truth); /diagnostics shows the role failure and the mission as ERROR;
the traceback is logged once, as FATAL.
With ``~record_rtf`` the mission is recorded with the fake's clock at that rtf,
the rest (from the vision loss on) at the launch's rtf.
"""
import math
import os
import subprocess
import sys
import threading
import unittest

import roslib.packages
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from std_msgs.msg import String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import STOPPED_SPEED, TELEOP_TOPIC, MissionRun, TimedTwists  # noqa: E402
from recording_tools import Collector, Diagnostics, subscribers_of  # noqa: E402
from faulty_layer import BISECT_KEY  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.geometry import wrap_angle, yaw_from_quaternion  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402

#: fault -> (the paper layout's failing role, the exception the reason names, the last
#: state before aborted); the one process names its mission owner (one loop runs every role)
EXPECTED = {
    'client': ('back_travel_client', 'TypeError: ' + BISECT_KEY, 'returning'),
    'server': ('back_travel_server', 'ZeroDivisionError: injected in the control step', 'returning'),
    'rotate': ('rotate_pi', 'RuntimeError: injected in the turn step', 'rotating'),
}
#: s of sim time: zero velocity on teleop at most this far from the abort (the fake
#: Kobuki's own command timeout is 0.6 s: the zero must come before it would stop the base)
ZERO_WITHIN = 0.5
#: s of sim time: a message received in the clock tick of the failure's log line (the fake's
#: /clock steps 0.01 s) may have been sent just before it
CLOCK_TICK = 0.011
#: the base moved in the second before the abort (server: m/s, rotate: rad/s)
MOVING_V, MOVING_W = 0.03, 0.1
#: s of sim time for the base to stop, then to stay put; m and rad it may move meanwhile
STOP_WITHIN, STAY_FOR, STAY_WITHIN, STAY_YAW = 1.0, 3.0, 0.002, 0.005
#: rad/s on ground truth that counts as not turning
STOPPED_W = 0.01


class Truth(object):
    """(sim time, x, y, yaw, v, w) of every /ground_truth/odom message."""

    def __init__(self):
        self._lock, self.items = threading.Lock(), []
        self.sub = rospy.Subscriber('/ground_truth/odom', Odometry, self._on_msg, queue_size=200)

    def _on_msg(self, msg):
        p, q, t = msg.pose.pose.position, msg.pose.pose.orientation, msg.twist.twist
        with self._lock:
            self.items.append((msg.header.stamp.to_sec(), p.x, p.y,
                               yaw_from_quaternion(q.x, q.y, q.z, q.w),
                               math.hypot(t.linear.x, t.linear.y), t.angular.z))

    def between(self, start, end):
        with self._lock:
            return [item for item in self.items if start <= item[0] <= end]

    def last(self):
        with self._lock:
            return self.items[-1]


class RoleFailureTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.fault = rospy.get_param('~fault')
        cls.replace = rospy.get_param('~replace', '')
        #: the failing process and the owner's (their diagnostics statuses are named after them)
        cls.node = cls.replace or 'blind_navigation'
        cls.owner = 'back_travel_client' if cls.replace else 'blind_navigation'
        cls.replacement = None
        role, error, cls.before = EXPECTED[cls.fault]
        cls.reason = '%s failed: %s' % (role if cls.replace else 'mission_owner', error)
        cls.mission = run = MissionRun(float(rospy.get_param('~wall_timeout', 240.0)))
        cls.teleop = TimedTwists(TELEOP_TOPIC)
        cls.truth = Truth()
        cls.status = Collector(names.STATUS, MissionStatus)
        cls.rosout = Collector('/rosout', Log)
        cls.diagnostics, cls.aborted_at = Diagnostics(), None
        rospy.Subscriber(names.STATE, String, cls._on_state, queue_size=10)
        mission = rospy.get_param('~mission')
        try:
            if cls.replace:
                cls.replace_node(run)
            run.record_mission(mission, rospy.get_param('~record_rtf', 0.0))
            run.trigger_by_publisher()
            run.wait(lambda: run.state_names()[-1:] in (['aborted'], ['home']),
                     'the mission never ended (home or aborted) after the %s fault' % cls.fault)
            run.wait(lambda: cls.aborted_at is not None or 'home' in run.state_names(),
                     'no time for the abort')
            run.wait_sim(STOP_WITHIN, 'the base stopping')
            cls.stopped = cls.truth.last()
            run.wait_sim(STAY_FOR, 'the base staying put')
            cls.final = cls.truth.last()
            run.wait_sim(1.5, 'the diagnostics after the end')
        finally:
            rospy.loginfo('ROLE FAILURE %s: states %s', cls.fault, run.state_names())
            run.stop_operator()
            if cls.replacement is not None and cls.replacement.poll() is None:
                cls.replacement.terminate()
                cls.replacement.wait(timeout=20.0)
        rospy.loginfo('ROLE FAILURE %s: reason %r', cls.fault,
                      cls.status.snapshot()[-1].reason if cls.status.snapshot() else None)

    @classmethod
    def replace_node(cls, run):
        """Kill the launch's node ``~replace`` and start faulty_layer.py with its script
        under its name, before the recording starts (it needs this node's sample
        subscription)."""
        name = '/' + cls.replace
        run.wait(lambda: name in subscribers_of(names.SAMPLE), '%s never subscribed' % name)
        subprocess.run(['rosnode', 'kill', name], check=True, timeout=run.wall_timeout)
        run.wait(lambda: name not in subscribers_of(names.SAMPLE), '%s was not killed' % name)
        found = roslib.packages.find_node('blind_navigation', 'faulty_layer.py')
        if not found:
            raise AssertionError('faulty_layer.py not found in package blind_navigation')
        cls.replacement = subprocess.Popen([found[0], cls.fault, cls.replace + '.py',
                                            '__name:=' + cls.replace])
        run.wait(lambda: name in subscribers_of(names.SAMPLE),
                 'the faulty %s never subscribed %s' % (name, names.SAMPLE))

    @classmethod
    def tearDownClass(cls):
        cls.mission.remove_recording()

    @classmethod
    def _on_state(cls, msg):
        if msg.data == 'aborted' and cls.aborted_at is None:
            cls.aborted_at = rospy.Time.now().to_sec()

    def test_1_mission_ends_aborted_naming_the_role_and_the_exception(self):
        states = self.mission.state_names()
        self.assertEqual(states[-2:], [self.before, 'aborted'], 'states %s' % states)
        reason = self.status.snapshot()[-1].reason
        self.assertIn(self.reason, reason)
        self.assertEqual(self.status.snapshot()[-1].outcome, MissionStatus.OUTCOME_ROLE_FAILURE)
        if self.fault != 'server':
            self.assertEqual(self.mission.goal_values(), [], 'goals were sent: %s' % self.mission.goal_values())

    def fatal_logs(self):
        return [msg for msg in self.rosout.snapshot()
                if msg.level == Log.FATAL and msg.name == '/' + self.node and 'Traceback' in msg.msg]

    def test_2_zero_velocity_on_the_mux_input_at_once(self):
        fatal = self.fatal_logs()
        self.assertTrue(fatal, 'no FATAL log of the failure')
        failed_at = fatal[0].header.stamp.to_sec()     # logged right after the halt
        after = self.teleop.after(failed_at - CLOCK_TICK)
        zeros = [item for item in after if item[1:] == (0.0, 0.0)]
        self.assertTrue(zeros, 'no zero velocity on %s after the failure' % TELEOP_TOPIC)
        rospy.loginfo('ROLE FAILURE %s: first zero on teleop %+.3f s (sim) from the failure, '
                      'aborted %+.3f s', self.fault, zeros[0][0] - failed_at,
                      self.aborted_at - failed_at)
        self.assertLessEqual(zeros[0][0] - failed_at, ZERO_WITHIN)
        self.assertLessEqual(self.aborted_at - failed_at, ZERO_WITHIN)
        moving = [item for item in self.teleop.after(zeros[0][0]) if item[1] or item[2]]
        self.assertLessEqual(len(moving), 1, 'motion commands after the stop: %s' % moving)
        self.assertEqual(after[-1][1:], (0.0, 0.0), 'the last command on teleop is not zero')

    def test_3_base_stops_and_stays_put(self):
        if self.fault != 'client':        # the client fails standing still, after the pi turn
            before = self.truth.between(self.aborted_at - 1.0, self.aborted_at)
            self.assertTrue(before, 'no ground truth before the abort')
            self.assertTrue(any(v > MOVING_V or abs(w) > MOVING_W for _, _, _, _, v, w in before),
                            'the base was not moving when the %s fault hit' % self.fault)
        _, x0, y0, yaw0, v, w = self.stopped
        _, x1, y1, yaw1, _, _ = self.final
        rospy.loginfo('ROLE FAILURE %s: %.1f s after the abort %.4f m/s %.4f rad/s; then moved '
                      '%.4f m %.4f rad in %.1f s', self.fault, STOP_WITHIN, v, w,
                      math.hypot(x1 - x0, y1 - y0), wrap_angle(yaw1 - yaw0), STAY_FOR)
        self.assertLess(v, STOPPED_SPEED)
        self.assertLess(abs(w), STOPPED_W)
        self.assertLess(math.hypot(x1 - x0, y1 - y0), STAY_WITHIN)
        self.assertLess(abs(wrap_angle(yaw1 - yaw0)), STAY_YAW)

    def test_4_diagnostics_show_the_failure_as_error(self):
        for name, text in (('%s: role failures' % self.node, self.reason),
                           ('%s: mission' % self.owner, 'aborted: ' + self.reason)):
            status = self.diagnostics.status(name)
            self.assertIsNotNone(status, 'no status %r on /diagnostics' % name)
            self.assertEqual(self.diagnostics.level(name), DiagnosticStatus.ERROR, status[0])
            self.assertIn(text, status[0])

    def test_5_traceback_logged_once_as_fatal(self):
        fatal = self.fatal_logs()
        self.assertEqual(len(fatal), 1, [msg.msg for msg in fatal])
        self.assertIn(self.reason, fatal[0].msg)


if __name__ == '__main__':
    rospy.init_node('test_role_failure')
    rostest.rosrun('blind_navigation', 'role_failure', RoleFailureTest)
