"""rostest helper: the test node as the mission's owner.

The layer's roles obey only the mission state published by the mission's owner
(ros/mission.py; back_travel_client in a real layer). A test that runs a role
without a client names itself as that role's ``~mission_owner`` in its .test file
and publishes the state with :class:`MissionOwner`.
"""
import time

import rospy
from actionlib_msgs.msg import GoalStatus
from std_msgs.msg import String

from blind_navigation import names
from blind_navigation.msg import BackTravelGoal

#: A goal no server drives (|v| far beyond the Kobuki's): accepted only in ``returning``,
#: then aborted for its speed without any motion.
UNDRIVABLE = BackTravelGoal(v=5.0, w=0.0, d=1.0, T=2.0, psi=0.0)


class MissionOwner(object):
    """Publishes the mission state (latched) from this node; ``nodes``: the nodes whose
    ``~mission_owner`` must name this node (checked at once, with a clear message)."""

    def __init__(self, *nodes):
        me = rospy.get_name()
        for node in nodes:
            owner = rospy.get_param(node + '/mission_owner', None)
            if owner != me:
                raise AssertionError('%s/mission_owner is %r: the .test must set it to this test '
                                     'node, %s' % (node, owner, me))
        self.pub = rospy.Publisher(names.STATE, String, queue_size=10, latch=True)

    def publish(self, state):
        self.pub.publish(String(data=state))

    def wait_heard(self, count, timeout):
        """Until ``count`` nodes subscribe to the state from this node."""
        deadline = time.monotonic() + timeout
        while self.pub.get_num_connections() < count:
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise AssertionError('%d node(s) do not follow the mission state on %s after %.0f s'
                                     % (count, self.pub.resolved_name, timeout))
            time.sleep(0.02)

    def wait_until_server_takes_goals(self, action, timeout):
        """Until the back-travel server behind ``action`` (a SimpleActionClient) sees
        the mission ``returning``: an undrivable goal is then aborted for its speed
        instead of rejected for the mission state."""
        deadline = time.monotonic() + timeout
        while True:
            action.send_goal(UNDRIVABLE)
            if not action.wait_for_result(rospy.Duration(timeout)):
                raise AssertionError('no result for a probe goal within %.0f s' % timeout)
            text = action.get_goal_status_text()
            if action.get_state() == GoalStatus.ABORTED:
                return
            if 'the mission is' not in text or time.monotonic() > deadline:
                raise AssertionError('the server did not take goals within %.0f s: %s'
                                     % (timeout, text))
            time.sleep(0.05)
