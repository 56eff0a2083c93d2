"""The Kobuki's auto-docking and battery for the mission owner's Inbox: :class:`DockingClient`
(docs/safety.md, "Docking") and :func:`subscribe_battery`."""
import threading

import actionlib
import rospy
from actionlib.action_client import get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist

from .. import names
from ..core import mission_state
from ..core.battery import reading_problem
from ..core.docking import DockingResult
from . import kobuki_msgs_compat as kobuki
from .common import subscribe_checked


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
        """Send the docking goal; without the server, why not into the Inbox at once (one look:
        a deadline already past, as a zero timeout waits forever)."""
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
        """The mission moved to ``new``: leaving ``docking`` cancels a pending goal."""
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


def subscribe_battery(threshold, inbox, guard, log):
    """With ``threshold`` (battery_low, V) > 0: each SensorState's battery (V) put into ``inbox``."""
    if not threshold > 0:
        return

    def on_core(msg):
        volts = msg.battery / 10.0
        problem = reading_problem(volts)
        if problem:
            rospy.logwarn_throttle(10.0, '%s: battery reading ignored: %s'
                                   % (rospy.get_name(), problem))
        inbox.put(battery=volts)
    log.info('battery_low %.1f V: a battery below it on %s while recording starts the return',
             threshold, rospy.resolve_name(names.CORE_SENSORS))
    subscribe_checked(names.CORE_SENSORS, kobuki.SensorState, guard(on_core), queue_size=1)
