#!/usr/bin/env python3
"""rostest: ``/blind_navigation/new_mission`` (std_srvs/Trigger) on the fake TurtleBot
(mission_new_mission.test: default launch, one process; mission_new_mission_paper.test:
the paper's node layout).

Mission 1: a short mission is recorded and ``go_home`` brings it home;
``new_mission`` called while the mission is ``rotating`` is refused naming it, and
``cancel`` at ``home`` is refused naming it.
Then ``new_mission`` at ``home`` is acknowledged: the state goes ``idle`` and
``recording`` again without a relaunch, the ``landmark_file`` symlink points at
a new file, and the mission 1 file stays byte-identical (SHA-256 before and
after mission 2). Mission 2 records landmarks into the new file, ``new_mission``
while ``recording`` is refused naming it, and ``go_home`` (``~second_end``
``vision_loss``: the fake's vision failed through /fake_turtlebot/set_vision and
detected by the restarted vision_monitor) brings it home within 2 % of its path
too. The client's /diagnostics names mission 2 and its file.
With ``~then_cancel``, ``new_mission`` starts mission 3 and :class:`CancelAfterNewMission`
plays test_mission_services.py's go_home and cancel in it (one launch for both).
"""
import hashlib
import os
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import Bool
from std_srvs.srv import SetBool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import MISSION_DONE_TOPIC, MissionRun  # noqa: E402
from recording_tools import Collector, Diagnostics  # noqa: E402
from test_mission_services import ServicesChecks, trigger  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402
from blind_navigation.core.store import load_landmarks  # noqa: E402


SET_VISION = '/fake_turtlebot/set_vision'
#: Each return must end within this fraction of the recorded path's length of the start.
MAX_RELATIVE_ERROR = 0.02
#: m: half the scripted mission (test_left_arc, 1.97 m): mission 2 recorded the driving.
DRIVEN_AT_LEAST = 1.0


def digest(path):
    with open(path, 'rb') as stream:
        return hashlib.sha256(stream.read()).hexdigest()


class NewMissionTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        mission = rospy.get_param('~mission')
        cls.run_ = run = MissionRun(float(rospy.get_param('~wall_timeout', 240.0)))
        cls.second_end = rospy.get_param('~second_end', 'go_home')
        cls.diagnostics = Diagnostics()
        cls.status = Collector(names.STATUS, MissionStatus)
        go_home, new_mission = trigger(names.GO_HOME), trigger(names.NEW_MISSION)
        cancel = trigger(names.CANCEL)
        try:
            run.wait_for_layer()
            run.play_mission(mission)
            cls.go_home_1 = go_home()
            cls.refused_rotating = new_mission()
            cls.outcome_1 = run.outcome()
            cls.cancel_at_home = cancel()
            cls.file_1 = os.path.realpath(cls.outcome_1.loaded.path)
            cls.digest_1 = digest(cls.file_1)
            run.stop_operator()
            cls.states_1 = run.state_names()

            stored_1 = len(run.storage_msgs)
            cls.new_reply = new_mission()
            run.wait(lambda: run.state_names()[len(cls.states_1):][-1:] == ['recording'],
                     'the state never became recording after new_mission; states %s'
                     % run.state_names())
            run.wait(lambda: len(run.storage_msgs) > stored_1,
                     'no storage message after new_mission (nothing recorded)')
            cls.file_2 = os.path.realpath(run.storage_msgs.snapshot(stored_1)[0].file)
            cls.link_2 = os.path.realpath(run.param('landmark_saver', 'landmark_file'))
            cls.refused_recording = new_mission()
            run.start = run.truth.position()
            run.mission_done.sub.unregister()
            run.mission_done = Collector(MISSION_DONE_TOPIC, Bool)
            run.play_mission(mission)
            if cls.second_end == 'vision_loss':
                rospy.wait_for_service(SET_VISION, timeout=run.wall_timeout)
                cls.go_home_2 = rospy.ServiceProxy(SET_VISION, SetBool)(False)
            else:
                cls.go_home_2 = go_home()
            cls.outcome_2 = run.outcome()
            run.wait(lambda: cls.diagnostics.status('%s: mission' % run.owner.lstrip('/'),
                                                    'mission file'),
                     'no mission diagnostics of %s' % run.owner)
            cls.mission_status = cls.diagnostics.status('%s: mission' % run.owner.lstrip('/'))[1]
            cls.states_2 = run.state_names()
        finally:
            run.stop_operator()

    @classmethod
    def tearDownClass(cls):
        if not rospy.get_param('~then_cancel', False):
            cls.run_.remove_recording()

    def test_new_mission_is_refused_while_a_mission_is_under_way(self):
        for reply, state in ((self.refused_rotating, 'rotating'),
                             (self.refused_recording, 'recording')):
            self.assertFalse(reply.success, reply.message)
            self.assertIn('the mission is %s' % state, reply.message)

    def test_cancel_at_home_is_refused_naming_it(self):
        self.assertFalse(self.cancel_at_home.success, self.cancel_at_home.message)
        self.assertIn('home', self.cancel_at_home.message)

    def test_both_missions_come_home(self):
        self.assertTrue(self.go_home_1.success and self.go_home_2.success,
                        (self.go_home_1.message, self.go_home_2.message))
        walk = ['idle', 'recording', 'rotating', 'returning', 'home']
        self.assertEqual(self.states_2, walk + walk)
        rotating = [msg.reason for msg in self.status.snapshot() if msg.state == 'rotating']
        self.assertEqual(len(rotating), 2, rotating)
        self.assertTrue(rotating[0].startswith('return requested (go_home'), rotating)
        self.assertTrue(rotating[1].startswith('vision lost' if self.second_end == 'vision_loss'
                                               else 'return requested (go_home'), rotating)
        for outcome in (self.outcome_1, self.outcome_2):
            rospy.loginfo('NEW_MISSION: error %.4f m on a %.2f m path (%.2f %%)', outcome.error,
                          outcome.loaded.total_distance,
                          100 * outcome.error / outcome.loaded.total_distance)
            self.assertLess(outcome.error, MAX_RELATIVE_ERROR * outcome.loaded.total_distance)

    def test_the_second_mission_records_into_a_new_file(self):
        self.assertTrue(self.new_reply.success, self.new_reply.message)
        self.assertIn('mission 2', self.new_reply.message)
        self.assertNotEqual(self.file_2, self.file_1)
        self.assertEqual(self.link_2, self.file_2, 'landmark_file does not point at the new file')
        self.assertEqual(os.path.realpath(self.outcome_2.loaded.path), self.file_2)
        # the operator drove the script again (under load it may lapse a little: what was
        # driven is what must come home, test_both_missions_come_home)
        second = self.outcome_2.loaded
        self.assertTrue(second.landmarks, 'nothing recorded in mission 2')
        self.assertGreater(second.total_distance, DRIVEN_AT_LEAST)

    def test_the_first_file_is_byte_identical(self):
        self.assertEqual(digest(self.file_1), self.digest_1)
        self.assertEqual(len(load_landmarks(self.file_1).landmarks),
                         len(self.outcome_1.loaded.landmarks))

    def test_the_diagnostics_name_the_mission_and_its_file(self):
        self.assertEqual(self.mission_status['mission'], '2')
        self.assertEqual(self.mission_status['mission file'], self.file_2)
        self.assertTrue(self.mission_status['mission id'].endswith('#2'),
                        self.mission_status['mission id'])


class CancelAfterNewMission(ServicesChecks, unittest.TestCase):
    """Mission 3 (``~then_cancel``), started by ``new_mission`` after mission 2's home: the
    checks of test_mission_services.py on its states and statuses (the run forgets the
    earlier missions' ones)."""

    @classmethod
    def setUpClass(cls):
        run = NewMissionTest.run_
        states, statuses = len(run.states), len(run.status)
        run.mission_done.sub.unregister()
        run.mission_done = Collector(MISSION_DONE_TOPIC, Bool)
        reply = trigger(names.NEW_MISSION)()
        if not reply.success:
            raise AssertionError('new_mission after mission 2 refused: %s' % reply.message)
        run.states.drop_before(states)
        run.status.drop_before(statuses)
        run.wait(lambda: run.state_names()[-1:] == ['recording'],
                 'mission 3 never recorded; states %s' % run.state_names())
        cls.play(run, run.status)

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()


def suite():
    """NewMissionTest, then (``~then_cancel``) CancelAfterNewMission on the same layer."""
    cases = [NewMissionTest] + ([CancelAfterNewMission] if rospy.get_param('~then_cancel', False) else [])
    return unittest.TestSuite(unittest.TestLoader().loadTestsFromTestCase(case) for case in cases)


if __name__ == '__main__':
    rospy.init_node('test_mission_new_mission')
    rostest.rosrun('blind_navigation', 'mission_new_mission', __name__ + '.suite')
