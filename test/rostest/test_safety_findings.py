#!/usr/bin/env python3
"""rostest: issue 16's findings 1-7 over ROS on the fake TurtleBot (ideal profile, rtf 6,
closed_loop, blind_navigation.launch as a user starts it, the 2.3 m mission
config/missions/test_safety.yaml): each bullet reproduced and checked to end with the
robot still or ``home`` within the normal accuracy, no motion commanded after a terminal
state, and the record intact or its loss reported.

One TestCase per mission (findings_rig.FindingMission); its setUpClass plays the faults of
its findings, each at its own phase, and each test method checks one bullet and prints one
``FINDING`` line. TestA attacks the default one process, TestB and the restarts the paper's
node layout (its own topics, services and nodes); the missions of a layout share its layer
(a LayerChain: the next one starts by ``new_mission``), the start-up cases launch their own.
The param ``~only`` (comma-separated class names) runs a subset. Behaviour alone (a loss while
standing still, a long takeover) is played in test/unit/test_mission_harness_findings.py.
"""
import json
import math
import os
import queue
import resource
import shutil
import socket
import subprocess
import sys
import threading
import time
import unittest

import rosgraph
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticStatus
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool, Empty, Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from findings_rig import (MISSION, NORMAL_ACCURACY, TEST_ROOT, WALL_TIMEOUT,  # noqa: E402
                          FindingMission, LayerChain, LayerLaunch, mission_directory)
from mission_tools import HOME_WALK, STOPPED_SPEED  # noqa: E402
from recording_tools import kill_node, node_pid, subscribers_of  # noqa: E402
from waiting import wait_for  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.landmark import Limits  # noqa: E402
from blind_navigation.core.plausibility import RouteBudget  # noqa: E402
from blind_navigation.core.progress import load_progress, progress_path  # noqa: E402
from blind_navigation.core.route import build_route  # noqa: E402
from blind_navigation.core.store import load_landmarks  # noqa: E402
from blind_navigation.ros.goal_client import GoalClient  # noqa: E402
from blind_navigation.ros.paper_owner import route_message  # noqa: E402
from blind_navigation.msg import BackTravelAction, BackTravelGoal  # noqa: E402
from blind_navigation.srv import SetReturnRoute  # noqa: E402

#: Finding 1: a 3 s burst of /odom at x = 1e6, 100 Hz.
BURST_X, BURST_RATE, BURST_TIME = 1e6, 100.0, 3.0
#: Finding 2: a twist no Kobuki makes, m/s.
BURST_TWIST = 1e6
#: Finding 4: the vision_lost flood, Hz (wall).
FLOOD_RATE = 1000.0
#: Finding 5a: the issue's goal while idle: d = 1000 m (T so long that d fits the limits).
IDLE_GOAL = BackTravelGoal(v=0.5, w=0.0, d=1000.0, T=2000.0, psi=0.0)
#: Finding 5b: what a second client sends during the return (a plausible landmark).
STRANGER_GOAL = BackTravelGoal(v=0.15, w=0.0, d=0.6, T=4.0, psi=0.0)
#: Why the one process rejects every back_travel goal (ros/mission_owner.REJECTED).
ONE_PROCESS_REJECTS = 'the one-process layer drives its return itself'
#: s of sim time watched after a terminal state (longer than a standstill + pi turn
#: where a turn could follow, finding 4a).
WATCH = 4.0
#: s of wall time a node restarted mid-phase (finding 7a) has to end the mission it cannot
#: continue, from its kill: starting a node on this loaded machine takes seconds; the
#: client's own backstop, rotation_timeout, is minutes.
RESTART_REACTION = 30.0
#: The layers the missions share (one after another through new_mission, module docstring):
#: the one process (logging to /rosout and its stream only: TestE limits its file sizes,
#: so it ends the chain) and the paper's layout.
ONE_PROCESS = LayerChain('one_process', env={'ROS_PYTHON_LOG_CONFIG_FILE': os.path.join(
    os.path.dirname(os.path.abspath(__file__)), 'stream_logging.conf')})
PAPER = LayerChain('paper', one_process=False)


def report(finding, text, *args):
    """Print the finding's outcome line (paths shown under the test's landmark root)."""
    line = text % args if args else text
    print('FINDING %s: %s' % (finding, line.replace(TEST_ROOT + os.sep, '')), flush=True)


def wait_connected(publisher, node, what):
    """Until ``node`` subscribes the topic of ``publisher`` and the publisher is connected
    to every subscriber (this node's own included)."""
    topic = publisher.resolved_name
    wait_for(lambda: node in subscribers_of(topic), '%s subscribes %s' % (node, topic), WALL_TIMEOUT)
    wait_for(lambda: publisher.get_num_connections() >= len(subscribers_of(topic)),
             '%s: connected to every subscriber' % what, WALL_TIMEOUT)


def odometry_burst(mission, make, rate=BURST_RATE, duration=BURST_TIME):
    """Publish ``rate`` x ``duration`` messages ``make()`` (nav_msgs/Odometry) on /odom beside
    the base's, ``rate`` Hz of sim time for ``duration`` s of sim time, as `rostopic pub -r`
    does, once connected to the layer of ``mission``; returns the count. Paced on the wall
    clock at the fake's rtf (a pace on this node's sim clock, which lags under load, sent
    a sixth of them). The publisher stays until the mission closes: unregistered at once,
    it would drop the messages still queued."""
    publisher = mission.keep(rospy.Publisher('/odom', Odometry, queue_size=1000))
    interval = 1.0 / (rate * mission.rtf)
    wait_connected(publisher, mission.owner, 'the /odom burst')
    count, next_time = int(round(rate * duration)), time.monotonic()
    for _ in range(count):
        publisher.publish(make())
        next_time += interval
        time.sleep(max(0.0, next_time - time.monotonic()))
    return count


def lose_vision(mission):
    """vision_lost from this node, once it is connected to every subscriber (`rostopic pub -1`,
    which lane_mission_closed_loop.test types, would wait 3 s of wall time for late ones)."""
    publisher = mission.keep(rospy.Publisher(names.VISION_LOST, Empty, queue_size=1))
    wait_connected(publisher, mission.owner, 'vision_lost')
    publisher.publish(Empty())


class BaseOdometry(object):
    """The latest /odom message of the fake base (not of a burst)."""

    def __init__(self):
        self.latest = None
        self.sub = rospy.Subscriber('/odom', Odometry, self._on_msg, queue_size=5)

    def _on_msg(self, msg):
        if msg._connection_header.get('callerid') == '/mobile_base':
            self.latest = msg


class Flood(object):
    """Publishes std_msgs/Empty on vision_lost at FLOOD_RATE Hz (wall) in a thread until :meth:`stop`."""

    def __init__(self, owner):
        self.publisher = rospy.Publisher(names.VISION_LOST, Empty, queue_size=100)
        wait_connected(self.publisher, owner, 'the vision_lost flood')
        self.count = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        next_time = time.monotonic()
        while not self._stop.is_set() and not rospy.is_shutdown():
            self.publisher.publish(Empty())
            self.count += 1
            next_time += 1.0 / FLOOD_RATE
            time.sleep(max(0.0, next_time - time.monotonic()))

    def stop(self):
        self._stop.set()
        self._thread.join(10.0)
        self.publisher.unregister()


class Stranger(object):
    """A second client of the layer's action: its goals as another node."""

    def __init__(self):
        self.client = GoalClient(names.BACK_TRAVEL, BackTravelAction)
        assert self.client.wait_for_server(rospy.Duration(WALL_TIMEOUT)), 'no back_travel server'

    def send(self, goal):
        """(GoalStatus, its text) of ``goal``."""
        self.client.send_goal(goal)
        assert self.client.wait_for_result(rospy.Duration(WALL_TIMEOUT)), 'no result for a stranger\'s goal'
        return self.client.get_state(), self.client.get_goal_status_text()


def set_route(route, landmarks, completed, callerid=None):
    """Call set_return_route as this node, or with ``callerid`` forged in the connection
    header (rospy lets a client's headers override it); returns (ok, message)."""
    rospy.wait_for_service(names.SET_RETURN_ROUTE, WALL_TIMEOUT)
    proxy = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute,
                               headers={'callerid': callerid} if callerid else None)
    response = proxy(header=Header(stamp=rospy.Time.now(), frame_id='odom'), route=route,
                     landmarks=[value for landmark in landmarks for value in landmark],
                     completed=completed)
    return response.ok, response.message


def turn_lines(mission):
    """rotate_pi's 'turning by' log lines of this mission."""
    return mission.logged('turning by')


def landmarks_beyond_limits(loaded):
    """Labels of the landmarks whose d no Kobuki covers in their T."""
    limits = Limits()
    return [label for label, landmark in zip(loaded.labels, loaded.landmarks)
            if limits.distance_problem(landmark.d, landmark.T)]


class MissionCase(unittest.TestCase):
    """A TestCase whose setUpClass plays one mission (``play``) and closes it after; on a
    ``CHAIN``'s layer the next case's mission goes on (unless ``ENDS_CHAIN`` or it failed)."""

    mission = None
    CHAIN = None
    ENDS_CHAIN = False

    @classmethod
    def setUpClass(cls):
        try:
            cls.play()
        except BaseException:
            if cls.mission is not None:
                cls.mission.close()
                cls.mission = None
            raise

    @classmethod
    def tearDownClass(cls):
        if cls.mission is not None:
            cls.mission.close(end_chain=cls.CHAIN is None or cls.ENDS_CHAIN)
            cls.mission = None

    @classmethod
    def settle(cls):
        """Until the robot stands (ground truth)."""
        run = cls.mission.run
        cls.mission.wait(lambda: run.truth.speed() < STOPPED_SPEED, 'the robot stands')

    @classmethod
    def counted_within(cls, count, since, seconds, what):
        """Until ``count()`` reaches ``since``, at most ``seconds`` of sim time (a check
        asserts it after); returns ``count()``."""
        m, until = cls.mission, rospy.get_time() + seconds
        m.wait(lambda: count() >= since or rospy.get_time() >= until, what)
        return count()

    @classmethod
    def idle_goal_sent(cls):
        """Finding 5a: IDLE_GOAL from a second client while idle, 2 s watched (``idle_goal``:
        its answer, ``idle_goal_motion``, ``idle_goal_commands``); returns the client."""
        m, stranger = cls.mission, Stranger()
        cls.idle_goal_time = rospy.get_time()
        cls.idle_goal = stranger.send(IDLE_GOAL)
        m.wait_sim(2.0)
        cls.idle_goal_motion = m.track.motion(cls.idle_goal_time, rospy.get_time())
        cls.idle_goal_commands = m.layer_commands()
        return stranger

    @classmethod
    def paper_turn(cls, label, before_trigger=lambda m: None):
        """A mission of the paper's layout nudged 0.3 m, ``before_trigger(mission)`` called,
        vision lost (from this node) and ``rotating`` reached (``cls.rotating_at``); returns
        (the mission, what ``before_trigger`` returned)."""
        m = cls.mission = FindingMission(label, chain=PAPER)
        m.wait_for_layer()
        m.nudge()
        m.wait(lambda: saved(m) >= 1, 'the saver saved a landmark of the nudge')
        extra = before_trigger(m)
        m.run.trigger_by_publisher()
        cls.rotating_at = m.wait_state('rotating')
        return m, extra

    @classmethod
    def drive_and_lose_vision(cls):
        """Record the whole mission, then the operator's vision_lost."""
        run = cls.mission.run
        cls.mission.wait_for_layer()
        run.play_mission(MISSION)
        lose_vision(cls.mission)

    def assert_home(self, what):
        m = self.mission
        self.assertEqual(m.run.state_names(), HOME_WALK, '%s: %s' % (what, m.final_reason()))
        self.assertLessEqual(self.error, NORMAL_ACCURACY, '%s: home %.3f m from the start (normal '
                             'accuracy %.3f m)' % (what, self.error, NORMAL_ACCURACY))


# --- findings 1, 2, 3, 4b, 4c, 5a, 5b, 6d on the one process: one mission, each at its phase ----

class TestA_OneProcessFaults(MissionCase):
    """The default layer (one process). While idle: a stray vision_lost (3) and a goal with
    d = 1000 on back_travel (5a); while recording: a 3 s burst of /odom at x = 1e6 at
    100 Hz (1); the trigger: a vision_lost flood at 1000 Hz until the return has begun
    (4b); during the return: 3 s of /odom with twist 1e6 at 100 Hz (2) and a second
    client's goal (5b); after home: vision_lost and a goal again (4c); all along: a
    symlink planted at landmarks.progress.yaml.tmp (6d). The one process serves
    back_travel only to reject every goal (ros/mission_owner.REJECTED)."""

    CHAIN = ONE_PROCESS

    @classmethod
    def play(cls):
        def plant(directory):
            cls.victim = os.path.join(directory, 'victim.txt')      # removed with the mission
            with open(cls.victim, 'w') as stream:
                stream.write('not the progress\n')
            cls.planted = os.path.join(directory, 'landmarks.progress.yaml.tmp')
            os.symlink(cls.victim, cls.planted)

        m = cls.mission = FindingMission('one_process_faults', prepare=plant, chain=ONE_PROCESS)
        run = m.run
        odometry = BaseOdometry()
        try:
            m.wait_idle()
            # finding 3: vision_lost while idle
            lose_vision(m)
            m.wait_sim(1.0)
            # finding 5a: another node's goal while idle
            stranger = cls.idle_goal_sent()
            # finding 1: the burst while recording
            m.wait_for_layer()
            cls.states_before_mission = run.state_names()
            run.start_operator(MISSION)
            run.wait_moved(0.3, 'recording before the burst')
            before = m.refused_odometry()
            cls.burst_count = odometry_burst(m, cls.absurd_odometry)
            cls.burst_refused = cls.counted_within(lambda: m.refused_odometry() - before, cls.burst_count,
                                                   3.0, 'the diagnostics count the burst refused')
            run.wait_for_operator(MISSION)
            # finding 4b: the trigger is a flood that lasts into the return
            flood = Flood(m.owner)
            try:
                returning = m.wait_state('returning')
                m.wait(lambda: run.truth.speed() > 0.02, 'the robot moves on the return')
                m.wait_sim(1.0)
            finally:
                flood.stop()
            cls.flood_count, cls.flood_until = flood.count, rospy.get_time() - returning
            # finding 2: impossible twists during the return
            before = m.refused_odometry()
            cls.twist_count = odometry_burst(m, lambda: fast_copy(odometry.latest))
            # finding 5b: a second client during the return
            cls.stranger_goal = stranger.send(STRANGER_GOAL)
            cls.during_return = m.state_time('home') is None
            cls.final, cls.final_at = m.wait_final()
            cls.rotating_at, cls.returning_at = m.state_time('rotating'), m.state_time('returning')
            cls.twist_refused = cls.counted_within(lambda: m.refused_odometry() - before, cls.twist_count,
                                                   3.0, 'the diagnostics count the twists refused')
            cls.settle()
            cls.error = run.error()
            # finding 4c: vision_lost after home, and a goal
            lose_vision(m)
            cls.home_goal = stranger.send(IDLE_GOAL)
            cls.still = m.still_after(cls.final_at, WATCH)
            cls.states = run.state_names()
        finally:
            odometry.sub.unregister()
        cls.loaded = run.recorded()
        with open(cls.victim) as stream:
            cls.victim_text = stream.read()
        cls.planted_target = os.readlink(cls.planted) if os.path.islink(cls.planted) else None
        cls.progress = load_progress(progress_path(m.landmark_file))
        cls.leftovers = [name for name in os.listdir(m.directory) if name.endswith('.tmp')
                         and name != os.path.basename(cls.planted)]
        cls.travelled = m.track.length(cls.returning_at, cls.final_at)
        cls.turned = abs(m.track.turned(cls.rotating_at, cls.returning_at))

    @staticmethod
    def absurd_odometry():
        msg = Odometry()
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = 'odom'
        msg.pose.pose.position.x = BURST_X
        msg.pose.pose.orientation.w = 1.0
        return msg

    def assert_rejected(self, answer, what):
        self.assertEqual(answer[0], GoalStatus.REJECTED, what)
        self.assertIn(ONE_PROCESS_REJECTS, answer[1], what)

    def test_finding1_odometry_burst_while_recording(self):
        loaded = self.loaded
        budget = RouteBudget(loaded.landmarks)
        report(1, '%d /odom messages at x = 1e6 (100 Hz, 3 s) while recording: %d refused; '
               '%d landmarks, %.2f m recorded, largest d %.3f m, %d beyond the limits; return '
               'travelled %.2f m (budget %.2f m); %s %.3f m from the start',
               self.burst_count, self.burst_refused, len(loaded.landmarks), loaded.total_distance,
               max(lm.d for lm in loaded.landmarks), len(landmarks_beyond_limits(loaded)),
               self.travelled, budget.limit, self.final, self.error)
        self.assertGreaterEqual(self.burst_refused, self.burst_count, 'a burst message was used')
        self.assertEqual(landmarks_beyond_limits(loaded), [])
        self.assertEqual(loaded.gaps, [], 'the burst broke the recording')
        self.assertAlmostEqual(loaded.total_distance, 2.3, delta=0.23, msg='recorded length')
        self.assertLessEqual(self.travelled, budget.limit)
        self.assert_home('finding 1')

    def test_finding2_impossible_twist_during_the_return(self):
        report(2, '%d /odom messages with twist 1e6 m/s (100 Hz, 3 s) during the return: %d '
               'refused; %s %.3f m from the start', self.twist_count, self.twist_refused,
               self.final, self.error)
        self.assertTrue(self.during_return, 'the return ended before the twist burst')
        self.assertGreaterEqual(self.twist_refused, self.twist_count)
        self.assert_home('finding 2')

    def test_finding3_stray_vision_lost_while_idle(self):
        report(3, 'vision_lost while idle: states then %s; %d landmarks, %.2f m recorded '
               '(the whole 2.3 m); %s %.3f m from the start: %s', self.states_before_mission,
               len(self.loaded.landmarks), self.loaded.total_distance, self.final, self.error,
               self.mission.final_reason())
        self.assertEqual(self.states_before_mission, ['idle', 'recording'])
        self.assertGreater(self.loaded.total_distance, 0.9 * 2.3, 'the recording stopped early')
        self.assert_home('finding 3')

    def test_finding4b_vision_lost_flood(self):
        report('4b', '%d vision_lost at %.0f Hz from vision loss until %.1f s into the return: '
               'states %s, turned %.2f rad before the return; %s %.3f m from the start',
               self.flood_count, FLOOD_RATE, self.flood_until, self.states, self.turned,
               self.final, self.error)
        self.assertGreater(self.flood_until, 0.0, 'the flood did not last into the return')
        self.assertAlmostEqual(self.turned, math.pi, delta=0.3, msg='not one pi turn')
        self.assert_home('finding 4b')

    def test_finding4c_vision_lost_after_home(self):
        late, moved, turned = self.still
        report('4c', 'vision_lost after home, a goal after home: %s (%s); states %s; %d motion '
               'commands after home; from home to %.0f s after them it moved %.4f m, turned %.4f rad',
               GoalStatus.to_string(self.home_goal[0]), self.home_goal[1], self.states, len(late),
               WATCH, moved, turned)
        self.assertEqual(self.final, 'home')
        self.assertEqual(self.states, HOME_WALK, 'a state after home')
        self.assert_rejected(self.home_goal, 'a goal after home')
        self.assertEqual(late, [], 'motion commanded after home')
        self.assertLess(moved, 0.005)
        self.assertLess(turned, 0.01)

    def test_finding5a_goal_while_idle(self):
        moved, turned = self.idle_goal_motion
        report('5a', 'goal d = 1000 m while idle: %s (%s); moved %.4f m, %d layer commands',
               GoalStatus.to_string(self.idle_goal[0]), self.idle_goal[1], moved,
               len(self.idle_goal_commands))
        self.assert_rejected(self.idle_goal, 'a goal while idle')
        self.assertEqual([c for c in self.idle_goal_commands if c[1] or c[2]], [])
        self.assertLess(moved, 0.005)

    def test_finding5b_second_client_during_the_return(self):
        report('5b', "a second client's goal during the return: %s (%s); %s %.3f m from the start",
               GoalStatus.to_string(self.stranger_goal[0]), self.stranger_goal[1], self.final, self.error)
        self.assertTrue(self.during_return, 'the return ended before the goal')
        self.assert_rejected(self.stranger_goal, 'a goal during the return')
        self.assert_home('finding 5b')

    def test_finding6d_planted_symlink_at_the_progress_tmp(self):
        report('6d', 'symlink %s -> %s planted: victim %r after the mission, the link %s; progress '
               'file %s; other temporary files left: %s', os.path.basename(self.planted),
               os.path.basename(self.victim), self.victim_text,
               'untouched' if self.planted_target == self.victim else 'CHANGED',
               'status %s' % self.progress.status if self.progress else 'missing', self.leftovers)
        self.assertEqual(self.victim_text, 'not the progress\n', 'the planted symlink was followed')
        self.assertEqual(self.planted_target, self.victim)
        self.assertIsNotNone(self.progress)
        self.assertEqual(self.progress.status, 'home')
        self.assertEqual(self.leftovers, [])


def fast_copy(msg):
    """``msg`` (the base's odometry) stamped now, with a twist no Kobuki makes."""
    copy = Odometry()
    copy.header.stamp, copy.header.frame_id = rospy.Time.now(), msg.header.frame_id
    copy.child_frame_id, copy.pose = msg.child_frame_id, msg.pose
    copy.twist.twist.linear.x = BURST_TWIST
    return copy


def saved(mission):
    """Landmarks the recorder reported saved so far (its last storage message)."""
    messages = mission.run.storage_msgs.snapshot()
    return messages[-1].landmarks if messages else 0


def unrecorded(mission, loaded):
    """m of the recording the file does not hold: the ground-truth path length from
    ``recording`` to ``rotating`` less the recorded sum of d (chords: within millimetres
    of the arcs on this mission)."""
    driven = mission.track.length(mission.state_time('recording'), mission.state_time('rotating'))
    return max(0.0, driven - loaded.total_distance)


# --- findings 4d, 5a, 5b, 5c, 6a on the paper's layout: its own topics, services, nodes ---------

class TestB_PaperLayoutFaults(MissionCase):
    """The paper's node layout (one_process:=false). While idle: a goal with d = 1000 to
    back_travel_server (5a); while recording: landmark_saver killed (SIGKILL) and started
    again 10 s later (6a: it continues the mission's file and catches up on the samples it
    missed, no gap); while rotating, before the turn: rotation_done true (4d); during the
    return: a second client's goal (5b), set_return_route with a NaN and a 1e6 anchor and
    completed 99, as a stranger and with the owner's callerid forged (5c); after home: a
    goal again (4c)."""

    SAVER = 'landmark_saver'
    SAVER_DOWN = 10.0           # s (sim) without a saver, as in the issue (10-18 s)
    CHAIN = PAPER

    @classmethod
    def play(cls):
        m = cls.mission = FindingMission('paper_faults', chain=PAPER, fresh=True)
        run = m.run
        m.wait_idle()
        # finding 5a: another node's goal while idle (the recording starts once this node
        # takes the samples: wait_for_layer)
        stranger = cls.idle_goal_sent()
        m.wait_for_layer()
        rospy.wait_for_service(names.SET_RETURN_ROUTE, WALL_TIMEOUT)
        # finding 6a: the saver killed mid-recording and restarted
        cls.file_before = os.path.realpath(m.landmark_file)
        run.start_operator(MISSION)
        m.wait(lambda: saved(m) >= 4, 'the saver saved 4 landmarks')
        kill_node('/' + cls.SAVER)
        cls.saved_before = saved(m)
        cls.killed_at = rospy.get_time()
        m.wait_sim(cls.SAVER_DOWN)
        m.start_node('landmark_saver.py', cls.SAVER)
        m.wait(lambda: [t for t, msg in list(run.storage_msgs.items)
                        if t > cls.killed_at and msg.landmarks > cls.saved_before],
               'the restarted saver saves')
        cls.restarted_at = [t for t, msg in list(run.storage_msgs.items) if t > cls.killed_at][0]
        run.wait_for_operator(MISSION)
        # the spoofed routes (built on the recording: one section per landmark sent)
        recorded = list(reversed(run.recorded().landmarks))
        far = route_message(build_route(list(reversed(recorded)), (1e6, 1e6)))
        nan = route_message(build_route(list(reversed(recorded)), (1e6, 1e6)))
        nan.x = [float('nan')] + list(nan.x[1:])
        # finding 4d: rotation_done true before rotate_pi turned (the trigger from this node:
        # `rostopic pub -1` blocks for 3 s, the turn would be over)
        done = rospy.Publisher(names.ROTATION_DONE, Bool, queue_size=1)
        wait_connected(done, m.owner, 'rotation_done')
        run.trigger_by_publisher()
        cls.rotating_at = m.wait_state('rotating')
        done.publish(Bool(data=True))
        cls.handover_refused = m.wait_logged('rotation_done true refused')
        cls.refused_at = rospy.get_time()
        done.unregister()
        m.wait_state('returning')
        m.wait(lambda: run.truth.speed() > 0.02, 'the robot moves on the return')
        # finding 5b: a second client during the return; 5c: spoofed routes
        cls.stranger_goal = stranger.send(STRANGER_GOAL)
        cls.route_answers = [
            ('stranger, NaN anchor', set_route(nan, recorded, 0)),
            ('owner forged, NaN anchor', set_route(nan, recorded, 0, m.owner)),
            ('owner forged, anchor at 1e6', set_route(far, recorded, 0, m.owner)),
            ('owner forged, completed 99', set_route(far, recorded, 99, m.owner))]
        cls.during_return = m.state_time('home') is None
        cls.final, cls.final_at = m.wait_final()
        cls.returning_at = m.state_time('returning')
        cls.settle()
        cls.error = run.error()
        # finding 4c: a goal after home
        cls.home_goal = stranger.send(IDLE_GOAL)
        cls.still = m.still_after(cls.final_at, WATCH)
        cls.landmarks = len(run.recorded().landmarks)
        cls.loaded = run.recorded()
        cls.file_after = os.path.realpath(m.landmark_file)
        cls.files = sorted(name for name in os.listdir(m.directory) if name.startswith('landmarks-'))
        cls.warnings = [msg.warnings for msg in m.status.snapshot() if msg.warnings]
        cls.missing = unrecorded(m, cls.loaded)
        cls.samples = len(run.samples.snapshot())      # every sample the publisher published
        cls.samples_while_down = len([t for t, _ in list(run.samples.items)
                                      if cls.killed_at < t < cls.restarted_at])

    def test_finding4c_goal_after_home(self):
        late, moved, turned = self.still
        report('4c', 'paper layout: a goal after home: %s (%s); %d motion commands after home; '
               'moved %.4f m, turned %.4f rad; rotate_pi turned %d time(s)',
               GoalStatus.to_string(self.home_goal[0]), self.home_goal[1], len(late), moved, turned,
               len(turn_lines(self.mission)))
        self.assertEqual(self.final, 'home')
        self.assertEqual(self.home_goal[0], GoalStatus.REJECTED)
        self.assertIn('the mission is home', self.home_goal[1])
        self.assertEqual(late, [], 'motion commanded after home')
        self.assertLess(moved, 0.005)
        self.assertLess(turned, 0.01)
        self.assertEqual(len(turn_lines(self.mission)), 1)

    def test_finding4d_rotation_done_true_before_the_turn(self):
        track = self.mission.track
        before = abs(track.turned(self.rotating_at, self.refused_at))
        at_return = abs(track.turned(self.rotating_at, self.returning_at))
        report('4d', 'rotation_done true %.2f s after rotating, the robot turned %.3f rad: %r; '
               'returning only after the turn (%.3f rad); %d turn(s); %s %.3f m from the start',
               self.refused_at - self.rotating_at, before, self.handover_refused.split(': ', 1)[-1],
               at_return, len(turn_lines(self.mission)), self.final, self.error)
        self.assertLess(before, 0.1, 'the hand-over was not before the turn')
        self.assertAlmostEqual(at_return, math.pi, delta=0.3, msg='returning before the turn ended')
        self.assertEqual(len(turn_lines(self.mission)), 1)
        self.assert_home('finding 4d')

    def test_finding5a_goal_while_idle(self):
        moved, turned = self.idle_goal_motion
        report('5a', 'paper layout: goal d = 1000 m while idle: %s (%s); moved %.4f m, %d layer commands',
               GoalStatus.to_string(self.idle_goal[0]), self.idle_goal[1], moved,
               len(self.idle_goal_commands))
        self.assertEqual(self.idle_goal[0], GoalStatus.REJECTED)
        # 'idle', or 'None' when the goal reaches the server before the owner's latched state
        self.assertRegex(self.idle_goal[1], r'the mission is (idle|None), not returning')
        self.assertEqual([c for c in self.idle_goal_commands if c[1] or c[2]], [])
        self.assertLess(moved, 0.005)

    def test_finding5b_second_client_during_the_return(self):
        m = self.mission
        # actionlib goal ids start with the sending node's name
        outcomes = [r.status.status for r in m.run.results.snapshot()
                    if r.status.goal_id.id.startswith(m.owner + '-')]
        report('5b', "paper layout: a second client's goal during the return: %s (%s); the layer's "
               '%d goals: %s; %s %.3f m from the start', GoalStatus.to_string(self.stranger_goal[0]),
               self.stranger_goal[1], len(outcomes), sorted(set(GoalStatus.to_string(s) for s in outcomes)),
               self.final, self.error)
        self.assertTrue(self.during_return, 'the return ended before the goal')
        self.assertEqual(self.stranger_goal[0], GoalStatus.REJECTED)
        self.assertIn('only %s sends back-travel goals' % m.owner, self.stranger_goal[1])
        self.assertEqual(outcomes, [GoalStatus.SUCCEEDED] * self.landmarks,
                         "the layer's return did not drive every landmark")
        self.assert_home('finding 5b')

    def test_finding5c_spoofed_return_routes(self):
        for what, (ok, message) in self.route_answers:
            report('5c', 'set_return_route (%s): ok=%s, %r', what, ok, message)
        report('5c', '%s %.3f m from the start', self.final, self.error)
        self.assertTrue(self.during_return, 'the return ended before the spoofed routes')
        expected = ['only %s sets the return route' % self.mission.owner, 'finite numbers',
                    'from where the route continues', 'completed 99 of only']
        for (what, (ok, message)), text in zip(self.route_answers, expected):
            self.assertFalse(ok, what)
            self.assertIn(text, message, what)
        self.assert_home('finding 5c')

    def test_finding6a_restarted_saver_continues_the_mission_file(self):
        m, loaded = self.mission, self.loaded
        succeeded = m.run.goal_outcomes().count(GoalStatus.SUCCEEDED)
        late, moved, turned = self.still
        report('6a', 'landmark_saver killed after %d landmarks, saving again %.1f s (sim) later: '
               'mission files %s, %d landmarks, gaps %s, %d samples published (%d while no saver '
               'ran); %d goals driven; warnings %r; %s %.3f m from the start (%.3f m of the path '
               'not in the file); after it %d motion commands, moved %.4f m',
               self.saved_before, self.restarted_at - self.killed_at, self.files, len(loaded.landmarks),
               [gap.before for gap in loaded.gaps], self.samples, self.samples_while_down, succeeded,
               self.warnings[-1:], self.final, self.error, self.missing, len(late), moved)
        self.assertEqual(self.file_after, self.file_before, 'the restarted saver started a new file')
        self.assertEqual(len(self.files), 1)
        self.assertGreaterEqual(self.samples_while_down, 3, 'the saver was not down long enough')
        self.assertEqual(len(loaded.landmarks), self.samples,
                         'the file does not hold a landmark for every sample published')
        self.assertEqual(loaded.gaps, [], 'the restarted saver did not catch up')
        self.assertEqual(succeeded, len(loaded.landmarks), 'not every landmark was driven back')
        self.assertEqual(self.warnings, [], 'a complete recording reported as degraded')
        self.assertEqual(m.run.state_names(), HOME_WALK, m.final_reason())
        self.assertLess(self.missing, 0.02, 'path missing from the file')
        self.assertLessEqual(self.error, NORMAL_ACCURACY)
        self.assertEqual(late, [])
        self.assertLess(moved, 0.005)


# --- finding 4a: rotation_done false during the standstill (the paper's node layout) ----------

class TestC_RotationDoneFalse(MissionCase):
    """rotation_done false while the robot stands still for the heading correction:
    aborted, and no pi turn after it."""

    CHAIN = PAPER

    @classmethod
    def play(cls):
        def connect(m):
            publisher = rospy.Publisher(names.ROTATION_DONE, Bool, queue_size=1)
            wait_connected(publisher, m.owner, 'rotation_done')
            return publisher
        m, done = cls.paper_turn('rotation_false', connect)
        done.publish(Bool(data=False))
        cls.final, cls.final_at = m.wait_final()
        done.unregister()
        cls.reason = m.final_reason()
        cls.still = m.still_after(cls.final_at, 3 * WATCH)

    def test_finding4a_rotation_done_false_during_the_standstill(self):
        late, moved, turned = self.still
        report('4a', 'rotation_done false %.2f s after rotating: %s (%s); in the %.0f s after: %d '
               'motion commands, moved %.4f m, turned %.4f rad, %d turn(s)', self.final_at - self.rotating_at,
               self.final, self.reason, 3 * WATCH, len(late), moved, turned,
               len(turn_lines(self.mission)))
        self.assertEqual(self.final, 'aborted')
        self.assertIn('pi rotation failed', self.reason)
        self.assertEqual(late, [])
        self.assertLess(turned, 0.01)
        self.assertEqual(turn_lines(self.mission), [])


# --- finding 6b: the landmark file cannot be written any more (a full disk) ------------------

class TestE_WriteFailure(MissionCase):
    """Mid-recording, the layer process may not grow a file beyond the landmark file's size
    (RLIMIT_FSIZE set on the running process: every later append fails with EFBIG, the
    path of ENOSPC). The layer logs to /rosout and its stream only (no log file, which the
    limit would hit first). Issue 28: the mission that cannot come back ends at the vision
    loss, standing still: no standstill, no pi turn (ground truth). The limit stays on the
    process: the chain ends here."""

    CHAIN, ENDS_CHAIN = ONE_PROCESS, True

    @classmethod
    def play(cls):
        m = cls.mission = FindingMission('write_failure', chain=ONE_PROCESS)
        run = m.run
        m.wait_for_layer()
        run.start_operator(MISSION)
        m.wait(lambda: saved(m) >= 6, 'the saver saved 6 landmarks')
        cls.file = os.path.realpath(m.landmark_file)
        limit_file_size(node_pid(m.owner), os.path.getsize(cls.file))
        cls.limited_at, cls.saved_before = rospy.get_time(), saved(m)
        run.wait_for_operator(MISSION)
        cls.lost_at = rospy.get_time()
        lose_vision(m)
        cls.final, cls.final_at = m.wait_final()
        recording = '%s: recording' % m.owner.lstrip('/')     # the one process's recording status
        m.wait(lambda: m.diagnostics.level(recording) == DiagnosticStatus.ERROR,
               'the diagnostics report the recording lost')
        cls.settle()
        cls.error = run.error()
        cls.still = m.still_after(cls.final_at, WATCH)
        cls.storage = run.storage_msgs.snapshot()[-1]
        cls.loaded = load_landmarks(cls.file)
        cls.lost_lines = m.logged('LANDMARK LOST')
        cls.saver_status = m.diagnostics.status(recording)
        cls.warnings = [msg.warnings for msg in m.status.snapshot() if msg.warnings]
        cls.level = (m.diagnostics.level(recording),
                     m.diagnostics.level('%s: mission' % m.owner.lstrip('/')))
        cls.displaced, cls.turned = m.track.motion(cls.lost_at, cls.final_at + WATCH)
        cls.turns = turn_lines(m)

    def test_finding6b_write_failure_is_reported_and_nothing_drives_on_a_lost_end(self):
        m, loaded = self.mission, self.loaded
        late, moved, turned = self.still
        report('6b', 'writes refused after %d landmarks: storage lost=%d (%.3f m, %.2f rad) error %r; '
               '%d ERROR log line(s) %r; diagnostics levels (saver, mission) %s, saver %r; mission '
               'warnings %r; the file holds %d whole landmarks (torn: %s); states %s: %r %.1f s (sim) '
               'after the vision loss; since the loss moved %.4f m, turned %.4f rad (%d turn lines); '
               'after it %d motion commands, moved %.4f m', self.saved_before, self.storage.lost,
               self.storage.lost_distance, self.storage.lost_turn, self.storage.error,
               len(self.lost_lines), (self.lost_lines or [''])[0].split(': ', 1)[-1],
               self.level, self.saver_status and self.saver_status[0], (self.warnings or [''])[-1],
               len(loaded.landmarks), [w for w in loaded.warnings if 'torn' in w], m.run.state_names(),
               m.final_reason(), self.final_at - self.lost_at, self.displaced, self.turned,
               len(self.turns), len(late), moved)
        self.assertGreater(self.storage.lost, 0, 'no landmark was lost: the limit did not bite')
        self.assertGreater(self.storage.lost_distance, 0.1, 'the lost landmarks were not driven')
        self.assertIn(self.file, self.storage.error)
        self.assertTrue(self.lost_lines, 'no ERROR in the log')
        self.assertIn('lost', self.saver_status[0])
        self.assertEqual(self.level[0], DiagnosticStatus.ERROR)
        self.assertTrue(self.warnings and 'RECORDING DAMAGED' in self.warnings[-1])
        self.assertEqual(len(loaded.landmarks), self.storage.landmarks, 'the file lost whole landmarks')
        self.assertEqual([w for w in loaded.warnings if 'torn' in w], [])
        # the end of the path is lost: the way back from where the robot is is unknown, and the
        # mission ends where vision was lost, before the standstill and the pi turn
        self.assertEqual(self.final, 'aborted', 'it drove on what is left of the record')
        for text in ('could not be written', 'not travelling back', self.file):
            self.assertIn(text, m.final_reason())
        self.assertLess(self.turned, 0.1, 'the robot turned after the vision loss')
        self.assertLess(self.displaced, 0.05, 'the robot drove after vision loss')
        self.assertEqual(self.turns, [], 'rotate_pi began a turn')
        self.assertEqual(late, [])
        self.assertLess(moved, 0.005)


def limit_file_size(pid, size):
    """No file of process ``pid`` may grow beyond ``size`` bytes (RLIMIT_FSIZE, soft; None:
    no limit again): its writes beyond fail with EFBIG, as on a full disk with ENOSPC."""
    hard = resource.prlimit(pid, resource.RLIMIT_FSIZE)[1]
    resource.prlimit(pid, resource.RLIMIT_FSIZE, (resource.RLIM_INFINITY if size is None else size, hard))


# --- issue 28: a storage that cannot hold a file, or holds few minutes, at start -------------

class SmallDisk(MissionCase):
    """The landmark directory is a tmpfs of SIZE KiB (mounted by the test: root only; skipped
    where mounting is not allowed), filled with FILL KiB before the layer starts."""

    SIZE = FILL = 0

    @classmethod
    def setUpClass(cls):
        try:
            super(SmallDisk, cls).setUpClass()
        except BaseException:
            cls.unmount()
            raise

    @classmethod
    def tearDownClass(cls):
        super(SmallDisk, cls).tearDownClass()
        cls.unmount()

    @classmethod
    def prepare(cls, directory):
        mounted = subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=%dk' % cls.SIZE, 'tmpfs', directory],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        if mounted.returncode != 0:
            raise unittest.SkipTest('cannot mount a tmpfs here: %s' % mounted.stdout.strip())
        cls.mounted = directory
        if cls.FILL:
            with open(os.path.join(directory, 'filler'), 'wb') as stream:
                try:
                    stream.write(b'\0' * (cls.FILL << 10))
                except OSError:
                    pass                # full
        info = os.statvfs(directory)
        cls.free = info.f_bavail * info.f_frsize

    @classmethod
    def unmount(cls):
        directory = getattr(cls, 'mounted', None)
        if directory:
            subprocess.run(['umount', directory], check=False)
            shutil.rmtree(directory, ignore_errors=True)
            cls.mounted = None


class TestL_FullAtStart(SmallDisk):
    """The landmark directory's file system is full when the layer starts: it cannot hold a
    mission file. The layer ends with one FATAL line naming the file and the error, and
    leaves no symlink to nothing."""

    SIZE = FILL = 16

    @classmethod
    def play(cls):
        m = cls.mission = FindingMission('full_at_start', prepare=cls.prepare)
        m.wait(lambda: m.layer.process.poll() is not None, 'the layer exits')
        cls.output = m.layer.output()
        cls.fatal = [line for line in cls.output.splitlines() if '[FATAL]' in line]
        cls.link = m.landmark_file
        cls.entries = sorted(os.listdir(m.directory))
        cls.commands = [c for c in m.layer_commands() if c[1] or c[2]]
        cls.uncaught = [line for line in cls.output.splitlines() if line.startswith('Traceback')]

    def test_issue28_a_full_storage_at_start_is_one_fatal_line_and_no_dangling_symlink(self):
        report('28 full', '%d bytes free: %d FATAL line(s) %r; directory then %s; %d motion commands; '
               'traceback: %s', self.free, len(self.fatal), self.fatal, self.entries, len(self.commands),
               bool(self.uncaught))
        self.assertEqual(len(self.fatal), 1, self.output[-3000:])
        for text in (self.mission.directory, 'No space left on device (ENOSPC)'):
            self.assertIn(text, self.fatal[0])
        self.assertFalse(os.path.islink(self.link) and not os.path.exists(self.link),
                         'a symlink to nothing at %s' % self.link)
        self.assertEqual(self.entries, ['filler'])
        self.assertEqual(self.commands, [])
        self.assertEqual(self.uncaught, [], self.output[-3000:])


class TestM_LowSpaceAtStart(SmallDisk):
    """The landmark directory's file system holds 32 KiB: fewer than LOW_SPACE_MINUTES of
    recording at the rate assumed before one is measured. The saver warns when it opens the
    file, and the mission status carries the warning from the first landmark on."""

    SIZE = 32

    @classmethod
    def play(cls):
        m = cls.mission = FindingMission('low_space', prepare=cls.prepare)
        m.wait_for_layer()
        cls.warned = m.wait_logged('LOW SPACE')
        m.wait(lambda: [msg for msg in m.status.snapshot() if 'LOW SPACE' in msg.warnings],
               'the mission status carries the low-space warning')
        cls.status = [msg for msg in m.status.snapshot() if 'LOW SPACE' in msg.warnings][0]
        m.wait(lambda: m.run.storage_msgs.snapshot(), 'a storage message reaches this node')
        cls.storage = m.run.storage_msgs.snapshot()[0]
        cls.states = m.run.state_names()

    def test_issue28_low_space_is_warned_at_start(self):
        report('28 low space', '%d bytes free: %r; status %s: %r', self.free, self.warned,
               self.status.state, self.status.warnings)
        self.assertIn(self.mission.directory, self.warned)
        self.assertIn('min of recording', self.warned)
        self.assertIn(self.status.state, ('idle', 'recording'))     # with the first storage report
        self.assertIn('LOW SPACE', self.storage.space_warning, 'not warned with the first storage report')
        self.assertEqual(self.states[-1], 'recording')


# --- finding 6c: a landmark_file that is a directory -------------------------------------------

class TestF_LandmarkFileDirectory(MissionCase):
    """landmark_file names a directory (with a file in it): the layer refuses it by name and
    leaves it as it was; nothing is recorded or driven."""

    @classmethod
    def play(cls):
        def plant(directory):
            os.makedirs(os.path.join(directory, 'landmarks.yaml'))
            with open(os.path.join(directory, 'landmarks.yaml', 'keep.txt'), 'w') as stream:
                stream.write('keep\n')

        m = cls.mission = FindingMission('directory', prepare=plant)
        m.wait(lambda: m.layer.process.poll() is not None, 'the layer exits on the directory')
        cls.output = m.layer.output()
        cls.refusal = [line for line in cls.output.splitlines() if 'is a directory' in line]
        cls.entries = sorted(os.listdir(m.directory))
        cls.inside = sorted(os.listdir(m.landmark_file)) if os.path.isdir(m.landmark_file) else None
        cls.states = m.run.state_names()
        cls.commands = [c for c in m.layer_commands() if c[1] or c[2]]
        # an uncaught exception prints its traceback from the start of a line; rospy's own
        # warning of a connection torn down while it was being made (the process exiting)
        # carries one after its message, and is not the layer's
        cls.uncaught = [line for line in cls.output.splitlines() if line.startswith('Traceback')]

    def test_finding6c_a_directory_landmark_file_is_refused_by_name(self):
        report('6c', 'landmark_file is a directory: %r; directory now %s holding %s; states %s; '
               '%d motion commands; traceback: %s', (self.refusal or [''])[0], self.entries,
               self.inside, self.states, len(self.commands), bool(self.uncaught))
        self.assertTrue(self.refusal, 'the refusal does not name the directory')
        self.assertIn(self.mission.landmark_file, self.refusal[0])
        self.assertEqual(self.entries, ['landmarks.yaml'], 'the directory was renamed or a file made')
        self.assertEqual(self.inside, ['keep.txt'])
        self.assertNotIn('recording', self.states)
        self.assertEqual(self.commands, [])
        self.assertEqual(self.uncaught, [], 'a traceback instead of a refusal:\n%s' % self.output[-3000:])


# --- finding 7a: rotate_pi killed mid-turn and restarted (the paper's node layout) ------------

class TestG_RotatePiRestart(MissionCase):
    """rotate_pi killed (SIGKILL) mid-turn and started again: it cannot know how far the robot
    turned, so the mission ends aborted at once, and nothing moves after."""

    CHAIN = PAPER

    @classmethod
    def play(cls):
        m, _ = cls.paper_turn('rotate_pi_restart')
        m.wait(lambda: abs(m.track.turned(cls.rotating_at, rospy.get_time())) > 0.4 and
               [c for c in m.layer_commands() if c[3] == '/rotate_pi' and c[2] != 0.0],
               'rotate_pi turns 0.4 rad')
        kill_node('/rotate_pi')
        cls.killed_at, cls.killed_wall = rospy.get_time(), time.monotonic()
        cls.turned_at_kill = m.track.turned(cls.rotating_at, cls.killed_at)
        m.start_node('rotate_pi.py', 'rotate_pi')
        cls.final, cls.final_at = m.wait_final()
        cls.reaction_wall = time.monotonic() - cls.killed_wall
        cls.reason = m.final_reason()
        cls.still = m.still_after(cls.final_at, WATCH)

    def test_finding7a_rotate_pi_restarted_mid_turn_ends_the_mission(self):
        late, moved, turned = self.still
        report('7a', 'rotate_pi killed %.2f rad into the turn, restarted: %s %.1f s (sim; %.1f s '
               'wall) after the kill: %r; after it %d motion commands, moved %.4f m, turned %.4f rad',
               self.turned_at_kill, self.final, self.final_at - self.killed_at, self.reaction_wall,
               self.reason, len(late), moved, turned)
        self.assertGreater(abs(self.turned_at_kill), 0.2, 'not killed mid-turn')
        self.assertEqual(self.final, 'aborted')
        self.assertIn('pi rotation failed', self.reason)
        self.assertLess(self.reaction_wall, RESTART_REACTION, 'the mission hung in rotating')
        self.assertEqual(late, [])
        self.assertLess(moved, 0.005)
        self.assertLess(turned, 0.01)


# --- finding 7b: back_travel_client restarted mid-return with a bad progress file -------------

class ClientRestart(MissionCase):
    """back_travel_client killed (SIGKILL) mid-return, its progress file tampered with
    (:meth:`tamper`), the client started again: the return cannot trust its progress, so
    the mission ends aborted naming the file, and nothing moves after."""

    LABEL = None
    CHAIN, ENDS_CHAIN = PAPER, True

    @classmethod
    def play(cls):
        m = cls.mission = FindingMission(cls.LABEL, chain=PAPER)
        cls.drive_and_lose_vision()
        m.wait_state('returning')
        cls.progress_file = progress_path(m.landmark_file)

        def completed():
            try:
                progress = load_progress(cls.progress_file)
            except Exception:           # being replaced: read it again
                return 0
            return progress.completed if progress and progress.status == 'returning' else 0

        m.wait(lambda: completed() >= 2, '2 landmarks driven back')
        kill_node('/back_travel_client')
        cls.killed_at = rospy.get_time()
        cls.tamper(cls.progress_file)
        states_before, statuses_before = len(m.run.states), len(m.status)
        m.start_node('back_travel_client.py', 'back_travel_client')
        m.wait(lambda: m.run.state_names()[states_before:], 'the restarted client publishes its state')
        m.wait(lambda: m.status.snapshot()[statuses_before:], 'the restarted client publishes its status')
        cls.states_after = m.run.state_names()[states_before:]
        cls.final_at = [t for t, msg in list(m.run.states.items)[states_before:]][0]
        cls.reason = m.status.snapshot()[statuses_before:][-1].reason
        cls.orphan = m.track.length(cls.killed_at, cls.final_at)
        cls.still = m.still_after(cls.final_at, WATCH)

    def check(self, finding, what, *texts):
        late, moved, turned = self.still
        report(finding, '%s in the progress file, client restarted mid-return: states %s: %r; the '
               'goal in flight drove %.3f m meanwhile; after it %d motion commands, moved %.4f m',
               what, self.states_after, self.reason, self.orphan, len(late), moved)
        self.assertEqual(self.states_after, ['aborted'])
        for text in (self.progress_file,) + texts:
            self.assertIn(text, self.reason)
        self.assertEqual(late, [])
        self.assertLess(moved, 0.005)


class TestH_CorruptProgress(ClientRestart):
    LABEL = 'corrupt_progress'

    @staticmethod
    def tamper(path):
        with open(path, 'w') as stream:
            stream.write('status: returning\ncompleted: [4\n')      # torn: not YAML

    def test_finding7b_corrupt_progress_on_a_client_restart(self):
        self.check('7b', 'torn YAML', 'not a YAML text')


# --- finding 7d: the master restarted mid-recording ------------------------------------------

def free_port():
    with socket.socket() as probe:
        probe.bind(('localhost', 0))
        return probe.getsockname()[1]


class PrivateMaster(object):
    """A rosmaster of the test's own on ``port`` (:meth:`restart`: killed, started again)."""

    def __init__(self, port):
        self.uri = 'http://localhost:%d' % port
        self.port, self.process = port, None
        self.start()

    def start(self):
        self.process = subprocess.Popen([shutil.which('rosmaster'), '--core', '-p', str(self.port), '-w', '3'],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        start_new_session=True)

        def up():
            try:
                return bool(rosgraph.Master('/safety_findings', master_uri=self.uri).getPid())
            except Exception:       # not accepting connections yet
                return False
        wait_for(up, 'the private master at %s answers' % self.uri, WALL_TIMEOUT)

    def stop(self):
        if self.process.poll() is None:
            self.process.terminate()
            self.process.wait(WALL_TIMEOUT)

    def restart(self):
        self.stop()
        self.start()

    def has_param(self, name):
        return rosgraph.Master('/safety_findings', master_uri=self.uri).hasParam(name)


class TestJ_MasterRestart(unittest.TestCase):
    """The fake TurtleBot and the layer on a master of their own; the master is restarted
    (terminated, started again on its port) mid-recording. The nodes keep the connections
    they made, but the new master knows none of them. The one process needs no new
    connection: its diagnostics wait out the outage, the mission goes on and comes home
    (master_restart_probe.py watches it from inside that world). The paper's layout's action
    client, made when the return starts, would find no server: aborted, the robot where the
    pi turn left it (before issue 30's switch, the default's outcome)."""

    @classmethod
    def setUpClass(cls):
        LayerChain.stop_active()
        rtf = float(rospy.get_param('/mobile_base/rtf'))
        master = PrivateMaster(free_port())
        env = {'ROS_MASTER_URI': master.uri}
        directory = mission_directory('master_restart')
        launch = probe = None
        try:
            launch = LayerLaunch('master_restart', directory, rtf, env=env, fake=True)
            wait_for(lambda: master.has_param('/use_sim_time') and master.has_param('/blind_navigation/recorder'),
                     'the private launch set its params', WALL_TIMEOUT)
            probe = subprocess.Popen([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                                   'master_restart_probe.py')],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, universal_newlines=True,
                                     env=dict(os.environ, **env))
            events = queue.Queue()
            threading.Thread(target=cls.read_events, args=(probe.stdout, events), daemon=True).start()
            cls.restart_at = cls.next_event(events, 'restart_master')['at']
            master.restart()
            probe.stdin.write('restarted\n')
            probe.stdin.flush()
            cls.summary = cls.next_event(events, 'summary')
            cls.output = launch.output()
        finally:
            if probe is not None and probe.poll() is None:
                probe.terminate()
                probe.wait(WALL_TIMEOUT)
            if launch is not None:
                launch.stop()
            master.stop()
            shutil.rmtree(directory, ignore_errors=True)

    @staticmethod
    def read_events(stream, events):
        for line in stream:
            if line.startswith('PROBE '):
                events.put(json.loads(line[len('PROBE '):]))
        events.put({'event': 'probe ended'})

    @staticmethod
    def next_event(events, name):
        deadline = time.monotonic() + 3 * WALL_TIMEOUT
        while True:
            try:
                event = events.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise AssertionError('master_restart_probe: no %s event' % name)
            if event['event'] == name:
                return event
            if event['event'] == 'probe ended':
                raise AssertionError('master_restart_probe ended before %s (see its output)' % name)

    def test_finding7d_master_restart_mid_recording_ends_aborted(self):
        s = self.summary
        report('7d', 'master restarted %.1f s (sim) into the recording: states %s: %r, %.3f m from the '
               'start; turned %.2f rad after vision loss, moved %.3f m from there in all; after %s: %d '
               'motion commands, moved %.4f m, turned %.4f rad', self.restart_at - s['recording_at'],
               s['states'], s['reason'], s['home_error'], s['turned_after_loss'], s['displaced'],
               s['states'][-1], s['late'], s['moved'], s['turned'])
        self.assertEqual(s['states'], HOME_WALK, s['reason'])
        self.assertLessEqual(s['home_error'], NORMAL_ACCURACY, 'home %.3f m from the start (normal '
                             'accuracy %.3f m)' % (s['home_error'], NORMAL_ACCURACY))
        self.assertEqual(s['late'], 0)
        self.assertLess(s['moved'], 0.005)
        self.assertLess(s['turned'], 0.01)


def tearDownModule():
    LayerChain.stop_active()


def selected():
    """The test cases of this module, those of a chain together (one-process, then paper),
    in name order; only those ``~only`` names, if set."""
    only = [name for name in rospy.get_param('~only', '').split(',') if name]
    module = sys.modules[__name__]
    chains = [ONE_PROCESS, PAPER, None]
    cases = sorted((name for name in dir(module) if name.startswith('Test')),
                   key=lambda name: (chains.index(getattr(getattr(module, name), 'CHAIN', None)), name))
    unknown = sorted(set(only) - set(cases))
    if unknown:
        raise ValueError('~only names unknown test cases %s (known: %s)' % (unknown, cases))
    return unittest.TestSuite(unittest.TestLoader().loadTestsFromTestCase(getattr(module, name))
                              for name in cases if not only or name in only)


if __name__ == '__main__':
    rospy.init_node('test_safety_findings')
    rostest.rosrun('blind_navigation', 'safety_findings', __name__ + '.selected')
