"""One odometry subscription per process, shared by its roles (:class:`OdometryFeed`): raw
nav_msgs/Odometry behind the plausibility gate, resets carried across and their frame shared
(docs/safety.md, "Odometry resets"), a history, the corrected frame once set."""
import threading
import time

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from rospy.rostime import is_wallclock

from ..core.geometry import yaw_from_quaternion
from ..core.heading_correction import CorrectedOdometry
from ..core.odometry_reset import Frame, ResetCarrier
from ..core.odometry_wire import odom_state, read_odometry
from ..core.plausibility import OdometryGate
from ..core.recorder import OdometryHistory
from ..core.vision import wire_lost_reason
from .common import set_pose, subscribe, unsubscribe
from .faults import Expected

#: No receive queue limit: with one, a receive thread that fell behind leaves holes in the history.
RECEIVE_QUEUE = None


def ros_time():
    """rospy.get_time(), without building a rospy.Time under wall time (once per message)."""
    return time.time() if is_wallclock() else rospy.get_time()


def visual_yaw(wire):
    """The yaw of a visual-odometry message (core/odometry_wire.WireOdometry), None if lost."""
    return yaw_from_quaternion(wire.qx, wire.qy, wire.qz, wire.qw) if wire_lost_reason(wire) is None else None


class OdometryFeed(object):
    """Shared odometry of ``topic``."""

    def __init__(self, topic, guard, checked=True, frame_topic=None):
        self.topic, self.checked = topic, checked
        self._on_message_guarded = guard(self._on_message)
        self.carrier = ResetCarrier(OdometryGate()) if checked else None
        self.expected = Expected.of(Odometry)
        self._reanchor_listeners, self._holders = [], set()
        self.lost = None            # why the odometry's frame is lost (an untrusted reset), or None
        self.frame_id = 'odom'
        self._lock, self.carrier_lock = threading.Condition(), threading.Lock()  # the state; a message
        self._waiting = 0           # threads waiting for a state: notified per state
        self._subscriber = self._subscribed_at = None     # and when (rospy time) it began
        self._states = OdometryHistory()    # the accepted OdomStates
        self._received = None       # rospy time (s) the newest accepted state arrived
        self._listeners = self._raw_listeners = ()     # f(state) per accepted state; f(wire) per message
        self._corrector, self._new_subscription = None, False
        self.refused = 0            # messages not used (invalid or implausible)
        self._frame_pub = None      # a reset's frame shared with the other nodes' feeds
        if checked and frame_topic:
            self._frame_pub = rospy.Publisher(frame_topic, PoseStamped, queue_size=1, latch=True)
            subscribe(frame_topic, PoseStamped, guard(self._on_frame))

    def acquire(self, holder):
        """``holder`` (any hashable) needs this odometry."""
        with self._lock:
            self._holders.add(holder)
            if self._subscriber is None:
                self._subscriber = subscribe(self.topic, rospy.AnyMsg, self._on_message_guarded,
                                             expected=self.expected, queue_size=RECEIVE_QUEUE,
                                             tcp_nodelay=True)
                self._subscribed_at = ros_time()
                self._new_subscription = True   # what happened unheard is no jump to check

    def release(self, holder):
        """``holder`` no longer needs it: unsubscribe when nobody does."""
        with self._lock:
            self._holders.discard(holder)
            subscriber = self._subscriber if not self._holders else None
            if subscriber is not None:
                self._subscriber = None
                self.lost = None    # the next holder starts on the frame it finds
        if subscriber is not None:
            unsubscribe(subscriber)

    def add_listener(self, callback, raw=False):
        """``callback(state)`` for every accepted state; ``raw``: ``callback(wire)`` for every message."""
        with self._lock:
            if raw:
                self._raw_listeners += (callback,)
            else:
                self._listeners += (callback,)

    def on_reanchor(self, callback):
        """``callback(reason, trusted)`` when the gate re-anchored (``trusted``: carried across)."""
        self._reanchor_listeners.append(callback)

    def _on_frame(self, msg):
        """Another node's feed carried a reset across: take its frame unless this one did."""
        q = msg.pose.orientation
        frame = Frame(msg.pose.position.x, msg.pose.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
        with self.carrier_lock:
            taken = self.carrier.adopt(frame, msg.header.stamp.to_sec())
            if taken == 'restart':
                with self._lock:    # taken in the odometry's new frame as it came
                    self._states.clear()
        if taken:
            rospy.logwarn('%s: odometry on %s: the frame %s carried a reset at %.3f s across with: '
                          '(%.3f, %.3f, %.3f)', rospy.get_name(), rospy.resolve_name(self.topic),
                          msg._connection_header.get('callerid', '?'), msg.header.stamp.to_sec(),
                          *frame)

    def remove_listener(self, callback):
        with self._lock:
            self._listeners = tuple(c for c in self._listeners if c != callback)
            self._raw_listeners = tuple(c for c in self._raw_listeners if c != callback)

    def _on_message(self, msg):
        if self.expected.accepts(self.topic, msg._connection_header):
            with self.carrier_lock:     # a frame adopted meanwhile waits (_on_frame)
                self._take(msg._buff)

    def _take(self, buff):
        try:
            wire = read_odometry(buff)
        except ValueError as error:
            self._refuse('not a nav_msgs/Odometry: %s' % error)
            return
        for listener in self._raw_listeners:     # a tuple: replaced, never changed, when edited
            listener(wire)
        if not self.checked:
            return
        try:
            state = odom_state(wire)
        except ValueError as error:
            self._refuse(str(error))
            return
        if self._new_subscription:
            self._new_subscription = False
            self.carrier.gate.reset()       # the first state heard now is the reference
        taken = self.carrier.take(state)
        if taken.problem:
            self._refuse(taken.problem)
            return
        reset = taken.reset
        now = ros_time()
        with self._lock:
            if reset is not None and reset.frame is None:
                self._states.clear()        # the history before it is another frame
                self.lost = reset.reason
            for state in taken.states:      # (a stamp going back: sim time reset, a new history)
                self._states.append(state)
                if self._corrector is not None:
                    self._corrector.update(state)
            if self.lost is None:
                self._received = now
            self.frame_id = wire.frame_id or self.frame_id
            listeners = self._listeners
            if self._waiting:
                self._lock.notify_all()
        for state in taken.states:
            for listener in listeners:
                listener(state)
        if reset is None:
            return
        trusted = reset.frame is not None      # a re-anchor: logged, a trusted one's frame shared
        (rospy.logwarn if trusted else rospy.logerr)('%s: %s', rospy.get_name(), reset.reason)
        if trusted and self._frame_pub is not None:
            msg = PoseStamped()
            msg.header.stamp = rospy.Time.from_sec(self.carrier.reset_stamp)
            msg.header.frame_id = self.frame_id
            set_pose(msg.pose, *self.carrier.frame)
            self._frame_pub.publish(msg)
        for callback in list(self._reanchor_listeners):
            callback(reset.reason, trusted)

    def _refuse(self, reason):
        self.refused += 1
        rospy.logwarn_throttle(5.0, '%s: odometry on %s not used: %s'
                               % (rospy.get_name(), rospy.resolve_name(self.topic), reason))

    def latest(self):
        with self._lock:
            return self._states.latest

    def state_at(self, stamp, wait=0.0):
        """The newest raw state stamped at or before ``stamp`` (else the oldest kept), waiting at
        most ``wait`` s (wall) for one stamped at or after it."""
        with self._lock:
            if wait > 0:
                self._wait_for(lambda: self._states.latest is not None and self._states.latest.stamp >= stamp,
                               wait)
            return self._states.at(stamp)

    def _wait_for(self, predicate, timeout):
        self._waiting += 1
        try:
            return self._lock.wait_for(predicate, timeout=timeout)
        finally:
            self._waiting -= 1

    def age(self):
        """s since the newest accepted state (the frame lost: the last before) arrived; None: none."""
        with self._lock:
            received = self._received
        return None if received is None else ros_time() - received

    def listening(self):
        """s since the current subscription began, None while not subscribed."""
        with self._lock:
            since = self._subscribed_at if self._subscriber is not None else None
        return None if since is None else ros_time() - since

    def fresh(self, timeout):
        """The newest state (corrected once set) stamped now if fresh within ``timeout`` s, else None."""
        now = ros_time()
        with self._lock:
            if self.lost is not None or self._received is None or now - self._received > timeout:
                return None
            state = self._corrector.state if self._corrector is not None else self._states.latest
        return state._replace(stamp=now)

    def wait_fresh(self, timeout, wait=0.0):
        """:meth:`fresh`, waiting at most ``wait`` s (wall) for a state."""
        with self._lock:
            return self._wait_for(lambda: self.fresh(timeout), wait)

    def describe_missing(self, timeout):
        """Why :meth:`fresh` returned None, for logs and results."""
        topic = rospy.resolve_name(self.topic)
        if self.lost is not None:
            return 'the odometry on %s cannot be used: %s' % (topic, self.lost)
        if self._received is None:
            return 'no valid odometry received on %s' % topic
        return 'odometry on %s is older than %.2f s' % (topic, timeout)

    def set_correction(self, correction, reference):
        """:meth:`fresh` in ``correction``'s frame (the raw one at ``reference``); None: the raw frame."""
        with self._lock:
            self._corrector = None if correction is None else CorrectedOdometry.started(
                correction, reference, self._states.latest)
            self.lost = None if correction is None else self.lost
