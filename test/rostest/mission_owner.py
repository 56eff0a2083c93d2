"""rostest helper: the test node as the mission's owner.

The layer's roles obey only the mission state published by the mission's owner
(ros/mission.py; back_travel_client in a real layer). A test that runs a role
without a client names itself as that role's ``~mission_owner`` in its .test file
and publishes the state with :class:`MissionOwner`.
"""
import time

import rospy
from std_msgs.msg import Empty, Header, String

from blind_navigation import names
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.route import build_route
from blind_navigation.msg import BackTravelGoal
from blind_navigation.ros.paper_owner import route_message
from blind_navigation.srv import SetReturnRoute

#: A goal no server takes (|v| far beyond the Kobuki's): rejected as a bad goal while
#: the mission is returning, for the mission state otherwise.
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
        self.end_pub = rospy.Publisher(names.RECORDING_END, Empty, queue_size=1, latch=True)

    def publish(self, state):
        """Publish ``state``; ``rotating`` also ends the recording at once (the pi turn
        begins, as the paper's owner does it)."""
        self.pub.publish(String(data=state))
        if state == 'rotating':
            self.end_pub.publish(Empty())

    def wait_heard(self, count, timeout):
        """Until ``count`` nodes subscribe to the state from this node."""
        deadline = time.monotonic() + timeout
        while self.pub.get_num_connections() < count:
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise AssertionError('%d node(s) do not follow the mission state on %s after %.0f s'
                                     % (count, self.pub.resolved_name, timeout))
            time.sleep(0.02)

    def set_route(self, goals, anchor, timeout, version=None):
        """As back_travel_client does when the return starts: give the back-travel
        server the route back from ``anchor`` (x, y: where the robot is) through
        ``goals`` (landmark tuples in the order they will be sent), none done yet;
        retried while the server has not yet seen the mission ``returning``.
        ``version``: the ReturnRoute version sent, if not the current one."""
        route = route_message(build_route([Landmark(*goal) for goal in reversed(goals)], anchor))
        if version is not None:
            route.version = version
        rospy.wait_for_service(names.SET_RETURN_ROUTE, timeout)
        set_route = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
        deadline = time.monotonic() + timeout
        while True:
            response = set_route(header=Header(stamp=rospy.Time.now(), frame_id='odom'),
                                 route=route,
                                 landmarks=[value for goal in goals for value in goal], completed=0)
            if response.ok:
                return
            if 'the mission is' not in response.message or time.monotonic() > deadline:
                raise AssertionError('return route refused: %s' % response.message)
            time.sleep(0.05)
