"""One goal at a time to an action server, with SimpleActionClient's calls but without
its send_goal race (ros/actionlib#206): SimpleActionClient drops every transition that
comes before send_goal has stored the new goal's handle, so the result of a server that
answers at once (a rejection) is lost and wait_for_result waits in vain. Here each goal
has callbacks of its own on an ActionClient goal handle, tracked before the goal is sent."""
import threading

import actionlib
import rospy
from actionlib.action_client import CommState
from actionlib_msgs.msg import GoalStatus

#: the status SimpleActionClient.get_state reports for a goal being cancelled
_SIMPLE_STATE = {GoalStatus.RECALLING: GoalStatus.PENDING, GoalStatus.PREEMPTING: GoalStatus.ACTIVE}


class GoalClient(object):
    """wait_for_server, send_goal, wait_for_result, get_state, get_goal_status_text,
    get_result and cancel_goal, as actionlib.SimpleActionClient's."""

    def __init__(self, name, action):
        self.client = actionlib.ActionClient(name, action)
        self._handle, self._done = None, threading.Event()

    def wait_for_server(self, timeout=rospy.Duration()):
        return self.client.wait_for_server(timeout)

    def send_goal(self, goal, done_cb=None, feedback_cb=None):
        """Send ``goal``; the goal sent before is no longer tracked. ``done_cb(status, result)``
        once it has ended, ``feedback_cb(feedback)`` on each feedback: this goal's only."""
        done = self._done = threading.Event()

        def on_transition(handle):      # called under the goal's own lock: once DONE
            if handle.get_comm_state() == CommState.DONE and not done.is_set():
                done.set()
                if done_cb is not None:
                    done_cb(handle.get_goal_status(), handle.get_result())
        on_feedback = None if feedback_cb is None else (lambda _handle, feedback: feedback_cb(feedback))
        self._handle = self.client.send_goal(goal, on_transition, on_feedback)

    def wait_for_result(self, timeout=rospy.Duration()):
        """True once the goal sent last has ended; False after ``timeout`` of ROS time (not
        positive: no limit) or at shutdown."""
        if self._handle is None:
            return False
        deadline = rospy.get_rostime() + timeout
        while not self._done.wait(0.01):
            if rospy.is_shutdown() or (timeout > rospy.Duration() and rospy.get_rostime() >= deadline):
                return self._done.is_set()
        return True

    def get_state(self):
        if self._handle is None:
            return GoalStatus.LOST
        status = self._handle.get_goal_status()
        return _SIMPLE_STATE.get(status, status)

    def get_goal_status_text(self):
        return self._handle.get_goal_status_text() if self._handle is not None else ''

    def get_result(self):
        return self._handle.get_result() if self._handle is not None else None

    def cancel_goal(self):
        if self._handle is not None:
            self._handle.cancel()
