#!/usr/bin/env python3
"""rostest: vision lost on the fake with its dock, dock_at_home (mission_docking.test).

With ``~aside`` (m) the fake's dock is first moved that far sideways (a world event, the
fake's ``mobile_base/move_dock``): the robot turns, returns, looks for the dock and ends
``home`` with a reason naming the dock not seen, outcome DOCK_FAILED; ground truth: it
turned on the spot while docking and stands after ``home``. Then the dock is put behind
the robot where it stands (as if it had backed off it), ``new_mission`` starts mission 2.
The docking mission (the only one without ``~aside``): the states walk idle, recording,
rotating, returning, docking, docked; the status names the charger, outcome DOCKED; the
fake's SensorState reports charging (6) and the robot stands on the dock's contacts.
"""
import math
import os
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import Bool, String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import MISSION_DONE_TOPIC, STOPPED_SPEED, MissionRun, PathByState  # noqa: E402
from recording_tools import Collector  # noqa: E402
from test_mission_services import trigger  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.geometry import Pose2D  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402
from blind_navigation.ros import kobuki_msgs_compat as kobuki  # noqa: E402
from blind_navigation.sim.dock import CHARGING, DISCHARGING, Dock  # noqa: E402
from blind_navigation.sim.docking import LOST_TIME  # noqa: E402

DOCK_WALK = ['idle', 'recording', 'rotating', 'returning', 'docking', 'docked']
ASIDE_WALK = ['idle', 'recording', 'rotating', 'returning', 'docking', 'home']
MOVE_DOCK = '/mobile_base/move_dock'
#: m the robot's centre may be from the docked pose: the dock's contacts meet within 0.05 m
#: of its axis (sim/dock.CONTACT_HALF_WIDTH) and 0.005 m of its face
ON_THE_DOCK = 0.06
#: m the robot may travel (ground truth) while the dock drive looks for an unseen dock: it
#: turns on the spot (a scan of one turn), so only its turning slip moves its centre
NO_WANDERING = 0.1
#: s of sim time the robot is watched after ``home``: the longest the fake lets its dock drive
#: move without a verdict (sim/docking.LOST_TIME), so a drive still running would show
WATCH = LOST_TIME
#: m it may travel meanwhile: standing, ground truth moves only by the base's ripple
AFTER_HOME = 0.01


class DockingTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission_run = run = MissionRun(float(rospy.get_param('~wall_timeout', 200.0)))
        cls.core = Collector(names.CORE_SENSORS, kobuki.SensorState)
        cls.travel = PathByState(key=str)       # m travelled in each state by its name
        cls.aside = float(rospy.get_param('~aside', 0.0))
        mission = rospy.get_param('~mission')
        try:
            if cls.aside:
                cls._mission_with_the_dock_aside(mission)
                cls.dock = cls._move_dock(Dock.behind(run.truth.pose()))
                cls._new_mission(mission)
            else:
                cls.dock = Dock.behind(Pose2D(0.0, 0.0, 0.0))     # dock:=start: the start at 0
                run.record_mission(mission)
            run.trigger_by_publisher()
            run.wait_until_final()
            run.wait(lambda: cls.core.snapshot() and cls.core.snapshot()[-1].charger == CHARGING,
                     'the fake never reported charging (charger %d) after %s' % (
                         CHARGING, run.state_names()))
        finally:
            run.stop_operator()

    @classmethod
    def _move_dock(cls, dock):
        spec = '%.3f %.3f %.3f' % tuple(dock.pose)
        cls.mission_run.tell_fake(MOVE_DOCK, String(spec), 'fake_kobuki: dock moved to ' + spec)
        return Dock(Pose2D(*(float(part) for part in spec.split())))

    @classmethod
    def _mission_with_the_dock_aside(cls, mission):
        """Mission 1 with the dock ``aside`` m to its left: it ends home; watched WATCH s more."""
        run, start = cls.mission_run, Dock.behind(Pose2D(0.0, 0.0, 0.0)).pose
        cls._move_dock(Dock(Pose2D(start.x - cls.aside * math.sin(start.yaw),
                                   start.y + cls.aside * math.cos(start.yaw), start.yaw)))
        run.record_mission(mission)
        run.trigger_by_publisher()
        run.wait_until_final()
        run.wait_sim(WATCH, 'watching the robot after home')
        cls.first = dict(states=run.state_names(), status=run.status.snapshot()[-1],
                         docking=cls.travel.of('docking'), after_home=cls.travel.of('home'),
                         speed=run.truth.speed(),
                         charger=cls.core.snapshot()[-1].charger)
        run.stop_operator()

    @classmethod
    def _new_mission(cls, mission):
        """new_mission from home, the operator again, until it is done and the robot stopped."""
        run, states = cls.mission_run, len(cls.first['states'])
        reply = trigger(names.NEW_MISSION)()
        assert reply.success, 'new_mission refused at home: %s' % reply.message
        run.wait(lambda: run.state_names()[states:][-1:] == ['recording'],
                 'the state never became recording after new_mission; states %s' % run.state_names())
        run.mission_done.sub.unregister()
        run.mission_done = Collector(MISSION_DONE_TOPIC, Bool)
        run.start_operator(mission)
        run.wait_for_operator(mission)

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()

    def test_the_return_ends_docked_on_the_charger(self):
        run = self.mission_run
        status = run.status.snapshot()[-1]
        x, y = run.truth.position()
        docked = self.dock.docked_pose()
        rospy.loginfo('DOCKING: %s; %s; the robot %.3f m from the docked pose, charger %d',
                      run.state_names(), status.reason, math.hypot(x - docked.x, y - docked.y),
                      self.core.snapshot()[-1].charger)
        self.assertEqual(run.state_names(), (ASIDE_WALK if self.aside else []) + DOCK_WALK)
        self.assertIn('docked on the charger', status.reason)
        self.assertEqual(status.outcome, MissionStatus.OUTCOME_DOCKED)
        self.assertLess(math.hypot(x - docked.x, y - docked.y), ON_THE_DOCK)
        self.assertLess(run.truth.speed(), STOPPED_SPEED)


class AsideDockingTest(DockingTest):
    """With ``~aside``: mission 1 with the dock aside, then the docking mission."""

    def test_a_dock_moved_aside_ends_home_naming_it_without_wandering(self):
        first = self.first
        rospy.loginfo('DOCKING aside %.2f m: %s; %s; travelled %.4f m docking, %.4f m in %g s after home',
                      self.aside, first['states'], first['status'].reason, first['docking'],
                      first['after_home'], WATCH)
        self.assertEqual(first['states'], ASIDE_WALK)
        reason = first['status'].reason
        self.assertTrue(reason.startswith('docking failed: ') and 'dock not seen' in reason, reason)
        self.assertEqual((first['status'].state, first['status'].outcome),
                         ('home', MissionStatus.OUTCOME_DOCK_FAILED))
        self.assertLess(first['docking'], NO_WANDERING)
        self.assertLess(first['after_home'], AFTER_HOME)
        self.assertLess(first['speed'], STOPPED_SPEED)
        self.assertEqual(first['charger'], DISCHARGING)


if __name__ == '__main__':
    rospy.init_node('test_mission_docking')
    rostest.rosrun('blind_navigation', 'mission_docking',
                   AsideDockingTest if rospy.get_param('~aside', 0.0) else DockingTest)
