"""Heals rospy subscriptions that never connected to a publisher.

rospy can miss a master's publisherUpdate when a subscriber and a publisher of
the same topic register at the same moment: the subscriber then never connects
to that publisher and never hears it (seen in this package's tests: rotate_pi
never received /blind_navigation/vision_lost, so the robot did not turn). The
watchdog asks the master, every ``period`` s of wall time, which nodes publish
each topic this node subscribes to, and hands the URIs of publishers it has no
connection to, to rospy's own publisher-update path, which connects them.
Uses rospy 1.15's registration internals (the Noetic line); does nothing if
they are not there.
"""
import threading
import time

import rosgraph
import rospy
from rospy.impl.registration import RegManager, get_registration_listeners, get_topic_manager


def _registration_manager():
    for listener in get_registration_listeners().listeners:
        if isinstance(listener, RegManager):
            return listener
    return None


def heal_once(master, reg_manager):
    """Connect this node's subscriptions to every publisher the master lists; returns
    the (topic, publisher URI) pairs that were missing."""
    topics = get_topic_manager()
    publishers, _, _ = master.getSystemState()
    by_topic = dict((topic, nodes) for topic, nodes in publishers)
    missing = []
    for topic, _ in topics.get_subscriptions():
        impl = topics.get_subscriber_impl(topic)
        if impl is None:
            continue
        uris = [master.lookupNode(node) for node in by_topic.get(topic, [])]
        unconnected = [uri for uri in uris if not impl.has_connection(uri)]
        if unconnected:
            missing += [(topic, uri) for uri in unconnected]
            reg_manager.publisher_update(topic, uris)
    return missing


def start(period=2.0):
    """Run the watchdog in a daemon thread for the rest of the node's life."""
    reg_manager = _registration_manager()
    if reg_manager is None:
        rospy.logdebug('subscription watchdog: no rospy RegManager; not started')
        return

    def watch():
        master = rosgraph.Master(rospy.get_name())
        strikes = {}
        while not rospy.is_shutdown():
            time.sleep(period)
            try:
                missing = heal_once(master, reg_manager)
            except Exception as error:      # master busy or gone: try again next period
                rospy.logdebug('subscription watchdog: %s', error)
                continue
            for topic, uri in missing:
                # A connection being set up right now is not missing yet: report only
                # publishers still unconnected at the next check.
                strikes[(topic, uri)] = strikes.get((topic, uri), 0) + 1
                if strikes[(topic, uri)] == 2:
                    rospy.logwarn('%s: reconnected %s to its publisher %s (missed registration)',
                                  rospy.get_name(), topic, uri)
            strikes = dict((key, count) for key, count in strikes.items() if key in missing)

    threading.Thread(target=watch, name='subscription_watchdog', daemon=True).start()
