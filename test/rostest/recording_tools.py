"""Helpers shared by the recording rostests (test_recording_*.py): graph waits,
topic collectors, /diagnostics statuses, the yaml-cpp reader, SIGKILL of a node by name."""
import os
import signal
import subprocess
import threading
import xmlrpc.client

import rosgraph
import roslib.packages
import rosnode
import rospy
import yaml
from diagnostic_msgs.msg import DiagnosticArray

import waiting

WALL_TIMEOUT = 30.0         # s, for anything that waits on the graph
CALLER = '/recording_test'


def wait_for(condition, message, timeout=WALL_TIMEOUT):
    """Wait until ``condition()``; fail with ``message`` (see waiting.wait_for)."""
    waiting.wait_for(condition, message, timeout, poll=0.05)


def subscribers_of(topic):
    """Nodes subscribed to ``topic`` (resolved in this node's namespace)."""
    topic = rospy.resolve_name(topic)
    _, subscribers, _ = rosgraph.Master(CALLER).getSystemState()
    return {node for name, nodes in subscribers if name == topic for node in nodes}


class Collector(object):
    """Keeps every message of one topic, thread-safe; ``items`` holds (sim receive time, msg)."""

    def __init__(self, topic, msg_type):
        self.items, self._lock = [], threading.Lock()
        self.sub = rospy.Subscriber(topic, msg_type, self._on_msg, queue_size=100)

    def _on_msg(self, msg):
        with self._lock:
            self.items.append((rospy.get_time(), msg))

    def snapshot(self, since=0):
        """The messages from the ``since``-th on."""
        with self._lock:
            return [msg for _, msg in self.items[since:]]

    def __len__(self):
        with self._lock:
            return len(self.items)

    def drop_before(self, count):
        """Forget the first ``count`` messages (those of an earlier mission)."""
        with self._lock:
            del self.items[:count]


class Diagnostics(object):
    """The newest /diagnostics status of each name (``<node>: <role>: <check>``), thread-safe.
    Unlike a log line, which is lost when the node logs it before this node's /rosout
    subscription connected, a status is published again every second."""

    def __init__(self):
        self._lock, self._latest = threading.Lock(), {}
        self.sub = rospy.Subscriber('/diagnostics', DiagnosticArray, self._on_msg, queue_size=50)

    def _on_msg(self, msg):
        with self._lock:
            for status in msg.status:
                self._latest[status.name] = status

    def status(self, name, key=None):
        """(summary message, {key: value}) of the newest status ``name``, or None; with
        ``key``, None until a status holds that value (diagnostic_updater first
        publishes each status as 'Node starting up', without values)."""
        with self._lock:
            status = self._latest.get(name)
        values = {} if status is None else {kv.key: kv.value for kv in status.values}
        return None if status is None or (key and key not in values) else (status.message, values)

    def level(self, name):
        """The level (DiagnosticStatus.OK, WARN, ERROR, ...) of the newest status ``name``, or None."""
        with self._lock:
            status = self._latest.get(name)
        return None if status is None else status.level


def landmark_info(path):
    """Run the yaml-cpp reader; its YAML output as a dict."""
    found = roslib.packages.find_node('blind_navigation', 'landmark_info')
    if not found:
        raise AssertionError('landmark_info is not built (tools/landmark_info.cpp)')
    output = subprocess.run([found[0], '--list', path],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True,
                            timeout=WALL_TIMEOUT)
    if output.returncode != 0:
        raise AssertionError('landmark_info %s failed (%d): %s' % (path, output.returncode,
                                                                   output.stderr))
    return yaml.safe_load(output.stdout)


def node_pid(name):
    """The process id of ROS node ``name`` (from its own XML-RPC API; the master is asked
    each time: rosnode's cache would give a node killed earlier under the same name)."""
    uri = rosnode.get_api_uri(rosgraph.Master(CALLER), name, skip_cache=True)
    if not uri:
        raise AssertionError('node %s is not registered with the master' % name)
    code, message, pid = xmlrpc.client.ServerProxy(uri).getPid(CALLER)
    if code != 1:
        raise AssertionError('getPid of %s failed: %s' % (name, message))
    return pid


def kill_node(name):
    """SIGKILL the process of ROS node ``name``; returns its pid."""
    pid = node_pid(name)
    os.kill(pid, signal.SIGKILL)
    return pid
