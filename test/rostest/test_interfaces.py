#!/usr/bin/env python3
"""rostest: the package's message, service and action definitions are generated
and usable over a real ROS master (topic, service and actionlib round trips); the
one-process layer (the mission owner, interfaces.test) serves the paper's names on
this node's odometry: ``record_landmark`` saves one extra landmark of the mission's
recording at the odometry of the request's stamp (its T and psi; d the path from the
previous landmark), refuses bad requests, ``final`` and requests outside the recording
(naming the state), saving nothing; ``back_travel`` rejects every goal naming why (no
status published without a goal changing), and nothing drives. The owner's docking client
(ros/motion.py) sends its goal at once, or says at once that no server is there."""
import math
import re
import threading
import unittest
from types import SimpleNamespace

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Header, String
from std_srvs.srv import Trigger

from blind_navigation.core.docking import DockingResult
from blind_navigation.core.store import load_landmarks
from blind_navigation.msg import (BackTravelAction, BackTravelFeedback, BackTravelGoal,
                                  BackTravelResult, PathSample)
from blind_navigation.ros import kobuki_msgs_compat as kobuki
from blind_navigation.ros.goal_client import GoalClient
from blind_navigation.ros.motion import DockingClient
from blind_navigation.ros.mission_owner import Inbox
from blind_navigation.srv import RecordLandmark, RecordLandmarkResponse

import test_odometry_feed
import test_subscription_watchdog
from recording_tools import Collector
from waiting import wait_for

TIMEOUT = 10.0
#: s (wall) the layer may take to come up on a loaded machine
LAYER_TIMEOUT = 60.0
SPEED = 0.1             # m/s along +x once the odometry moves
RECORD = '/blind_navigation/record_landmark'
#: Requests saving nothing: (command, psi, T, what the answer says).
BAD = [('final', 0.0, 1.0, "'final' is not taken here"), ('../../x.yaml', 0.0, 1.0, 'unknown command'),
       ('sample', float('nan'), 1.0, 'finite'), ('sample', 0.0, 0.0, 'T > 0')]


class Odometer(object):
    """Odometry at 50 Hz: standing at x = 0 until :meth:`move`, then SPEED m/s along +x until
    :meth:`stop`; ``sent``: (stamp, x) of every message."""

    def __init__(self):
        self.pub = rospy.Publisher('/odom', Odometry, queue_size=50)
        self.sent, self._lock = [], threading.Lock()
        self.moved_at = self.stopped_at = None
        self.timer = rospy.Timer(rospy.Duration(0.02), self._tick)

    def move(self):
        self.moved_at = rospy.get_time()

    def stop(self):
        self.stopped_at = rospy.get_time()

    def x_sent_at(self, stamp):
        """x of the last message stamped at or before ``stamp``."""
        with self._lock:
            return [x for t, x in self.sent if t <= stamp][-1]

    def _tick(self, _event):
        now = rospy.Time.now()
        t, msg = now.to_sec(), Odometry()
        moving = self.moved_at is not None and t >= self.moved_at and self.stopped_at is None
        end = self.stopped_at if self.stopped_at is not None else t
        msg.header.stamp, msg.header.frame_id, msg.child_frame_id = now, 'odom', 'base_footprint'
        msg.pose.pose.position.x = SPEED * max(0.0, end - self.moved_at) if self.moved_at else 0.0
        msg.pose.pose.orientation.w = 1.0
        msg.twist.twist.linear.x = SPEED if moving else 0.0
        with self._lock:
            self.sent.append((t, msg.pose.pose.position.x))
        self.pub.publish(msg)


class InterfacesTest(unittest.TestCase):

    def test_path_sample_has_the_papers_three_variables(self):
        # and which sample it is, for a restarted recorder (srv/RecordedSamples.srv)
        self.assertEqual(PathSample.__slots__, ['header', 'command', 'yaw', 'period',
                                                'recording', 'seq'])

    def test_action_goal_is_a_landmark(self):
        self.assertEqual(BackTravelGoal.__slots__, ['v', 'w', 'd', 'T', 'psi'])
        self.assertEqual(BackTravelResult.__slots__, ['distance', 'duration', 'outcome'])
        self.assertEqual(BackTravelFeedback.__slots__, ['distance'])

    def test_topic_round_trip(self):
        received = []
        rospy.Subscriber('interfaces_test/sample', PathSample, received.append)
        publisher = rospy.Publisher('interfaces_test/sample', PathSample, queue_size=1)
        deadline = rospy.Time.now() + rospy.Duration(TIMEOUT)
        while not received and rospy.Time.now() < deadline and not rospy.is_shutdown():
            publisher.publish(PathSample(command='sample', yaw=0.25, period=2.0))
            rospy.sleep(0.1)
        self.assertTrue(received, 'no PathSample came back within %.0f s' % TIMEOUT)
        self.assertEqual((received[0].command, received[0].yaw, received[0].period),
                         ('sample', 0.25, 2.0))

    def test_service_round_trip(self):
        def handle(request):
            return RecordLandmarkResponse(saved=True, label='landmark_000001', message='')
        rospy.Service('interfaces_test/record', RecordLandmark, handle)
        rospy.wait_for_service('interfaces_test/record', timeout=TIMEOUT)
        response = rospy.ServiceProxy('interfaces_test/record', RecordLandmark)(
            command='sample', yaw=0.1, period=1.0)
        self.assertTrue(response.saved)
        self.assertEqual(response.label, 'landmark_000001')

    def test_action_round_trip(self):
        def execute(goal):
            server.publish_feedback(BackTravelFeedback(distance=goal.d / 2))
            server.set_succeeded(BackTravelResult(distance=goal.d, duration=goal.T))
        server = actionlib.SimpleActionServer('interfaces_test/back_travel', BackTravelAction,
                                              execute_cb=execute, auto_start=False)
        server.start()
        client = GoalClient('interfaces_test/back_travel', BackTravelAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(TIMEOUT)),
                        'action server did not come up within %.0f s' % TIMEOUT)
        client.send_goal(BackTravelGoal(v=0.1, w=0.0, d=0.2, T=2.0, psi=0.0))
        self.assertTrue(client.wait_for_result(rospy.Duration(TIMEOUT)), 'no action result')
        self.assertEqual(client.get_result().distance, 0.2)

    def test_the_mission_owner_rejects_back_travel_goals(self):
        teleop = Collector('/cmd_vel_mux/input/teleop', Twist)
        statuses = Collector('/blind_navigation/back_travel/status', GoalStatusArray)
        client = GoalClient('/blind_navigation/back_travel', BackTravelAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(LAYER_TIMEOUT)),
                        'the layer served no back_travel action within %.0f s' % LAYER_TIMEOUT)
        client.send_goal(BackTravelGoal(v=0.1, w=0.0, d=0.2, T=2.0, psi=0.0))
        self.assertTrue(client.wait_for_result(rospy.Duration(TIMEOUT)), 'no action result')
        self.assertEqual(client.get_state(), GoalStatus.REJECTED)
        self.assertIn('drives its return itself', client.get_goal_status_text())
        rejected = lambda: [m for m in statuses.snapshot() if any(    # noqa: E731  (the only goal)
            s.status == GoalStatus.REJECTED and 'drives its return' in s.text for s in m.status_list)]
        wait_for(rejected, 'a status naming the goal rejected', TIMEOUT)
        heard = len(statuses)
        rospy.sleep(2.0)        # two periods of the former 1 Hz status thread (status_frequency)
        self.assertEqual(len(statuses), heard, 'the status is published without a goal changing')
        moving = [m for m in teleop.snapshot() if m.linear.x or m.angular.z]
        self.assertEqual(moving, [], 'the rejected goal drove the robot')

    def test_the_docking_client_sends_its_goal_without_waiting_for_the_server(self):
        """ros/motion.DockingClient: without the auto-docking server, start() has put why
        into the owner's inbox when it returns; with one (found meanwhile), the goal is sent
        and its end comes in."""
        inbox = Inbox()
        docking = DockingClient(inbox, None, SimpleNamespace(info=rospy.loginfo))
        docking.start()
        self.assertEqual(inbox.take(0.0)[2], {'docking': DockingResult(
            False, 'no auto-docking action server on /dock_drive_action')})
        server = actionlib.SimpleActionServer('/dock_drive_action', kobuki.AutoDockingAction, execute_cb=(
            lambda goal: server.set_succeeded(kobuki.AutoDockingResult(text='on the dock'))), auto_start=False)
        server.start()
        self.assertTrue(docking.client.wait_for_server(rospy.Duration(TIMEOUT)),
                        'the docking client did not find the server within %.0f s' % TIMEOUT)
        docking.start()
        self.assertEqual(inbox.take(TIMEOUT)[2], {'docking': DockingResult(True, 'on the dock')})

    def test_the_mission_owner_serves_record_landmark(self):
        states = Collector('/blind_navigation/state', String)
        state = lambda: ([m.data for m in states.snapshot()] or [''])[-1]    # noqa: E731
        rospy.wait_for_service(RECORD, timeout=LAYER_TIMEOUT)
        record = rospy.ServiceProxy(RECORD, RecordLandmark)
        odometer = Odometer()
        wait_for(lambda: odometer.pub.get_num_connections() > 0, 'the layer subscribed to /odom')
        rospy.sleep(0.5)                # standing: the recording begins at x = 0
        odometer.move()
        wait_for(lambda: state() == 'recording', lambda: 'the mission recording (state %r)' % state())
        bad = [record(header=Header(stamp=rospy.Time.now()), command=command, yaw=psi, period=T)
               for command, psi, T, _ in BAD]
        stamp = rospy.Time.now()
        good = record(header=Header(stamp=stamp), command='sample', yaw=0.25, period=0.5)
        odometer.stop()
        self.assertTrue(rospy.ServiceProxy('/blind_navigation/go_home', Trigger)().success)
        wait_for(lambda: state() not in ('recording', ''), 'the recording ending after go_home')
        late = record(header=Header(stamp=rospy.Time.now()), command='sample', yaw=0.0, period=1.0)
        rospy.ServiceProxy('/blind_navigation/cancel', Trigger)()     # the robot stays still
        odometer.timer.shutdown()

        for answer, (command, _, _, says) in zip(bad, BAD):
            self.assertFalse(answer.saved, command)
            self.assertIn(says, answer.message, command)
        self.assertTrue(good.saved, good.message)
        self.assertTrue(re.match(r'^landmark_\d+$', good.label), good.label)
        loaded = load_landmarks(rospy.get_param('~landmark_file'))
        index = loaded.labels.index(good.label)
        mine = loaded.landmarks[index]
        self.assertAlmostEqual(mine.T, 0.5, places=6)
        self.assertAlmostEqual(mine.psi, 0.25, places=6)
        self.assertAlmostEqual(mine.v, SPEED, places=6)
        # straight along +x from x = 0: the d up to it is the odometry's x at its stamp
        travelled, expected = sum(lm.d for lm in loaded.landmarks[:index + 1]), \
            odometer.x_sent_at(stamp.to_sec())
        rospy.loginfo('RECORD_LANDMARK: %s, d %.4f m, path to it %.4f m, odometry at the stamp '
                      '%.4f m', good.label, mine.d, travelled, expected)
        self.assertAlmostEqual(travelled, expected, delta=1e-3)
        self.assertEqual([lm for lm in loaded.landmarks if abs(lm.T - 0.5) + abs(lm.psi - 0.25) < 1e-6],
                         [mine], 'one landmark of the request')
        self.assertTrue(all(math.isfinite(value) for lm in loaded.landmarks for value in lm))
        self.assertFalse(late.saved)
        named = re.search(r'the mission is (\w+), not recording', late.message)
        self.assertTrue(named and named.group(1) not in ('idle', 'recording'), late.message)


def every_case():
    """This module's cases, then test_odometry_feed.py's and test_subscription_watchdog.py's
    (on topics of their own beside the layer)."""
    loader = unittest.TestLoader()
    return unittest.TestSuite([loader.loadTestsFromTestCase(InterfacesTest),
                               loader.loadTestsFromModule(test_odometry_feed),
                               loader.loadTestsFromModule(test_subscription_watchdog)])


if __name__ == '__main__':
    rospy.init_node('test_interfaces')
    rostest.rosrun('blind_navigation', 'interfaces', __name__ + '.every_case')
