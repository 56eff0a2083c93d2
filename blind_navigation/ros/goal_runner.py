"""Sends one action goal at a time and waits for its end, on actionlib's ActionClient.

Each goal gets callbacks bound to it, so a status that arrives before ``send_goal``
returns (a server in the same process) is never lost, as SimpleActionClient can lose
it; :attr:`GoalRunner.heard` is when the server last spoke of the current goal.
"""
import threading

import actionlib
import rospy
from actionlib.action_client import CommState, get_name_of_constant
from actionlib_msgs.msg import GoalStatus


class GoalRunner(object):
    """``action``: the action's name; ``action_spec``: its Action class."""

    def __init__(self, action, action_spec):
        self.client = actionlib.ActionClient(action, action_spec)
        self._handle = None
        self._done = threading.Event()
        self.status = None
        self.text = ''
        self.result = None
        self.feedback = None
        self.heard = None           # rospy time the server last spoke of the current goal

    def wait_for_server(self, timeout):
        """True once the action server is up (``timeout``: a rospy.Duration)."""
        return self.client.wait_for_server(timeout)

    def send(self, goal):
        """Send ``goal``; the previous one must have ended."""
        self._done.clear()
        self.status, self.text, self.result, self.feedback = None, '', None, None
        self.heard = rospy.get_time()
        done, state = self._done, {}

        def on_transition(handle):
            if not done.is_set():
                self.heard = rospy.get_time()
            if handle.get_comm_state() == CommState.DONE and not done.is_set():
                state.update(status=handle.get_goal_status(), text=handle.get_goal_status_text(),
                             result=handle.get_result())
                self.status, self.text, self.result = state['status'], state['text'], state['result']
                done.set()

        def on_feedback(_handle, feedback):
            if not done.is_set():
                self.feedback = feedback
                self.heard = rospy.get_time()

        self._handle = self.client.send_goal(goal, on_transition, on_feedback)

    def wait(self, timeout):
        """True once the goal ended within ``timeout`` wall seconds."""
        return self._done.wait(timeout)

    def cancel(self):
        """Ask the server to cancel the goal."""
        if self._handle is not None and not self._done.is_set():
            self._handle.cancel()

    @property
    def succeeded(self):
        return self.status == GoalStatus.SUCCEEDED

    def describe(self):
        """The goal's end, e.g. ``ABORTED: time allowance ...``."""
        name = get_name_of_constant(GoalStatus, self.status) if self.status is not None else 'UNKNOWN'
        return '%s: %s' % (name, self.text) if self.text else name
