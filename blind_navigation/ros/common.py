"""Small rospy glue shared by every node: subscriptions watched (healed if they missed a
publisher's registration, their types checked at the master: docs/DESIGN.md, "Threads"),
Twist, poses, ROS_HOME."""
import heapq
import itertools
import os
import threading
import time
import xmlrpc.client

import rosgraph
import rospkg
import rospy
from geometry_msgs.msg import Twist, Vector3

from . import faults
from .faults import shutting_down  # noqa: F401 -- the roles' one import of it
from ..core.geometry import quaternion_from_yaw

#: Wall seconds after a subscription at which it is checked.
CHECK_AFTER = (1.0, 3.0, 10.0)

_lock = threading.Condition()
_due = []          # heap of (wall time, sequence, rospy.Subscriber, topic, ros/faults.Expected or None)
_expected = {}     # rospy.Subscriber -> ros/faults.Expected, while subscribed
_sequence = itertools.count()
_thread = None


def heal_once(master, node, subscribers):
    """The master's publishers to each of ``subscribers`` with fewer connections; the topics healed."""
    publishers = dict((topic, nodes) for topic, nodes in master.getSystemState()[0])
    healed = []
    for subscriber in subscribers:
        topic = subscriber.resolved_name
        if topic is None or topic in healed:    # unregistered meanwhile, or done
            continue
        nodes = publishers.get(topic, [])
        if subscriber.get_num_connections() < len(nodes):
            node.publisherUpdate(rospy.get_name(), topic, [master.lookupNode(n) for n in nodes])
            healed.append(topic)
    return healed


def unsubscribe(subscriber):
    """Unregister ``subscriber``; its expected type, if any, checked at the master once more."""
    topic = subscriber.resolved_name
    with _lock:
        expected = _expected.pop(subscriber, None)
    subscriber.unregister()
    if expected is not None and topic is not None:
        with _lock:
            _schedule(None, topic, expected, (0.0,))


def _schedule(subscriber, topic, expected, delays):
    """(under _lock) Check at ``delays`` s from now."""
    global _thread
    now = time.monotonic()
    for delay in delays:
        heapq.heappush(_due, (now + delay, next(_sequence), subscriber, topic, expected))
    if _thread is None:
        _thread = threading.Thread(target=_run, name='subscription_watchdog', daemon=True)
        _thread.start()
    _lock.notify()


def _next_due():
    """The subscriptions due, once due; None at shutdown."""
    with _lock:
        while not rospy.is_shutdown():
            wait = _due[0][0] - time.monotonic() if _due else None    # None: until subscribe()
            if wait is not None and wait <= 0:
                due = []
                while _due and _due[0][0] <= time.monotonic():
                    due.append(heapq.heappop(_due)[2:])
                return due
            _lock.wait(wait)
    return None


def _run():
    master = rosgraph.Master(rospy.get_name())
    node = xmlrpc.client.ServerProxy(rospy.get_node_uri())
    for due in iter(_next_due, None):
        try:
            healed = heal_once(master, node, [s for s, _, _ in due if s is not None])
            expected = dict((topic, e) for _, topic, e in due if e is not None and topic)
            if expected:
                faults.check_types(master.getTopicTypes(), expected)
        except Exception as error:      # master busy or gone: the next check tries again
            rospy.logdebug('subscription watchdog: %s', error)
            continue
        for topic in healed:
            rospy.logwarn('%s: reconnected %s to its publishers (missed registration)',
                          rospy.get_name(), topic)


def subscribe(topic, data_class, callback, callback_args=None, expected=None, **options):
    """``rospy.Subscriber`` checked at :data:`CHECK_AFTER` s (its type too, with ``expected``)."""
    subscriber = rospy.Subscriber(topic, data_class, callback, callback_args, **options)
    with _lock:
        if expected is not None:
            _expected[subscriber] = expected
        _schedule(subscriber, subscriber.resolved_name, expected, CHECK_AFTER)
    return subscriber


def subscribe_checked(topic, data_class, callback, callback_args=None, **options):
    """:func:`subscribe` of ``topic`` as ``data_class``, another type refused."""
    expected = faults.Expected.of(data_class)

    def on_raw(raw, args=None):
        if expected.accepts(topic, raw._connection_header):
            msg = data_class()
            msg.deserialize(raw._buff)
            callback(msg) if callback_args is None else callback(msg, args)
    return subscribe(topic, rospy.AnyMsg, on_raw, callback_args, expected, **options)


def twist(v=0.0, w=0.0):
    """geometry_msgs/Twist with linear.x = v and angular.z = w."""
    return Twist(linear=Vector3(x=v), angular=Vector3(z=w))


def ros_home_file(relative, configured=''):
    """The file ``configured`` (a path param), or if empty ``relative`` under $ROS_HOME."""
    return os.path.abspath(os.path.expanduser(configured.strip() or os.path.join(
        rospkg.get_ros_home(), relative)))


def set_pose(pose_msg, x, y, yaw):
    """Fill a geometry_msgs/Pose in place from a planar pose (x, y in m, yaw in rad)."""
    pose_msg.position.x, pose_msg.position.y = x, y
    q = pose_msg.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(yaw)


class RoleLog(object):
    """rospy logging with the role's name in every line."""

    def __init__(self, prefix):
        self.prefix = prefix + ': '
        self._warned = {}               # text -> when it was last logged (warn_throttle)

    def info(self, text, *args):
        rospy.loginfo(self.prefix + text, *args)

    def warn(self, text, *args):
        rospy.logwarn(self.prefix + text, *args)

    def error(self, text, *args):
        rospy.logerr(self.prefix + text, *args)

    def warn_throttle(self, period, text, *args):
        """``text`` at most once per ``period`` s of this role (rospy's own throttle keys on
        the calling line: this one, for every role and text)."""
        now, last = rospy.get_time(), self._warned.get(text)
        if last is None or not last <= now < last + period:
            self._warned[text] = now
            rospy.logwarn(self.prefix + text, *args)
