#!/usr/bin/env python3
"""rostest: the Kobuki driver's odometry reset during a mission (issue 21 item 6)
on the fake TurtleBot, blind_navigation.launch as a user starts it.

Once the mission is in ``~reset_state`` (recording or returning) and the robot
(ground truth) has driven ``~reset_after`` m in it, this node sends
``/mobile_base/commands/reset_odometry`` (kobuki_node's: the fake zeroes pose,
gyro heading and wheel angles; the twist goes on), after asking for
``~silence`` s without odometry first if > 0 (a restarted driver: silent, then
from the origin). Asserted: /odom really restarted near the origin; the
mission ends ``~expect``: ``home`` within ``~max_error_share`` of the path
driven while recording (ground truth), or ``aborted`` with a reason naming the
reset; never ``home`` farther off; the robot stands still at the end; the
layer logged the reset as re-anchored (home) or not (aborted); the file has
a gap, naming the reset, only where a reset during the recording was not
carried across.

With ``~restart`` the fake restarts instead (``/mobile_base/restart``: /clock
from 0 and odometry from the origin, as a kill and relaunch; issue 28 item 4),
and the test starts the fake and the layer itself (findings_rig.LayerLaunch:
their output kept) to assert also: the samples and the landmarks go on after
the restart, each loop warned once that the time moved back, the abort names
the clock, and no log of the run holds a thread's traceback.
"""
import glob
import math
import os
import sys
import threading
import unittest

import rospkg
import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from std_msgs.msg import Empty, Float64

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from findings_rig import LayerLaunch, mission_directory  # noqa: E402
from mission_tools import STOPPED_SPEED, MissionRun, PathByState  # noqa: E402
from recording_tools import Collector  # noqa: E402
from waiting import wait_for  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.odometry_reset import is_untrusted_reset  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402

RESET_TOPIC = '/mobile_base/commands/reset_odometry'
GAP_TOPIC = '/mobile_base/odometry_gap'
#: the fake's restart (sim/nodes/fake_kobuki.py): /clock from 0, odometry from the origin
RESTART_TOPIC = '/mobile_base/restart'
#: What no log of a restarted run may hold: a thread's traceback, rospy's exception text.
FORBIDDEN = ('Exception in thread', 'ROS time moved backwards')
#: What the layer's warnings and the abort say about the clock (ros/clock.py).
MOVED_BACK = 'ROS time moved back'
#: s of the restarted clock from which a robot whose mission the restart ended stands still:
#: a loop looks at the clock at least every 1 s (diagnostics), 1 s more to stop and say so
STILL_AFTER = 2.0
#: m: /odom this close to the origin right after the reset restarted from it
NEAR_ORIGIN = 0.1
#: m/s: the S-curve mission's speed (config/missions/test_s_curve.yaml); m: a reset's jump
MISSION_MAX_V, JUMP = 0.1, 0.5


class ResetTrigger(object):
    """Sends the reset once the mission is in ``state`` and the robot drove ``after`` m
    there (ground truth); records the /odom positions after it."""

    def __init__(self, mission_run, state, after, silence, restart=False):
        self.mission_run, self.state, self.after, self.silence = mission_run, state, after, silence
        self.restart = restart
        self._lock = threading.Lock()
        self._last = None
        self._driven = 0.0
        self.sent_at = None
        self.before = None              # the /odom position when the reset was sent
        self.after_reset = []           # /odom positions after it
        self.truth_after = []           # (stamp, ground-truth speed) after it
        self.reset_pub = rospy.Publisher(RESET_TOPIC, Empty, queue_size=1)
        self.gap_pub = rospy.Publisher(GAP_TOPIC, Float64, queue_size=1)
        self.restart_pub = rospy.Publisher(RESTART_TOPIC, Empty, queue_size=1)
        rospy.Subscriber('/odom', Odometry, self._on_odom, queue_size=500)
        rospy.Subscriber('/ground_truth/odom', Odometry, self._on_truth, queue_size=50)
        self._odom = None

    def wait_for_base(self):
        self.mission_run.wait(lambda: self.reset_pub.get_num_connections() >= 1
                              and self.gap_pub.get_num_connections() >= 1
                              and self.restart_pub.get_num_connections() >= 1,
                              'the fake base does not subscribe %s, %s and %s'
                              % (RESET_TOPIC, GAP_TOPIC, RESTART_TOPIC))

    def _on_odom(self, msg):
        p = msg.pose.pose.position
        with self._lock:
            self._odom = (p.x, p.y)
            if self.sent_at is not None:
                self.after_reset.append((msg.header.stamp.to_sec(), p.x, p.y))

    def _on_truth(self, msg):
        p = msg.pose.pose.position
        names_seen = self.mission_run.state_names()
        with self._lock:
            if self.sent_at is not None:        # (the first: the one the reset was sent at)
                self.truth_after.append((msg.header.stamp.to_sec(), abs(msg.twist.twist.linear.x)))
            if self.sent_at is not None or names_seen[-1:] != [self.state]:
                return
            if self._last is not None:
                self._driven += math.hypot(p.x - self._last[0], p.y - self._last[1])
            self._last = (p.x, p.y)
            if self._driven < self.after:
                return
            self.sent_at, self.before = msg.header.stamp.to_sec(), self._odom
            self.truth_after.append((self.sent_at, abs(msg.twist.twist.linear.x)))
        rospy.loginfo('RESET: %s at sim t %.2f (%s, %.2f m driven, odom at %s)',
                      'the fake restarted' if self.restart else 'silence %.1f s, then reset_odometry'
                      % self.silence if self.silence else 'reset_odometry', self.sent_at, self.state,
                      self._driven, self.before)
        if self.silence > 0:
            self.gap_pub.publish(Float64(self.silence))
        (self.restart_pub if self.restart else self.reset_pub).publish(Empty())


def sampling_param(name):
    """The sampling publisher's param ``name`` in the one process (a rate shared by several
    roles is the process's own)."""
    for key in ('/blind_navigation/sampling_publisher/' + name, '/blind_navigation/' + name):
        if rospy.has_param(key):
            return float(rospy.get_param(key))
    raise AssertionError('no param %s of the sampling publisher' % name)


class OdometryResetMissionTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission = rospy.get_param('~mission')
        cls.max_share = float(rospy.get_param('~max_error_share'))
        cls.expect = rospy.get_param('~expect')
        cls.restart = rospy.get_param('~restart', False)
        cls.rig = None
        if cls.restart:                 # the fake and the layer, their output kept
            cls.rig = LayerLaunch('clock_restart', mission_directory('clock_restart'),
                                  float(rospy.get_param('~rtf')), fake=True)
            wait_for(lambda: rospy.has_param('/blind_navigation/recorder') or cls.rig.process.poll() is not None,
                     'the rig launch set its params', 60.0)
        cls.mission_run = MissionRun(float(rospy.get_param('~wall_timeout', 240.0)))
        cls.paths = PathByState()
        cls.log = Collector('/rosout', Log)
        cls.status = Collector(names.STATUS, MissionStatus)
        cls.trigger = ResetTrigger(cls.mission_run, rospy.get_param('~reset_state'),
                                   float(rospy.get_param('~reset_after')),
                                   float(rospy.get_param('~silence', 0.0)), cls.restart)
        try:
            cls.mission_run.wait_for_layer()
            cls.trigger.wait_for_base()
            cls.mission_run.start_operator(cls.mission)
            cls.mission_run.wait_for_operator(cls.mission)
            cls.mission_run.trigger_by_publisher()
            cls.mission_run.wait_until_final()
            cls.error, cls.speed = cls.mission_run.error(), cls.mission_run.truth.speed()
            cls.loaded = cls.mission_run.recorded()
            if cls.restart:         # the schedule's longest period (the rig's params go with it)
                cls.longest_period = 1.0 / min(sampling_param('straight_rate'),
                                               sampling_param('curved_rate'))
        finally:
            cls.mission_run.stop_operator()
            if cls.rig is not None:
                cls.rig.stop()
        cls.final = cls.mission_run.state_names()[-1]
        statuses = [s for s in cls.status.snapshot() if s.state == cls.final]
        cls.reason = statuses[-1].reason if statuses else ''
        cls.code = statuses[-1].outcome if statuses else None
        cls.forward = cls.paths.of('recording')
        rospy.loginfo('ODOMETRY RESET %s in %s: state %s (%s), %.3f m from the start = %.2f %% of '
                      'the %.2f m driven, %d landmarks, %d gap(s)', cls.mission, cls.trigger.state,
                      cls.final, cls.reason, cls.error, 100.0 * cls.error / max(cls.forward, 1e-9),
                      cls.forward, len(cls.loaded.landmarks), len(cls.loaded.gaps))

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()

    def test_the_odometry_restarted_from_the_origin_in_its_state(self):
        self.assertIsNotNone(self.trigger.sent_at, 'the reset was never sent (%s never reached %.2f m)'
                             % (self.trigger.state, self.trigger.after))
        bx, by = self.trigger.before
        self.assertGreater(math.hypot(bx, by), 3 * NEAR_ORIGIN, 'odometry was near its origin already')
        # a jump of /odom (> JUMP) to near the origin (what the mission's top speed drives
        # in the silence farther), within a second of sim time of the command
        near = NEAR_ORIGIN + MISSION_MAX_V * self.trigger.silence
        soon = [self.trigger.before] + [(x, y) for stamp, x, y in self.trigger.after_reset
                                        if stamp <= self.trigger.sent_at + self.trigger.silence + 1.0]
        jumps = [b for a, b in zip(soon, soon[1:])
                 if math.hypot(b[0] - a[0], b[1] - a[1]) > JUMP and math.hypot(*b) < near]
        self.assertTrue(jumps, '/odom did not restart from the origin after the reset: %s' % soon[:10])

    def test_the_mission_ends_as_expected_never_home_farther_off(self):
        if self.final == 'home':
            self.assertLessEqual(self.error, self.max_share * self.forward,
                                 'home %.3f m from its start, %.2f %% of the %.2f m path (limit %.1f %%)'
                                 % (self.error, 100.0 * self.error / self.forward, self.forward,
                                    100.0 * self.max_share))
        else:
            self.assertEqual(self.final, 'aborted')
            if self.restart:
                self.assertIn(MOVED_BACK, self.reason, 'the reason does not name the clock')
            if not self.restart or self.trigger.state == 'recording':
                self.assertIn('odometry reset', self.reason)
        self.assertEqual(self.final, self.expect, 'ended %s (%s)' % (self.final, self.reason))
        # the cause as a code: every abort here is the odometry's (a reset it cannot carry, or
        # the odometry silent past its grace), the clock's move back only named in the reason
        self.assertEqual(self.code, MissionStatus.OUTCOME_HOME if self.final == 'home' else
                         MissionStatus.OUTCOME_ODOMETRY, self.reason)

    def test_robot_stands_still_at_the_end(self):
        self.assertLess(self.speed, STOPPED_SPEED)

    def test_the_layer_logged_the_reset(self):
        if self.restart and self.trigger.state != 'recording':
            self.skipTest('the mission ends at the jump, before the odometry reset is confirmed')
        wanted = 'odometry reset re-anchored' if self.expect == 'home' else 'odometry reset not re-anchored'
        lines = [m.msg for m in self.log.snapshot() if wanted in m.msg]
        self.assertTrue(lines, 'no "%s" on /rosout' % wanted)

    def test_the_recording_has_a_gap_only_where_the_reset_was_not_carried_across(self):
        if self.trigger.state == 'rotating':    # the recording goes on until the turn begins
            self.assertIn([is_untrusted_reset(gap.reason) for gap in self.loaded.gaps], ([], [True]),
                          'at most one gap, naming the reset: %s' % (self.loaded.gaps,))
        elif self.trigger.state != 'recording':
            self.assertEqual(self.loaded.gaps, [])
        elif self.expect == 'home':
            self.assertEqual(self.loaded.gaps, [], 'the reset was carried across: no gap')
        else:
            self.assertEqual([is_untrusted_reset(gap.reason) for gap in self.loaded.gaps], [True],
                             'one gap naming the reset: %s' % (self.loaded.gaps,))

    # --- the fake restarted (~restart) ------------------------------------------------------
    def samples_after_restart(self):
        """The samples published after the clock went back: those after the first whose
        stamp is earlier than the one before it. The one process publishes no samples: its
        storage messages (one per step that stored landmarks) instead."""
        run = self.mission_run
        samples = (run.storage_msgs if run.compact else run.samples).snapshot()
        stamps = [msg.header.stamp.to_sec() for msg in samples]
        back = [i for i in range(1, len(stamps)) if stamps[i] < stamps[i - 1]]
        return samples[back[0]:] if back else []

    def test_the_samples_and_landmarks_go_on_after_the_restart(self):
        if not self.restart or self.trigger.state != 'recording':
            self.skipTest('no restart while recording')
        after = self.samples_after_restart()
        self.assertTrue(after, 'no sample after the clock went back')
        if not self.mission_run.compact:
            self.assertEqual(after[-1].command, 'final', 'the recording did not end with its final sample')
        # from the new clock's start to the end, no tick missed: every pause (the first one
        # from 0, the restart) shorter than two of the schedule's longest periods
        longest = self.longest_period
        stamps = [msg.header.stamp.to_sec() for msg in after]
        worst = max(b - a for a, b in zip([0.0] + stamps, stamps))
        self.assertLess(worst, 2 * longest, 'a pause of %.2f s in the samples after the restart' % worst)
        # every landmark after the gap (the restart) was saved: one per sample but its first
        labels = self.loaded.labels
        gap = labels.index(self.loaded.gaps[0].before) if self.loaded.gaps else len(labels)
        rospy.loginfo('RESTART: %d samples over %.1f s after it (longest pause %.2f s), %d landmarks '
                      'after the gap', len(after), stamps[-1] - stamps[0], worst, len(labels) - gap)
        self.assertGreaterEqual(len(labels) - gap, len(after) - 1,
                                'landmarks after the gap %d, samples after the restart %d'
                                % (len(labels) - gap, len(after)))

    def test_every_loop_said_once_that_the_time_moved_back(self):
        if not self.restart:
            self.skipTest('no restart')
        warned = [m.msg for m in self.log.snapshot() if MOVED_BACK in m.msg and m.level == Log.WARN]
        # one that runs: while recording the one process's mission loop (the paper layout's sampling)
        loop = ('mission_owner' if self.mission_run.compact else 'sampling') \
            if self.trigger.state == 'recording' else 'diagnostics'
        self.assertTrue(any(loop in line for line in warned), 'the %s loop did not say so: %s'
                        % (loop, warned))
        loops = [line.split(MOVED_BACK)[0] for line in warned]
        self.assertEqual(sorted(set(loops)), sorted(loops), 'a loop said it more than once: %s' % warned)

    def test_the_robot_stands_still_soon_after_a_restart_that_ends_the_mission(self):
        if not self.restart or self.trigger.state == 'recording':
            self.skipTest('no restart, or while recording (the operator drives on)')
        truth = self.trigger.truth_after
        back = next((i for i in range(1, len(truth)) if truth[i][0] < truth[i - 1][0]), len(truth))
        self.assertLess(back, len(truth), 'no ground truth on the new clock')
        # the layer looks at the clock at least once a second (diagnostics) and the ideal base
        # stops at once: standing still from STILL_AFTER s of the new clock on
        moving = [(stamp, speed) for stamp, speed in truth[back:]
                  if stamp >= STILL_AFTER and speed >= STOPPED_SPEED]
        last = max([stamp for stamp, speed in truth[back:] if speed >= STOPPED_SPEED] or [0.0])
        rospy.loginfo('RESTART: the robot moved until %.2f s of the new clock', last)
        self.assertEqual(moving[:5], [], 'the robot drove on after the restart')

    def test_no_log_of_the_run_holds_a_thread_traceback(self):
        if not self.restart:
            self.skipTest('no restart')
        run_logs = os.path.join(rospkg.get_log_dir(), rospy.get_param('/run_id'))
        texts = {'the rig launch (screen output)': self.rig.output()}
        for path in glob.glob(os.path.join(run_logs, '*.log')):
            with open(path, errors='replace') as stream:
                texts[path] = stream.read()
        bad = ['%s: %s' % (where, text) for where, content in sorted(texts.items())
               for text in FORBIDDEN if text in content]
        self.assertEqual(bad, [], 'of %d logs' % len(texts))


if __name__ == '__main__':
    rospy.init_node('test_mission_odometry_reset')
    rostest.rosrun('blind_navigation', 'mission_odometry_reset', OdometryResetMissionTest)
