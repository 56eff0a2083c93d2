"""What may move the robot: :class:`SafetyMonitor` (bumper, cliff, wheel drop),
:class:`MotionOutput` (one role's ``cmd_vel``, clamped, while it may move),
:class:`TakeoverWatch` (the operator's takeover: nothing sent) and the Kobuki's auto-docking
and battery for the mission owner (:class:`DockingClient`, :func:`subscribe_battery`)."""
import threading

import rospy
from actionlib.action_client import get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from std_msgs.msg import String

from .. import names
from ..core import mission_state
from ..core.battery import reading_problem
from ..core.docking import DockingResult
from ..core.pause import CONTACT_DEFAULTS, Takeover
from ..core.safety import CONTACT, SafetyEvents, VelocityLimits
from . import faults, kobuki_msgs_compat as kobuki
from .common import subscribe, subscribe_checked, twist
from .goal_client import GoalClient

#: How a halt by a safety event begins; kind -> (message class, field naming the sensor)
SAFETY_HALT = 'safety: '
EVENT_TYPES = {'bumper': (kobuki.BumperEvent, 'bumper'), 'cliff': (kobuki.CliffEvent, 'sensor'),
               'wheel_drop': (kobuki.WheelDropEvent, 'wheel')}
#: The layer's nodes that publish on its mux input, in either layout.
LAYER_NODES = ('blind_navigation', 'back_travel_server', 'rotate_pi', 'calibrate_gyro')


class SafetyMonitor(object):
    """The Kobuki's safety events (``active``); ``contact_wait``: s after a release a press bounces."""

    def __init__(self, guard):
        self.contact_wait = CONTACT_DEFAULTS['contact_wait']
        self._events = SafetyEvents()
        self._lock = threading.Lock()
        self._callbacks = []
        for kind, topic in names.SAFETY_EVENTS.items():
            msg_type, index_field = EVENT_TYPES[kind]
            subscribe_checked(topic, msg_type, guard(self._on_event), (kind, index_field),
                              queue_size=10)

    def on_trip(self, callback):
        self._callbacks.append(callback)

    def _on_event(self, msg, args):
        kind, index_field = args
        now = rospy.get_time()
        with self._lock:
            bounce = kind == CONTACT and self._events.continues(kind, now, self.contact_wait)
            reason = self._events.update(kind, getattr(msg, index_field), msg.state, now)
        if reason:
            (rospy.logdebug if bounce else rospy.logerr)(
                '%s: SAFETY STOP: %s%s', rospy.get_name(), reason, ' (a bounce)' if bounce else '')
            for callback in list(self._callbacks):
                callback(reason)

    @property
    def active(self):
        with self._lock:
            return self._events.active

    @property
    def terminal(self):
        """The active conditions other than a bumper contact."""
        with self._lock:
            return self._events.terminal


class MotionOutput(object):
    """The velocity output of ``role``; ``mission``: the MissionStateView (None: no mission)."""

    def __init__(self, role, max_v, max_w, mission=None, safety=None, takeover=None):
        if max_v < 0 or max_w <= 0:
            raise ValueError('velocity limits: need max_v >= 0 and max_w > 0 (max_v %r, max_w %r)'
                             % (max_v, max_w))
        self.role, self.mission = role, mission
        self.max_v, self.max_w = float(max_v), float(max_w)
        self.limits = VelocityLimits(self.max_v, self.max_w)
        self.halted = None          # why, while halted
        self.takeover, self.safety = takeover, safety   # silent during a takeover; halts it
        self._lock = threading.Lock()
        self._pub = rospy.Publisher(names.CMD_VEL, Twist, queue_size=1)
        if safety is not None:
            safety.on_trip(lambda reason: self.halt(SAFETY_HALT + reason))
        if mission is not None:
            mission.on_change(self._on_state)
        faults.on_fault(self.halt)
        rospy.on_shutdown(lambda: self.halt('node shutdown'))

    def _on_state(self, old, new):
        if mission_state.may_move(self.role, old) and not mission_state.may_move(self.role, new):
            self.halt('mission state %s' % new)

    def limit(self, limits):
        """Clamp to ``limits`` (a goal's) as well as the configured ones."""
        with self._lock:
            self.limits = VelocityLimits(min(self.max_v, limits.max_v), min(self.max_w, limits.max_w))

    def publish(self, v, w):
        with self._lock:
            moving = self.halted is None and not faults.faulty() and mission_state.may_move(
                self.role, self.mission.state if self.mission else None)
            self._send(*(self.limits.clamp(v, w) if moving else (0.0, 0.0)))

    def stop(self):
        with self._lock:
            self._send(0.0, 0.0)

    def halt(self, reason):
        with self._lock:
            self.halted = reason
            self._send(0.0, 0.0)

    def release(self):
        with self._lock:
            self.halted = None

    def contact_over(self):
        """Release a safety event's halt once no condition is active; any other halt stays."""
        with self._lock:
            if self.halted and self.halted.startswith(SAFETY_HALT) and self.safety is not None \
                    and not self.safety.active:
                self.halted = None

    def _send(self, v, w):
        if self.takeover is not None and self.takeover.active():
            return                  # the operator drives: never fight a person for the robot
        if self.takeover is not None:
            self.takeover.sent(v, w)    # before it is sent: the mux may echo it at once
        try:
            self._pub.publish(twist(v, w))
        except rospy.ROSException:
            pass  # publisher already closed at shutdown


class TakeoverWatch(object):
    """The operator's takeover, one watch per process (core/pause.Takeover; docs/safety.md,
    "Takeover"): another node's command, a ``takeover_inputs`` input, a command not ours."""

    def __init__(self, params, guard):
        self._takeover = Takeover(params)
        self._lock = threading.Lock()
        self._own = set(rospy.resolve_name(node) for node in LAYER_NODES) | {rospy.get_name()}
        self._base = True           # the mux output is read (not while docking)
        subscribe(names.CMD_VEL, Twist, guard(self._on_command), queue_size=10)
        subscribe(names.CMD_VEL_MUX_ACTIVE, String, guard(self._on_mux), queue_size=10)
        subscribe(names.MUX_OUTPUT, Twist, guard(self._on_output), queue_size=10)

    def sent(self, v, w):
        """This process publishes (v, w) on the mux input."""
        with self._lock:
            self._takeover.sent(v, w, rospy.get_time())

    def watch_base(self, on):
        """Read the mux output (``on``), or not: while docking the dock drive drives it."""
        with self._lock:
            self._base = bool(on)

    def _on_output(self, msg):
        with self._lock:
            if not self._base:
                return
            self._takeover.at_base(msg.linear.x, msg.angular.z, rospy.get_time(),
                                   rospy.resolve_name(names.MUX_OUTPUT))

    def _on_command(self, msg):
        caller = msg._connection_header.get('callerid', '?')
        if caller not in self._own:
            with self._lock:
                self._takeover.command(caller, rospy.get_time())

    def _on_mux(self, msg):
        with self._lock:
            self._takeover.mux_active(msg.data, rospy.get_time())

    def active(self):
        """Why an operator holds the robot now, or None."""
        with self._lock:
            return self._takeover.active(rospy.get_time())

    def paused(self):
        """s paused by takeovers so far."""
        with self._lock:
            self._takeover.active(rospy.get_time())
            return self._takeover.paused(rospy.get_time())


class DockingClient(object):
    """The docking goal of one owner; ``inbox``: its Inbox; ``takeover``: its TakeoverWatch."""

    def __init__(self, inbox, takeover, log):
        self.inbox, self.takeover, self.log = inbox, takeover, log
        # made at start-up: by the docking the server has long been found
        self.client = GoalClient(names.DOCK_DRIVE, kobuki.AutoDockingAction)
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
