"""The Kobuki's auto-docking for the mission owner (dock_at_home): a client of
kobuki_auto_docking's action ``dock_drive_action`` (kobuki_msgs/AutoDocking). The goal is sent when the mission's Step asks (core/docking); its end goes into the owner's
Inbox as ``docking`` (core/docking.DockingResult). While the mission is ``docking`` the dock
drive drives ``mobile_base/commands/velocity`` past the mux, so the takeover watch does not
read that output (ros/takeover.py); once the mission leaves ``docking`` a goal still pending
is cancelled and one zero velocity is published there (docs/safety.md, "Docking").
"""
import threading

import actionlib
import rospy
from actionlib.action_client import get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist

from .. import names
from ..core import mission_state
from ..core.docking import DockingResult
from . import kobuki_msgs_compat as kobuki


class DockingClient(object):
    """The docking goal of one owner; ``inbox``: its Inbox; ``takeover``: its TakeoverWatch."""

    def __init__(self, inbox, takeover, log):
        self.inbox, self.takeover, self.log = inbox, takeover, log
        # made at start-up: by the docking the server has long been found
        self.client = actionlib.SimpleActionClient(names.DOCK_DRIVE, kobuki.AutoDockingAction)
        self.velocity = rospy.Publisher(names.MUX_OUTPUT, Twist, queue_size=1)
        self._lock = threading.Lock()
        self._goal = 0              # the goal's number; 0: none pending
        log.info('dock_at_home: once home, the mission docks with %s',
                 rospy.resolve_name(names.DOCK_DRIVE))

    def start(self):
        """Send the docking goal; without the auto-docking server the mission hears why not
        (its Inbox), at once (one look: a deadline already past; a zero timeout waits forever)."""
        now = rospy.get_rostime()
        if now.is_zero() or not self.client.wait_for_server(rospy.Duration(-now.secs, -now.nsecs)):
            self.inbox.put(docking=DockingResult(False, 'no auto-docking action server on %s' %
                                                 rospy.resolve_name(names.DOCK_DRIVE)))
            return
        with self._lock:
            self._goal += 1
            goal = self._goal
            self.client.send_goal(kobuki.AutoDockingGoal(), done_cb=lambda status, result:
                                  self._done(goal, status, result))
        self.log.info('docking: the auto-docking goal is sent')

    def _done(self, goal, status, result):
        with self._lock:
            if goal != self._goal:
                return
            self._goal = 0
        text = getattr(result, 'text', '') or 'the auto-docking goal ended %s' % get_name_of_constant(
            GoalStatus, status)
        self.inbox.put(docking=DockingResult(status == GoalStatus.SUCCEEDED, text))

    def state(self, new):
        """The mission moved to ``new``: the base watched or not; a pending goal cancelled
        (and the base stopped) once it leaves ``docking``."""
        self.takeover.watch_base(new != mission_state.DOCKING)
        if new != mission_state.DOCKING:
            self.cancel('the mission is %s' % new)

    def cancel(self, why):
        """Cancel a pending goal and stop the base (one zero velocity past the mux)."""
        with self._lock:
            pending, self._goal = self._goal, 0
        if pending:
            self.client.cancel_goal()
            self.velocity.publish(Twist())
            self.log.info('docking: the auto-docking goal is cancelled (%s)', why)
