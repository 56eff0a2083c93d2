"""Shared rig of the safety rostests (test_safety_*.py): a sim clock owned by the
test, a straight recorded path (landmarks written by the test as a recorder
would, the ideal FakeBase at its end), layer nodes started and killed by the
test (rosrun), state and /rosout collectors, and the walk of a
back_travel_client (the mission's owner) to ``returning``: recording,
vision lost, the base turned by pi (the client checks the real turn), the pi
turn reported done."""
import contextlib
import math
import os
import signal
import subprocess
import threading
import time

import roslib.packages
import rospy
from rosgraph_msgs.msg import Clock, Log
from std_msgs.msg import Bool, Empty, String

from blind_navigation.core.landmark import Landmark
from blind_navigation.core.mission_state import TERMINAL
from blind_navigation.core.mission_files import LandmarkWriter
from blind_navigation.msg import StorageUsage

from fake_base import FakeBase
from recording_tools import Collector  # noqa: F401 (the safety tests import it from here)
from waiting import wait_for

SIM_BASE = 100.0       # s, sim time at the start (rospy treats 0 as unset)
CLOCK_STEP = 0.01      # s of sim time per /clock message


class SimClock(object):
    """Publishes /clock in a thread, ``rtf`` x real time."""

    def __init__(self, rtf=1.0):
        self._pub = rospy.Publisher('/clock', Clock, queue_size=10)
        self.t = SIM_BASE
        self.rtf = rtf
        self._lock = threading.Lock()
        self._frozen = False
        threading.Thread(target=self._run, daemon=True).start()
        wait_for(lambda: rospy.get_time() >= SIM_BASE, 'the test sees its own /clock')

    @contextlib.contextmanager
    def frozen(self):
        """Sim time stands still inside (``with clock.frozen() as t``), once this process
        sees the frozen time ``t``: whatever reacts meanwhile reacts in a callback, at
        once, and its sim time is ``t`` however late the machine runs it. A reaction
        that waits for the next control cycle cannot happen until the clock goes on."""
        with self._lock:
            self._frozen = True
            t = rospy.Time.from_sec(self.t).to_sec()     # as published: whole nanoseconds
        try:
            wait_for(lambda: rospy.get_time() >= t, 'the test sees the frozen clock')
            yield t
        finally:
            self._frozen = False

    @contextlib.contextmanager
    def slowed(self, rtf):
        """Sim time runs at ``rtf`` x real time inside (``with clock.slowed(0.2)``). For a
        reaction a node leaves to its next control cycle, which a frozen clock would
        never let happen: the machine's scheduling and delivery delays then count only
        ``rtf`` x in the sim-time latency, so what is asserted is the node's own design
        (its timeout and control period), not how loaded the test machine was."""
        previous, self.rtf = self.rtf, rtf
        try:
            yield
        finally:
            self.rtf = previous

    def _run(self):
        next_wall = time.monotonic()
        while not rospy.is_shutdown():
            with self._lock:
                if not self._frozen:
                    self.t += CLOCK_STEP
                t = self.t
            try:
                self._pub.publish(Clock(clock=rospy.Time.from_sec(t)))
            except rospy.ROSException:
                return
            next_wall += CLOCK_STEP / self.rtf
            time.sleep(max(0.0, next_wall - time.monotonic()))


def straight_landmarks(speeds, period=2.0):
    """A straight path along +x, one landmark per speed (d = v T)."""
    return [Landmark(v, 0.0, v * period, period, 0.0) for v in speeds]


def write_mission(directory, landmarks, name='landmarks', mission=None):
    """A recorder-like mission: a time-stamped file (of ``mission``, an id, if given),
    finished as at vision loss, and the ``<name>.yaml`` symlink to it. Returns
    (symlink path, real file path)."""
    os.makedirs(directory, exist_ok=True)
    real = os.path.join(directory, '%s-20240101-000000.yaml' % name)
    link = os.path.join(directory, name + '.yaml')
    for path in (real, link):
        if os.path.lexists(path):
            os.remove(path)
    writer = LandmarkWriter(real, {'mission': mission} if mission else None, fsync=False)
    for landmark in landmarks:
        writer.append(landmark)
    writer.finish()
    os.symlink(os.path.basename(real), link)
    return link, real


def path_length(landmarks):
    return sum(landmark.d for landmark in landmarks)


class Node(object):
    """A layer node started by the test (the package's executable, params as
    ``_name:=value``, remaps as ``from:=to``); :meth:`kill` ends it with a signal,
    waits and deletes the params it was given (rospy keeps them on the parameter server:
    a later node of that name would start with them)."""

    def __init__(self, node_type, name, params=None, remaps=None):
        found = roslib.packages.find_node('blind_navigation', node_type)
        if not found:
            raise AssertionError('node %s not found in the workspace' % node_type)
        args = [found[0], '__name:=' + name]
        args += ['_%s:=%s' % (key, value) for key, value in (params or {}).items()]
        args += ['%s:=%s' % item for item in (remaps or {}).items()]
        self.name, self.params = name, dict(params or {})
        self.process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        start_new_session=True)

    def kill(self, sig=signal.SIGINT, timeout=20.0):
        if self.process.poll() is None:
            os.killpg(self.process.pid, sig)
            try:
                self.process.wait(timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait(timeout)
        for key in self.params:
            try:
                rospy.delete_param('/%s/%s' % (self.name.lstrip('/'), key))
            except KeyError:
                pass                    # deleted already (a second kill)


#: Sim time's pace (x real time) of :func:`shared_rig`'s clock: nothing is timed against the
#: machine (a case that times a stop freezes or slows the clock: SimClock.frozen, .slowed),
#: and the clock and the base share the test's process, so a stall of it stalls both alike.
BASE_RTF = 3.0
#: What a back_travel_client started by a test needs (the launch files set it); no
#: vision_back_grace: the test plays the paper's rotate_pi, the turn begins at vision loss;
#: its wait for the action server (10 s) held in wall time at BASE_RTF, as
#: mission_rig.launch does (connecting takes wall time).
CLIENT_PARAMS = {'heading_correction': 'false', 'prune_loops': 'false', 'vision_back_grace': '0.0',
                 'server_timeout': str(10.0 * BASE_RTF)}
#: What a back_travel_server started by a test needs (the launch files set it).
SERVER_PARAMS = {'control': 'closed_loop'}


class Layer(object):
    """The mission-state side of a test: state and /rosout collectors and the
    publishers that walk a fresh client from idle to returning."""

    def __init__(self, prefix='/blind_navigation'):
        self.prefix = prefix
        self.states = Collector(prefix + '/state', String)
        self.rosout = Collector('/rosout', Log)
        self.storage = rospy.Publisher(prefix + '/storage', StorageUsage, queue_size=1)
        self.vision_lost = rospy.Publisher(prefix + '/vision_lost', Empty, queue_size=1)
        self.rotation_done = rospy.Publisher(prefix + '/rotation_done', Bool, queue_size=1)

    def state_list(self, since=0):
        return [msg.data for msg in self.states.snapshot(since)]

    def walk_to_returning(self, since, base, timeout=60.0):
        """idle -> recording -> rotating -> returning for the client started after
        ``since`` states, turning ``base`` (a FakeBase) by pi after vision loss."""
        self.walk_to_rotating(since, timeout)
        base.turn(math.pi)
        self.finish_rotation(since, timeout)

    def walk_to_rotating(self, since, timeout=60.0, target='rotating'):
        """idle -> recording (a storage message) -> ``target`` (vision_lost): rotating, or
        aborted where the client refuses the return before the turn."""
        wait_for(lambda: 'idle' in self.state_list(since), 'the new client publishes idle', timeout)
        # a recording of 1 m: asked home before the robot moved, the client ends home at once
        self._publish_until(self.storage, StorageUsage(file='x', distance=1.0), 'recording', since,
                            timeout)
        self._publish_until(self.vision_lost, Empty(), target, since, timeout)

    def finish_rotation(self, since, timeout=60.0):
        """rotating -> returning: rotation_done true (after the base really turned)."""
        self._publish_until(self.rotation_done, Bool(data=True), 'returning', since, timeout)

    def _publish_until(self, publisher, msg, target, since, timeout):
        """Publish ``msg`` every 0.2 s until the state ``target`` is seen."""
        deadline = time.monotonic() + timeout
        while target not in self.state_list(since):
            if time.monotonic() > deadline:
                raise AssertionError('state %s not reached (states %s)'
                                     % (target, self.state_list(since)))
            publisher.publish(msg)
            time.sleep(0.2)

    def wait_final(self, since, timeout=120.0):
        wait_for(lambda: set(self.state_list(since)) & set(TERMINAL),
                 'state home or aborted', timeout)
        return self.state_list(since)[-1]

    def logged(self, node, text, since=0):
        """/rosout lines of ``node`` containing ``text`` (from the ``since``-th line on)."""
        return [m.msg for m in self.rosout.snapshot(since) if m.name == node and text in m.msg]

    def reason_unless(self, final, expected, node, since=0):
        """'' when ``final`` is ``expected``, else ``node``'s abort line: an assert's message,
        waited for (:meth:`abort_reason`) only where the assert fails."""
        return '' if final == expected else self.abort_reason(node, since)

    def abort_reason(self, node, since=0, timeout=10.0):
        """``node``'s last abort line; its /rosout line may come after the state (another
        connection): wait at most ``timeout`` s (wall) for it, '' if none came."""
        deadline = time.monotonic() + timeout
        while not self.logged(node, '-> aborted', since) and time.monotonic() < deadline:
            time.sleep(0.05)
        lines = self.logged(node, '-> aborted', since)
        return lines[-1] if lines else ''


#: What :func:`shared_rig` made (once per node).
_SHARED = []


def shared_rig():
    """(SimClock at BASE_RTF, ideal FakeBase at the origin, Layer) of this node, made at the
    first call; later calls return the same: two clocks or bases would both publish."""
    if not _SHARED:
        clock = SimClock(rtf=BASE_RTF)
        _SHARED.extend([clock, FakeBase(), Layer()])
    return tuple(_SHARED)


def first_zero_after(commands, t0):
    """(time, index) of the first zero command received at or after t0, or None."""
    for index, (stamp, v, w) in enumerate(commands):
        if stamp >= t0 and v == 0.0 and w == 0.0:
            return stamp, index
    return None


def moving(base):
    return abs(base.v) > 1e-6 or abs(base.w) > 1e-6


def distance_from_origin(base):
    return math.hypot(base.x, base.y)
