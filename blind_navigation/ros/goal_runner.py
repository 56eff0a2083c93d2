"""Sends one action goal at a time and waits for its end, on actionlib's
ActionClient.

actionlib's SimpleActionClient learns the handle of a goal only when
``send_goal`` returns, but the server's first status for that goal can arrive
(on another thread) before that: a server in the same process (the layer's
default, one process) answers within microseconds. SimpleActionClient then
drops the transition as "a goal handle that we're not tracking" (an ERROR in
the log) and may miss the goal's start. Here every goal gets its own
callbacks, bound to that goal, so no transition is ever attributed to the
wrong goal or lost. :attr:`GoalRunner.heard` is when the server last spoke of
the current goal (a transition or feedback): a server that drives a goal
reports feedback all along, however long the goal takes.
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
