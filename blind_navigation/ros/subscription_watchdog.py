"""Heals rospy subscriptions that missed a publisher's registration.

Around a subscriber's own registration rospy can miss the master's publisher update;
:func:`watch` checks each new subscription a few times (:data:`CHECK_AFTER`), connects
publishers it has no connection to, and checks the topic's type at the master for an
expected type (ros/wiring.Expected). Costs nothing between checks.
"""
import heapq
import threading
import time

import rosgraph
import rospy
from rospy.impl.registration import RegManager, get_registration_listeners, get_topic_manager

from . import wiring

#: Wall seconds after a subscription at which it is checked.
CHECK_AFTER = (1.0, 3.0, 10.0)

_lock = threading.Condition()
_due = []          # heap of (wall time, topic)
_expected = {}     # topic -> ros/wiring.Expected, for the master's type check
_thread = None


def _registration_manager():
    for listener in get_registration_listeners().listeners:
        if isinstance(listener, RegManager):
            return listener
    return None


def heal_once(master, reg_manager, topics=None):
    """Connect this node's subscriptions (``topics``: resolved names, or all) to
    every publisher the master lists; returns the (topic, publisher URI) pairs
    that were missing."""
    manager = get_topic_manager()
    publishers, _, _ = master.getSystemState()
    by_topic = dict((topic, nodes) for topic, nodes in publishers)
    missing = []
    for topic, _ in manager.get_subscriptions():
        impl = manager.get_subscriber_impl(topic)
        if impl is None or (topics is not None and topic not in topics):
            continue
        uris = [master.lookupNode(node) for node in by_topic.get(topic, [])]
        unconnected = [uri for uri in uris if not impl.has_connection(uri)]
        if unconnected:
            missing += [(topic, uri) for uri in unconnected]
            reg_manager.publisher_update(topic, uris)
    return missing


def watch(subscriber, expected=None):
    """Check ``subscriber``'s topic (a rospy.Subscriber) at :data:`CHECK_AFTER`
    s from now (its type too, with ``expected``); starts the watchdog thread at the
    first call."""
    global _thread
    now = time.monotonic()
    with _lock:
        if expected is not None:
            _expected[subscriber.resolved_name] = expected
        for delay in CHECK_AFTER:
            heapq.heappush(_due, (now + delay, subscriber.resolved_name))
        if _thread is None:
            _thread = threading.Thread(target=_run, name='subscription_watchdog', daemon=True)
            _thread.start()
        _lock.notify()
    return subscriber


def _run():
    reg_manager = _registration_manager()
    if reg_manager is None:
        rospy.logdebug('subscription watchdog: no rospy RegManager; not running')
        return
    master = rosgraph.Master(rospy.get_name())
    while not rospy.is_shutdown():
        with _lock:
            while not _due:
                _lock.wait()
            wait = _due[0][0] - time.monotonic()
            if wait > 0:
                _lock.wait(wait)
                continue
            topics = set()
            while _due and _due[0][0] <= time.monotonic():
                topics.add(heapq.heappop(_due)[1])
        try:
            missing = heal_once(master, reg_manager, topics)
            expected = dict((topic, _expected[topic]) for topic in topics if topic in _expected)
            if expected:
                wiring.check_types(master.getTopicTypes(), expected)
        except Exception as error:      # master busy or gone: the next check tries again
            rospy.logdebug('subscription watchdog: %s', error)
            continue
        for topic, uri in missing:
            rospy.logwarn('%s: reconnected %s to its publisher %s (missed registration)',
                          rospy.get_name(), topic, uri)
