"""Helpers of the full-mission rostests (test_mission*.py): the fake TurtleBot and
the whole blind navigation layer run in one launch; a MissionRun watches the
graph, starts the scripted operator once the layer records, triggers the vision
loss and measures where the robot ends on /ground_truth/odom.

The operator (the fake's mission_driver node) is started by the test, not by the
launch, once the layer records: the fake's clock starts with the launch, and a
mission started before the sampling publisher would be partly unrecorded.
"""
import math
import os
import shutil
import subprocess
import sys
import threading
import time
from collections import namedtuple

import roslib.packages
import rospy
from actionlib_msgs.msg import GoalID, GoalStatus
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from std_msgs.msg import Bool, Empty, Float64, String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from recording_tools import Collector, subscribers_of  # noqa: E402
from waiting import wait_for  # noqa: E402

from blind_navigation import names
from blind_navigation.core.mission_state import TERMINAL as FINAL_STATES  # noqa: E402
from blind_navigation.core.heading_correction import correct_landmarks  # noqa: E402
from blind_navigation.core.geometry import Pose2D, yaw_from_quaternion  # noqa: E402
from blind_navigation.ros.layer import correction_from_message  # noqa: E402
from blind_navigation.core.store import load_landmarks  # noqa: E402
from blind_navigation.msg import (BackTravelActionGoal, BackTravelActionResult,  # noqa: E402
                                  MissionStatus, StorageUsage, HeadingCorrection, PathSample)

#: The state walk of a mission that comes home (back_travel_client owns it).
HOME_WALK = ['idle', 'recording', 'rotating', 'returning', 'home']
#: What a mission ended with: the robot's distance from the start (m, ground truth), its
#: speed (m/s) and the recorded file (core/store.LoadedPath).
Outcome = namedtuple('Outcome', 'error speed loaded')
TELEOP_TOPIC = '/cmd_vel_mux/input/teleop'
MISSION_DONE_TOPIC = '/mission_driver/done'
#: The fake base's clock pace (sim/nodes/fake_kobuki.py's ~rtf).
RTF_TOPIC = '/mobile_base/rtf'
#: The one process of blind_navigation.launch (its default): every role's params under it.
ONE_PROCESS = '/blind_navigation'
#: s of sim time: the operator has stopped sending; the base stops (paper profile's
#: motor time constant 0.25 s) before vision is lost, as in demo_observer.
SETTLE = 2.0
#: s wall for the layer to come up (node start-up, graph connections).
STARTUP_TIMEOUT = 30.0
#: m/s on /ground_truth/odom that counts as standing still (encoder-free truth:
#: exactly 0 on a stopped base; margin for the ripple of the paper profile).
STOPPED_SPEED = 0.005


class GroundTruth(object):
    """Latest /ground_truth/odom pose and speed (m, rad, m/s), thread-safe."""

    def __init__(self):
        self._lock = threading.Lock()
        self._latest = None
        self.sub = rospy.Subscriber('/ground_truth/odom', Odometry, self._on_msg, queue_size=1)

    def _on_msg(self, msg):
        p, q, t = msg.pose.pose.position, msg.pose.pose.orientation, msg.twist.twist
        with self._lock:
            self._latest = (p.x, p.y, math.hypot(t.linear.x, t.linear.y), msg.header.stamp.to_sec(),
                            yaw_from_quaternion(q.x, q.y, q.z, q.w))

    def latest(self):
        with self._lock:
            return self._latest

    def position(self):
        return self.latest()[:2]

    def pose(self):
        """The robot's pose (the fake's world frame)."""
        x, y, _, _, yaw = self.latest()
        return Pose2D(x, y, yaw)

    def speed(self):
        return self.latest()[2]


class TimedTwists(object):
    """(sim time of receipt, v, w) of every Twist on a topic."""

    def __init__(self, topic):
        self._lock, self.items = threading.Lock(), []
        self.sub = rospy.Subscriber(topic, Twist, self._on_msg, queue_size=100)

    def _on_msg(self, msg):
        with self._lock:
            self.items.append((rospy.Time.now().to_sec(), msg.linear.x, msg.angular.z))

    def after(self, t):
        with self._lock:
            return [item for item in self.items if item[0] >= t]


def _return_or_state(state):
    return 'return' if state == 'returning' or state in FINAL_STATES else state


class PathByState(object):
    """Ground-truth path length (m) driven in each mission state: the recording
    (``recording``) and the return after the pi turn (``returning`` and after); with
    ``key``, under ``key(state)`` (e.g. ``str``: each state by its own name)."""

    def __init__(self, key=_return_or_state):
        self._key = key
        self._lock = threading.Lock()
        self.state = None
        self.length = {}
        self._last = None
        rospy.Subscriber(names.STATE, String, self._on_state, queue_size=10)
        rospy.Subscriber('/ground_truth/odom', Odometry, self._on_truth, queue_size=200)

    def _on_state(self, msg):
        with self._lock:
            self.state = msg.data

    def _on_truth(self, msg):
        p = msg.pose.pose.position
        with self._lock:
            if self._last is not None and self.state is not None:
                step = math.hypot(p.x - self._last[0], p.y - self._last[1])
                key = self._key(self.state)
                self.length[key] = self.length.get(key, 0.0) + step
            self._last = (p.x, p.y)

    def of(self, key):
        with self._lock:
            return self.length.get(key, 0.0)


#: rad: the goals' psi as this node computes them (core/heading_correction with the
#: final sample's stamp) against the client's (its odometry's stamp at the turn's commit)
PSI_TOLERANCE = 1e-3


class MissionRun(object):
    """One mission on the fake TurtleBot, watched from the test node.

    ``wall_timeout`` (s) bounds each wait; the launch sets the sampling publisher's
    ``min_subscribers`` so that the recording starts only once this test takes the
    samples, which :meth:`wait_for_layer` does after it has seen ``idle``.

    The layer runs in one process (``/blind_navigation``, blind_navigation.launch's
    default) or in the paper's node layout (one_process:=false); ``compact`` tells
    which, ``owner`` is the node that owns the mission (back_travel_client's),
    :meth:`param` reads a role's param in either.
    """

    def __init__(self, wall_timeout):
        self.wall_timeout = wall_timeout
        self.compact = rospy.has_param(ONE_PROCESS + '/recorder')
        self.owner = ONE_PROCESS if self.compact else '/back_travel_client'
        #: vision_monitor's latched ~loss (the detector that fired and why)
        self.loss_topic = (ONE_PROCESS if self.compact else '/vision_monitor') + '/loss'
        self.states = Collector(names.STATE, String)
        self.truth = GroundTruth()
        self.goals = Collector(names.BACK_TRAVEL + '/goal', BackTravelActionGoal)
        self.results = Collector(names.BACK_TRAVEL + '/result', BackTravelActionResult)
        self.storage_msgs = Collector(names.STORAGE, StorageUsage)
        self.status = Collector(names.STATUS, MissionStatus)
        self.mission_done = Collector(MISSION_DONE_TOPIC, Bool)
        self.corrections = Collector(names.HEADING_CORRECTION, HeadingCorrection)
        self.samples = None
        self.operator = None
        self.start = None

    def param(self, role, name):
        """The param ``name`` of ``role`` (e.g. back_travel_server, control)."""
        return rospy.get_param('%s/%s/%s' % (ONE_PROCESS if self.compact else '', role, name))

    def state_names(self):
        return [msg.data for msg in self.states.snapshot()]

    def wait(self, condition, message, timeout=None):
        wait_for(condition, message, timeout or self.wall_timeout)

    def wait_sim(self, seconds, what):
        """Let ``seconds`` of sim time pass (bounded in wall time)."""
        until = rospy.Time.now().to_sec() + seconds
        self.wait(lambda: rospy.Time.now().to_sec() >= until,
                  'sim time did not advance %.1f s (%s): is the fake clock running?' % (seconds, what))

    def wait_for_layer(self):
        """Idle layer and ground truth; then take the samples, which starts the recording."""
        self.wait(lambda: self.state_names()[:1] == ['idle'], 'back_travel_client never published idle',
                  STARTUP_TIMEOUT)
        self.wait(lambda: self.truth.latest() is not None, 'no /ground_truth/odom from the fake base',
                  STARTUP_TIMEOUT)
        self.samples = Collector(names.SAMPLE, PathSample)
        self.wait(lambda: 'recording' in self.state_names(),
                  'state never became recording (no storage from the recorder reached the client)',
                  STARTUP_TIMEOUT)
        self.start = self.truth.position()

    def play_mission(self, mission):
        """Start the fake's scripted operator now and wait until it is done and the robot stopped."""
        self.start_operator(mission)
        self.wait_for_operator(mission)

    def wait_for_operator(self, mission):
        """Wait until the operator (started here or by the launch) is done and the robot stopped;
        returns the states seen when the operator was done."""
        self.wait(lambda: any(msg.data for msg in self.mission_done.snapshot()),
                  'mission_driver never finished %s' % mission)
        states = self.state_names()
        self.wait_sim(SETTLE, 'robot settling after the mission')
        return states

    def record_mission(self, mission, record_rtf=0.0):
        """Record ``mission`` (wait_for_layer, the operator, until it is done and the robot
        stopped); with ``record_rtf``, the fake's clock runs at that rtf meanwhile and at the
        launch's rtf again after. Returns the states seen when the operator was done."""
        if record_rtf:
            self.set_rtf(record_rtf)
        self.wait_for_layer()
        self.start_operator(mission)
        states = self.wait_for_operator(mission)
        if record_rtf:
            self.set_rtf(rospy.get_param('/mobile_base/rtf'))
        return states

    def set_rtf(self, rtf):
        """Run the fake's clock at ``rtf`` x real time from now on (its ~rtf topic), once the
        fake says so on /rosout: a test runs what it does not time faster than the launch's rtf."""
        self.tell_fake(RTF_TOPIC, Float64(rtf), 'fake_kobuki: rtf %g from' % rtf)

    def tell_fake(self, topic, message, line):
        """Publish ``message`` on the fake base's rig ``topic`` until the fake logs ``line``
        on /rosout (asked again each second: a line logged before this node's /rosout
        subscription connected to the fake is lost)."""
        rosout = Collector('/rosout', Log)
        publisher = rospy.Publisher(topic, type(message), queue_size=1, latch=True)
        asked = [float('-inf')]

        def logged():
            if any(line in msg.msg for msg in rosout.snapshot()):
                return True
            if time.monotonic() > asked[0] + 1.0:
                publisher.publish(message)
                asked[0] = time.monotonic()
            return False
        try:
            self.wait(lambda: publisher.get_num_connections() >= 1,
                      'the fake base does not subscribe %s' % topic, STARTUP_TIMEOUT)
            self.wait(logged, 'the fake base never logged %r' % line, STARTUP_TIMEOUT)
        finally:
            rosout.sub.unregister()
            publisher.unregister()

    def wait_moved(self, metres, what):
        """Until the robot is ``metres`` (ground truth) from where the recording began: the
        operator's process may start late on a loaded machine while the sim clock runs on."""
        def moved():
            x, y = self.truth.position()
            return math.hypot(x - self.start[0], y - self.start[1]) >= metres
        self.wait(moved, 'the robot never moved %.2f m from the start (%s)' % (metres, what))

    def start_operator(self, mission):
        found = roslib.packages.find_node('blind_navigation', 'mission_driver.py')
        if not found:
            raise AssertionError('mission_driver.py not found in package blind_navigation')
        self.operator = subprocess.Popen([found[0], '__name:=mission_driver', '_mission:=%s' % mission,
                                          'cmd_vel:=%s' % TELEOP_TOPIC, 'ground_truth:=/ground_truth/odom'])

    def wait_for_trigger_subscribers(self):
        """Until the mission's owner (it decides what vision loss does) subscribes the trigger."""
        self.wait(lambda: self.owner in subscribers_of(names.VISION_LOST),
                  '%s (back_travel_client) does not subscribe %s' % (self.owner, names.VISION_LOST))

    def trigger_by_rostopic(self):
        """The paper's manual trigger, exactly as typed in a shell."""
        self.wait_for_trigger_subscribers()
        subprocess.run(['rostopic', 'pub', '-1', names.VISION_LOST, 'std_msgs/Empty', '{}'],
                       check=True, timeout=self.wall_timeout)

    def trigger_by_publisher(self):
        """The same message from this node (latched: late subscribers get it too)."""
        self.wait_for_trigger_subscribers()
        self.trigger = rospy.Publisher(names.VISION_LOST, Empty, queue_size=1, latch=True)
        self.wait(lambda: self.trigger.get_num_connections() >= len(subscribers_of(names.VISION_LOST)),
                  'no connection to every %s subscriber' % names.VISION_LOST)
        self.trigger.publish(Empty())

    def wait_until_final(self):
        self.wait(lambda: self.state_names()[-1:] in ([name] for name in FINAL_STATES),
                  'the mission never ended (state home or aborted); states so far %s'
                  % self.state_names())
        self.wait_sim(SETTLE, 'robot stopping after the last goal')

    def outcome(self):
        """Wait until the mission ends (and the robot settles); its :data:`Outcome`."""
        self.wait_until_final()
        return Outcome(self.error(), self.truth.speed(), self.recorded())

    def error(self):
        """Ground-truth distance (m) between the mission's start and the robot now."""
        x, y = self.truth.position()
        return math.hypot(x - self.start[0], y - self.start[1])

    def recorded(self):
        """The landmark file the recorder reported last (core/store.LoadedPath)."""
        storage_msgs = self.storage_msgs.snapshot()
        if not storage_msgs:
            raise AssertionError('no storage was published: nothing recorded')
        return load_landmarks(storage_msgs[-1].file)

    def goal_values(self):
        """The goals seen on the action's goal topic. The client publishes them from
        the return's start (it makes its action client then), so this node may see
        only those after its subscription connected: the first, standing ones."""
        return [(g.goal.v, g.goal.w, g.goal.d, g.goal.T, g.goal.psi) for g in self.goals.snapshot()]

    def goals_expected(self, landmarks):
        """What back_travel_client sends for the recorded ``landmarks``, in sending order:
        reversed, and in the heading correction's frame when one was published
        (blind_navigation.launch runs heading_correction by default). The recording
        went on after the correction's reference until the turn began: the client
        counts that from its odometry when the turn is committed, this node from the
        recorder's final sample (a few cycles apart: compare psi with PSI_TOLERANCE)."""
        corrections = self.corrections.snapshot()
        if corrections:
            correction, reference = correction_from_message(corrections[-1])
            finals = [msg for msg in (self.samples.snapshot() if self.samples else ())
                      if msg.command == 'final']
            after = max(0.0, finals[-1].header.stamp.to_sec() - reference.stamp) if finals else 0.0
            landmarks = correct_landmarks(landmarks, correction, reference.yaw, after)
        return [tuple(landmark) for landmark in reversed(landmarks)]

    def goal_outcomes(self):
        """GoalStatus codes of the results the server published, in order."""
        return [r.status.status for r in self.results.snapshot()]

    def mission_object(self):
        """True when the layer runs in one process (ros/mission_owner.py): its return drives
        no BackTravel goals."""
        return self.compact

    def goals_started(self):
        """Goals the return has begun: those seen on the action's goal topic, or with
        in one process those its status counted while returning."""
        if not self.mission_object():
            return len(self.goals.snapshot())
        return max([min(s.completed + 1, s.landmarks) for s in self.status.snapshot()
                    if s.state == 'returning'] or [0])

    def wait_mid_return(self, goals, speed, timed_rtf=0.0):
        """Until more than ``goals`` goals were sent and the base drives faster than
        ``speed`` (m/s, ground truth); with ``timed_rtf``, the fake's clock then runs at that
        rtf (what follows is timed); (the speed, the sim time now)."""
        self.wait(lambda: self.goals_started() > goals and self.truth.speed() > speed,
                  'the robot never drove back at > %.2f m/s after %d goals' % (speed, goals))
        if timed_rtf:
            self.set_rtf(timed_rtf)
        return self.truth.speed(), rospy.Time.now().to_sec()

    def cancel_all_goals(self):
        """What `rostopic pub .../back_travel/cancel actionlib_msgs/GoalID {}` does: cancel every goal."""
        publisher = rospy.Publisher(names.BACK_TRAVEL + '/cancel', GoalID, queue_size=1)
        self.wait(lambda: publisher.get_num_connections() >= 1,
                  'back_travel_server does not subscribe %s/cancel' % names.BACK_TRAVEL)
        publisher.publish(GoalID())

    def remove_recording(self):
        """Delete the mission's private landmark directory (mission_rig.launch's ``dir``)."""
        for msg in self.storage_msgs.snapshot()[:1]:
            directory = os.path.dirname(msg.file)
            if directory.endswith('-mission-test'):
                shutil.rmtree(directory, ignore_errors=True)

    def close(self):
        """Unsubscribe every topic this run watches (a test that runs several missions
        in one node: a stale subscription to the samples would count as a listener of
        the next layer's sampling publisher and start its recording early)."""
        for watched in (self.states, self.truth, self.goals, self.results, self.storage_msgs,
                        self.mission_done, self.corrections, self.samples, self.status):
            if watched is not None:
                watched.sub.unregister()

    def stop_operator(self):
        if self.operator and self.operator.poll() is None:
            self.operator.terminate()
            try:
                self.operator.wait(timeout=10.0)
            except subprocess.TimeoutExpired:
                self.operator.kill()


class HomeMission(object):
    """Mixin of the mission tests whose mission ends home: the TestCase sets
    ``mission_run`` (a MissionRun) and ``loaded`` in setUpClass."""

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()

    def test_state_walks_to_home(self):
        self.assertEqual(self.mission_run.state_names(), HOME_WALK)

    def assert_every_landmark_succeeded(self, more_than):
        """More than ``more_than`` landmarks, and one succeeded goal for each."""
        count = len(self.loaded.landmarks)
        self.assertGreater(count, more_than)
        if self.mission_run.mission_object():   # no BackTravel action: the final status counts
            final = self.mission_run.status.snapshot()[-1]
            self.assertEqual((final.state, final.completed, final.landmarks), ('home', count, count),
                             'the final status: %s' % final)
        else:
            self.assertEqual(self.mission_run.goal_outcomes(), [GoalStatus.SUCCEEDED] * count)
