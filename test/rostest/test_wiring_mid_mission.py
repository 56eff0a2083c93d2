"""The case of wiring.test on its root namespace's layer (test_wiring.py runs it): wrong
wiring that appears while the robot moves.
The layer records on the ideal base of this node, vision_lost starts the pi turn;
once the base turns, a std_msgs/String publisher appears on
/mobile_base/events/cliff: exactly one FATAL line naming the topic,
kobuki_msgs/CliffEvent and std_msgs/String; the mission ends aborted naming the
fault; a zero command follows and every command after it is zero; the base stands
still."""
import time
import unittest

import rospy
from rosgraph_msgs.msg import Log
from std_msgs.msg import Empty, String

from fake_base import FakeBase
from recording_tools import Collector
from waiting import wait_for

LAYER = '/blind_navigation'
CLIFF = '/mobile_base/events/cliff'


class WiringMidMissionTest(unittest.TestCase):

    def states(self):
        return [m.data for m in self.state.snapshot()]

    def test_a_wrong_publisher_during_the_turn_stops_it(self):
        rosout = Collector('/rosout', Log)
        self.state = Collector(LAYER + '/state', String)
        base = FakeBase()
        base.wait_for_listeners(timeout=60.0)
        wait_for(lambda: 'recording' in self.states(), 'the layer records (states %s)' % self.states(),
                 timeout=60.0)
        base.drive(0.2, 1.5)
        vision_lost = rospy.Publisher(LAYER + '/vision_lost', Empty, queue_size=1, latch=True)
        vision_lost.publish(Empty())
        wait_for(lambda: abs(base.w) > 0.1, 'the pi turn drives the base (states %s)' % self.states(),
                 timeout=60.0)
        fault_at = rospy.get_time()
        wrong = rospy.Publisher(CLIFF, String, queue_size=5)
        fatal = lambda: [m.msg for m in rosout.snapshot() if m.level == Log.FATAL and m.name == LAYER]
        deadline = time.monotonic() + 30.0
        while not fatal() and time.monotonic() < deadline:
            wrong.publish(String(data='cliff'))
            time.sleep(0.1)
        wait_for(lambda: 'aborted' in self.states(), 'the mission aborted (states %s)' % self.states())
        for _ in range(20):                         # it goes on publishing: still one line
            wrong.publish(String(data='cliff'))
            time.sleep(0.1)
        lines = fatal()
        self.assertEqual(len(lines), 1, 'one FATAL line: %s' % lines)
        for text in (CLIFF, 'kobuki_msgs/CliffEvent', 'std_msgs/String'):
            self.assertIn(text, lines[0])
        self.assertEqual(self.states()[-2:], ['rotating', 'aborted'])
        reasons = [m.msg for m in rosout.snapshot() if m.name == LAYER and '-> aborted' in m.msg]
        self.assertTrue(reasons and 'wrong wiring: %s carries std_msgs/String' % CLIFF in reasons[-1],
                        reasons)
        after = [(t, v, w) for t, v, w in base.commands if t >= fault_at]
        zeros = [i for i, (_, v, w) in enumerate(after) if v == 0.0 and w == 0.0]
        self.assertTrue(zeros, 'a zero command after the fault: %s' % after[:5])
        moving = [c for c in after[zeros[0]:] if c[1] != 0.0 or c[2] != 0.0]
        self.assertEqual(moving, [], 'nothing but zero after the first zero')
        wait_for(lambda: base.w == 0.0 and base.v == 0.0, 'the base stands still', timeout=5.0)
        rospy.loginfo('WIRING MID MISSION: zero %.3f s after the wrong publisher appeared, '
                      '%d command(s) before it', after[zeros[0]][0] - fault_at, zeros[0])

