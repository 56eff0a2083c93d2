"""The paper layout's hand-shakes of its mission owner (back_travel_client) with the other
roles' nodes, in one place: the savers' storage reports (RemoteRecording), the pi turn handed
to rotate_pi (RemoteTurn: ``recording_end`` out, ``rotation_done`` in), the return's goals
(RemoteGoals: ``set_return_route``, one BackTravel goal per landmark), heading_correction's
correction and the other processes' ``role_failure``. docs/DESIGN.md, "The paper's layout".
"""
import os

import actionlib
import rospy
from actionlib.action_client import CommState, get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from std_msgs.msg import Bool, Empty, String

from blind_navigation import names
from blind_navigation.core import drive, outcome
from blind_navigation.core.return_plan import NO_LOSS, WriteLoss
from blind_navigation.msg import BackTravelAction, BackTravelGoal, HeadingCorrection, StorageUsage
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.layer import correction_from_message
from blind_navigation.ros.route_wire import route_message
from blind_navigation.srv import SetReturnRoute


def write_loss(msg):
    """The core/return_plan.WriteLoss a StorageUsage report names."""
    return WriteLoss(msg.lost, msg.lost_distance, msg.lost_turn, msg.error)


class RemoteRecording(object):
    """The landmark savers' StorageUsage reports, each handed to ``on_report(msg)``
    (through ``guard``); the write loss each file had: :meth:`loss_of`."""

    def __init__(self, guard, on_report):
        self.losses = {}                # real path of a landmark file -> its last WriteLoss reported
        self.on_report = on_report
        subscribe(names.STORAGE, StorageUsage, guard(self._on_storage), queue_size=5)

    def _on_storage(self, msg):
        if msg.lost:
            self.losses[os.path.realpath(msg.file)] = write_loss(msg)
        self.on_report(msg)

    def loss_of(self, path):
        """The core/return_plan.WriteLoss the saver of the landmark file ``path`` reported."""
        return self.losses.get(os.path.realpath(path), NO_LOSS)


class RemoteTurn(object):
    """The pi turn, rotate_pi's: :meth:`begin` ends the recording (``recording_end``,
    latched: the sampling publisher's ``final`` sample, then the turn); ``on_done(ok)``
    (through ``guard``) takes ``rotation_done``."""

    def __init__(self, guard, on_done):
        self.end_pub = rospy.Publisher(names.RECORDING_END, Empty, queue_size=1, latch=True)
        subscribe(names.ROTATION_DONE, Bool, guard(lambda msg: on_done(msg.data)), queue_size=1)

    def begin(self):
        self.end_pub.publish(Empty())


class RemoteGoals(object):
    """The return's goals on back_travel_server, one at a time; each goal's callbacks are
    bound to it (a status that comes before ``send_goal`` returns is kept). The action
    client is made at the first :meth:`connect` (docs/DESIGN.md, "The paper's layout")."""

    def __init__(self, guard):
        self.guard, self.client, self._handle = guard, None, None

    def connect(self, route, landmarks, completed, frame_id, timeout):
        """Wait for the action server, then set the route, its goals' ``landmarks`` (return
        order) and how many are ``completed`` on it: (why not or None, the response)."""
        if self.client is None:
            self.client = actionlib.ActionClient(names.BACK_TRAVEL, BackTravelAction)
        if not self.client.wait_for_server(rospy.Duration(timeout)):
            return ('action server %s not available after %.0f s (is back_travel_server running?)'
                    % (rospy.resolve_name(names.BACK_TRAVEL), timeout)), None
        service = rospy.resolve_name(names.SET_RETURN_ROUTE)
        try:
            rospy.wait_for_service(names.SET_RETURN_ROUTE, timeout)
            call = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
            response = call(header=rospy.Header(stamp=rospy.Time.now(), frame_id=frame_id),
                            route=route_message(route),
                            landmarks=[value for lm in landmarks for value in lm.as_list()],
                            completed=completed)
        except (rospy.ROSException, rospy.ServiceException) as error:
            return 'cannot set the return route on %s: %s' % (service, error), None
        return None if response.ok else 'return route refused: %s' % response.message, response

    def send(self, landmark, on_done):
        """Send the goal of ``landmark``; ``on_done(core/drive.Outcome)`` once it ended."""
        ended = []

        def on_transition(handle):
            if handle.get_comm_state() != CommState.DONE or ended:
                return
            ended.append(handle)
            status, text, result = handle.get_goal_status(), handle.get_goal_status_text(), handle.get_result()
            if status == GoalStatus.SUCCEEDED:
                return on_done(drive.Outcome(drive.SUCCEEDED, ''))
            name = get_name_of_constant(GoalStatus, status)
            on_done(drive.Outcome(drive.FAILED, 'ended %s' % ('%s: %s' % (name, text) if text else name),
                                  getattr(result, 'outcome', 0) or outcome.ROLE_FAILURE))

        self._handle = self.client.send_goal(BackTravelGoal(*landmark.as_list()),
                                             self.guard(on_transition))

    def cancel(self):
        """Ask the server to cancel the goal under way, if any."""
        if self._handle is not None and self._handle.get_comm_state() != CommState.DONE:
            self._handle.cancel()


def subscribe_failures(guard, on_failure):
    """``on_failure(reason)`` for each ``role_failure`` another process reports."""
    def on_report(msg):
        sender = msg._connection_header.get('callerid', '?')
        if sender != rospy.get_name():          # this process's roles report at once
            on_failure('%s (%s)' % (msg.data, sender))
    subscribe(names.ROLE_FAILURE, String, guard(on_report), queue_size=10)


def subscribe_correction(guard, on_correction):
    """``on_correction(core GyroCorrection)`` for each heading_correction measured."""
    subscribe(names.HEADING_CORRECTION, HeadingCorrection,
              guard(lambda msg: on_correction(correction_from_message(msg)[0])), queue_size=1)
