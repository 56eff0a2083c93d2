"""Rig of safety_findings.test: issue 16's findings reproduced on the fake TurtleBot.

The fake TurtleBot runs for the whole test (safety_findings.test includes
mission_rig.launch with ``layer:=false``); the layer is started by the test once
per mission (:class:`FindingMission`: mission_rig.launch with ``fake:=false``,
so blind_navigation.launch as a user starts it, with a fresh mission id and
landmark directory), because after ``home`` or ``aborted`` nothing may move until
a new mission starts. A FindingMission watches what the findings' checks need:
the mission (mission_tools.MissionRun), the layer's velocity commands on the
mux input (every Twist not from the operator), the ground-truth track, /rosout,
/diagnostics and the mission status; :meth:`FindingMission.still_after` is the
common verdict "no motion command after the terminal state, and the robot
stands still".
"""
import atexit
import bisect
import os
import shutil
import signal
import subprocess
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from std_srvs.srv import Trigger

from blind_navigation import names
from blind_navigation.core.geometry import wrap_angle, yaw_from_quaternion
from blind_navigation.msg import MissionStatus, PathSample

from mission_tools import FINAL_STATES, TELEOP_TOPIC, MissionRun
from recording_tools import Collector, Diagnostics
from safety_rig import Node
from waiting import wait_for

#: The scripted operator's node (mission_tools.MissionRun.start_operator): its Twists are not the layer's.
OPERATOR = '/mission_driver'
#: The 2.3 m mission the issue's faults were tried on (config/missions/test_safety.yaml).
MISSION = 'test_safety'
#: m from the start a closed-loop return ends within on the ideal profile (the limit of
#: lane_mission_closed_loop.test and the other closed-loop missions): "home within normal accuracy".
NORMAL_ACCURACY = 0.075
#: s wall any one wait of a mission may take (layer start-up, a phase of the mission).
WALL_TIMEOUT = 90.0
#: s of sim time the base needs to stop after the last command (the paper profile's motor
#: time constant 0.25 s, as mission_tools.SETTLE; the ideal base stops at once).
SETTLE = 1.0
#: Where each mission's landmark directory is made (as mission_rig.launch's default).
TEST_ROOT = os.path.join(os.environ.get('ROS_HOME', os.path.expanduser('~/.ros')), 'blind_navigation_test')
#: Ground-truth motion that still counts as standing still over a watch window: m, rad.
STILL_DISTANCE = 0.005
STILL_TURN = 0.01


class Track(object):
    """Ground-truth poses of the fake base, (sim receive time, x, y, yaw), thread-safe."""

    def __init__(self):
        self._lock = threading.Lock()
        self._times, self._poses = [], []
        self.sub = rospy.Subscriber('/ground_truth/odom', Odometry, self._on_msg, queue_size=200)

    def _on_msg(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        with self._lock:
            self._times.append(rospy.get_time())
            self._poses.append((p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)))

    def at(self, stamp):
        """The pose (x, y, yaw) last received at or before ``stamp`` (s of sim time)."""
        with self._lock:
            index = bisect.bisect_right(self._times, stamp) - 1
            if index < 0:
                raise AssertionError('no ground truth received before %.2f s' % stamp)
            return self._poses[index]

    def motion(self, since, until):
        """(largest distance m, largest |yaw change| rad) from the pose at ``since``
        over the poses received up to ``until``."""
        x0, y0, yaw0 = self.at(since)
        with self._lock:
            start = bisect.bisect_right(self._times, since)
            end = bisect.bisect_right(self._times, until)
            poses = self._poses[start:end]
        return (max([((x - x0) ** 2 + (y - y0) ** 2) ** 0.5 for x, y, _ in poses] or [0.0]),
                max([abs(wrap_angle(yaw - yaw0)) for _, _, yaw in poses] or [0.0]))

    def length(self, since, until):
        """Path length (m) driven from ``since`` to ``until``."""
        with self._lock:
            start = max(bisect.bisect_right(self._times, since) - 1, 0)
            end = bisect.bisect_right(self._times, until)
            points = [pose[:2] for pose in self._poses[start:end]]
        return sum(((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 0.5 for a, b in zip(points, points[1:]))

    def turned(self, since, until):
        """Yaw change (rad, signed, unwrapped) from ``since`` to ``until``."""
        with self._lock:
            start = max(bisect.bisect_right(self._times, since) - 1, 0)
            end = bisect.bisect_right(self._times, until)
            yaws = [pose[2] for pose in self._poses[start:end]]
        return sum(wrap_angle(b - a) for a, b in zip(yaws, yaws[1:]))


def mission_directory(label):
    """The landmark directory of this test's mission ``label`` (MissionRun.remove_recording
    removes it too: it ends in -mission-test)."""
    return os.path.join(TEST_ROOT, 'safety_findings_%s_%d-mission-test' % (label, os.getpid()))


def layer_commands(commands):
    """(sim receive time, v, w, sender) of every Twist a Collector of the mux input
    (``commands``) holds that is not from the operator."""
    return [(stamp, msg.linear.x, msg.angular.z, msg._connection_header.get('callerid', '?'))
            for stamp, msg in list(commands.items)
            if msg._connection_header.get('callerid') != OPERATOR]


def moving_commands_after(commands, since):
    """Of ``commands`` (:func:`layer_commands`), the non-zero ones of each layer node that
    follow its first zero command received at or after ``since``, or all its non-zero ones
    after ``since`` when no zero came: motion commanded after the layer knew the state of
    ``since``. (A command the node sent before it halted may arrive after the test saw the
    state: each node's commands arrive in order, so only those after its halting zero count.)"""
    late, by_sender = [], {}
    for command in commands:
        if command[0] >= since:
            by_sender.setdefault(command[3], []).append(command)
    for sent in by_sender.values():
        zeros = [i for i, (_, v, w, _) in enumerate(sent) if v == 0.0 and w == 0.0]
        late += [c for c in (sent[zeros[0]:] if zeros else sent) if c[1] != 0.0 or c[2] != 0.0]
    return late


class LayerLaunch(object):
    """The layer as a user starts it: ``roslaunch blind_navigation mission_rig.launch
    fake:=false`` (blind_navigation.launch plus the rig's rtf-scaled timeouts) in a
    process of its own, recording into ``directory`` (with ``fake``: the fake TurtleBot
    too, e.g. on a master of its own: ``env`` holds its ROS_MASTER_URI); its output is
    kept (``lines``) and copied to ``<ROS_LOG_DIR>/<label>.launch.log``. :meth:`stop` ends
    it as Ctrl-C would and deletes the params it set on this node's master, so the next
    mission's layer starts clean."""

    def __init__(self, label, directory, rtf, one_process=True, env=None, fake=False, args=()):
        roslaunch = shutil.which('roslaunch')
        if not roslaunch:
            raise AssertionError('roslaunch is not on PATH')
        self.params_before = set(rospy.get_param_names())
        self.lines = []
        log_dir = os.environ.get('ROS_LOG_DIR') or directory
        os.makedirs(log_dir, exist_ok=True)
        self.log_path = os.path.join(log_dir, 'safety_findings_%s.launch.log' % label)
        # --sigint-timeout: a node that outlives its master (safety_findings restarts it) is
        # killed after 5 s, not roslaunch's 15 s + 2 s; the layer ends on SIGINT well within it.
        command = [roslaunch, '--sigint-timeout=5', 'blind_navigation', 'mission_rig.launch',
                   'fake:=%s' % str(fake).lower(),
                   'control:=closed_loop', 'rtf:=%g' % rtf, 'dir:=%s' % directory,
                   'one_process:=%s' % ('true' if one_process else 'false')] + list(args)
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                        start_new_session=True, universal_newlines=True,
                                        env=dict(os.environ, **(env or {})))
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        with open(self.log_path, 'w') as log:
            for line in self.process.stdout:
                self.lines.append(line.rstrip('\n'))
                log.write(line)
                log.flush()

    def output(self):
        return '\n'.join(self.lines)

    def stop(self, timeout=40.0):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)    # roslaunch stops its nodes as on Ctrl-C
            try:
                self.process.wait(timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait(timeout)
        self._reader.join(timeout)
        for name in set(rospy.get_param_names()) - self.params_before:
            try:
                rospy.delete_param(name)
            except KeyError:
                pass                                    # deleted with its namespace already


class LayerChain(object):
    """One layer launch that plays several FindingMissions in turn: the first mission
    starts it, each next one starts with ``new_mission`` (the layer's service after home
    or aborted); nodes a mission restarted by hand serve the next ones too. One chain
    runs at a time (:meth:`stop_active`: before any other layer starts)."""

    active = None

    def __init__(self, label, one_process=True, env=None):
        self.label, self.one_process, self.env = label, one_process, env
        self.directory = mission_directory(label)
        self.layer, self.nodes = None, []

    def live(self):
        return self.layer is not None and self.layer.process.poll() is None

    def launch(self, rtf, prepare=None, args=()):
        """A fresh layer on a fresh directory (``prepare(directory)`` first)."""
        LayerChain.stop_active()
        shutil.rmtree(self.directory, ignore_errors=True)
        os.makedirs(self.directory)
        if prepare is not None:
            prepare(self.directory)
        LayerChain.active = self
        self.layer = LayerLaunch(self.label, self.directory, rtf, self.one_process, self.env, args=args)
        return self.layer

    def stop(self):
        """Ctrl-C to the nodes started by hand, then to the launch, while they end."""
        for node in self.nodes:
            if node.process.poll() is None:
                os.killpg(node.process.pid, signal.SIGINT)
        if self.layer is not None:
            self.layer.stop()
            self.layer = None
        for node in self.nodes:
            node.kill()
        self.nodes = []
        shutil.rmtree(self.directory, ignore_errors=True)
        if LayerChain.active is self:
            LayerChain.active = None

    @classmethod
    def stop_active(cls):
        if cls.active is not None:
            cls.active.stop()


atexit.register(LayerChain.stop_active)        # no layer outlives the test node


class FindingMission(object):
    """One mission of the layer on the fake TurtleBot for one or a few findings (module
    docstring). ``label`` names it; ``prepare(directory)`` runs before the layer starts;
    ``one_process`` false runs the paper's node layout; ``env`` is added to the layer
    launch's environment; ``args``: more launch args (``name:=value``) of mission_rig.launch.
    With ``chain`` (a LayerChain, whose layout and environment count) the mission plays on
    the chain's layer, started by ``new_mission`` if it runs already (it records at once:
    :meth:`wait_for_layer`), unless ``fresh``."""

    def __init__(self, label, one_process=True, prepare=None, env=None, args=(), chain=None, fresh=False):
        self.label = label
        self.chain = chain or LayerChain(label, one_process, env)
        self.rtf = float(rospy.get_param('/mobile_base/rtf'))
        self.run = None
        self.kept = []
        self.chained = chain is not None and chain.live() and not (fresh or prepare or args)
        if not self.chained:
            self.chain.launch(self.rtf, prepare, args)
        self.directory = self.chain.directory
        self.landmark_file = os.path.join(self.directory, 'landmarks.yaml')
        self.layer, self.nodes = self.chain.layer, self.chain.nodes
        self.commands = Collector(TELEOP_TOPIC, Twist)
        self.rosout = Collector('/rosout', Log)
        self.status = Collector(names.STATUS, MissionStatus)
        self.diagnostics = Diagnostics()
        self.track = Track()
        if self.chained:
            self.run = MissionRun(WALL_TIMEOUT)
            self.owner = self.run.owner
            self._new_mission()
            return
        layout_param = '/blind_navigation/recorder' if self.chain.one_process else '/back_travel_client/landmark_file'
        wait_for(lambda: rospy.has_param(layout_param) or self.layer.process.poll() is not None,
                 'the layer launch set its params', WALL_TIMEOUT)
        self.run = MissionRun(WALL_TIMEOUT)
        self.owner = self.run.owner

    def _new_mission(self):
        """``new_mission`` on the chain's layer, this node taking the samples (the
        recording starts at once); what this mission's watchers received of the last
        mission (its latched state and status) is dropped."""
        run = self.run
        self.wait(lambda: run.state_names()[-1:] and run.state_names()[-1] in FINAL_STATES,
                  "the last mission's final state (latched)")
        run.samples = Collector(names.SAMPLE, PathSample)
        stored = len(run.storage_msgs)
        rospy.wait_for_service(names.NEW_MISSION, WALL_TIMEOUT)
        reply = rospy.ServiceProxy(names.NEW_MISSION, Trigger)()
        if not reply.success:
            raise AssertionError('%s: new_mission refused: %s' % (self.label, reply.message))
        run.storage_msgs.drop_before(stored)
        self.wait(lambda: 'idle' in run.state_names(), 'state idle after new_mission')
        run.states.drop_before(run.state_names().index('idle'))
        for status in (run.status, self.status):
            self.wait(lambda: 'idle' in [msg.state for msg in status.snapshot()],
                      'the status of idle after new_mission')
            status.drop_before([msg.state for msg in status.snapshot()].index('idle'))

    def wait_for_layer(self):
        """The layer idle (a chained mission: past it), then recording (this node takes the
        samples); the robot's position then is the mission's start."""
        if not self.chained:
            self.run.wait_for_layer()
            return
        self.wait(lambda: 'recording' in self.run.state_names(), 'state recording')
        self.run.start = self.run.truth.position()

    def keep(self, publisher):
        """``publisher``, unregistered when the mission closes."""
        self.kept.append(publisher)
        return publisher

    def start_node(self, node_type, name):
        """(Re)start a layer node of the paper's layout by hand (its params are still on the
        parameter server); it is stopped with the chain's layer."""
        node = Node(node_type, name)
        self.nodes.append(node)
        return node

    def nudge(self, distance=0.3, speed=0.2):
        """Drive ``distance`` m straight ahead on teleop (this node as the operator) and let the
        robot stop: a recording the return has something to retrace on (core/return_plan.
        nothing_to_retrace ends a mission asked home before the robot moved ``home`` at once)."""
        teleop = self.keep(rospy.Publisher(TELEOP_TOPIC, Twist, queue_size=5))
        self.wait(lambda: teleop.get_num_connections() >= 1, 'the mux subscribes teleop')
        command = Twist()
        command.linear.x = speed
        until = rospy.get_time() + distance / speed
        while rospy.get_time() < until:
            teleop.publish(command)
            rospy.sleep(0.05)
        teleop.publish(Twist())
        self.wait_sim(1.0)

    # --- waits -----------------------------------------------------------------------------
    def wait(self, condition, what, timeout=WALL_TIMEOUT):
        wait_for(condition, '%s: %s (states %s)' % (self.label, what, self.run.state_names()), timeout)

    def wait_idle(self):
        self.wait(lambda: self.run.state_names()[:1] == ['idle'], 'the layer publishes idle')

    def state_time(self, state):
        """Sim time the test received the mission state ``state`` (the first time), or None."""
        for stamp, msg in list(self.run.states.items):
            if msg.data == state:
                return stamp
        return None

    def wait_state(self, state):
        self.wait(lambda: self.state_time(state) is not None, 'state %s' % state)
        return self.state_time(state)

    def final_state(self):
        """The first final state (home or aborted) the test received, or None."""
        return next((name for name in self.run.state_names() if name in FINAL_STATES), None)

    def wait_final(self):
        """Until home or aborted; returns (state, sim time it was received)."""
        self.wait(self.final_state, 'state home or aborted')
        final = self.final_state()
        return final, self.state_time(final)

    def wait_sim(self, seconds):
        until = rospy.get_time() + seconds
        self.wait(lambda: rospy.get_time() >= until, '%.1f s of sim time pass' % seconds)

    def logged(self, text, node=None):
        """/rosout lines (of ``node`` if given) containing ``text``."""
        return [m.msg for m in self.rosout.snapshot() if text in m.msg and (node is None or m.name == node)]

    def wait_logged(self, text, node=None):
        self.wait(lambda: self.logged(text, node), 'a log line %r%s' % (text, ' of %s' % node if node else ''))
        return self.logged(text, node)[-1]

    def final_reason(self):
        """The reason of the mission status that announced the final state (home or aborted),
        else of the last status (latched, from the owner). The owner publishes the state and
        then the status on two topics, so the state can arrive first: once the state is final,
        this waits for its status."""
        return self.final_status().reason

    def final_status(self):
        """The MissionStatus :meth:`final_reason` reads (its ``outcome``: the end's code)."""
        def final_statuses():
            return [msg for msg in self.status.snapshot() if msg.state in FINAL_STATES]
        if self.final_state():
            self.wait(final_statuses, 'the mission status of the final state')
            return final_statuses()[-1]
        statuses = self.status.snapshot()
        return statuses[-1] if statuses else MissionStatus()

    def refused_odometry(self):
        """Odometry messages the layer refused so far (the owner's 'odometry' diagnostics)."""
        status = self.diagnostics.status('%s: odometry' % self.owner.lstrip('/'), 'refused messages')
        return int(status[1]['refused messages']) if status else 0

    # --- verdicts --------------------------------------------------------------------------
    def layer_commands(self):
        return layer_commands(self.commands)

    def moving_commands_after(self, since):
        return moving_commands_after(self.layer_commands(), since)

    def still_after(self, since, watch):
        """From ``since`` (e.g. the terminal state) on, and for ``watch`` s of sim time after
        now (after whatever the caller did since then, e.g. a stray trigger): returns
        (the moving commands after ``since``, m moved and rad turned from ``since`` + SETTLE)."""
        start = since + SETTLE
        end = max(start, rospy.get_time()) + watch
        self.wait(lambda: rospy.get_time() >= end, 'the watch of %.0f s after %.2f s' % (watch, since))
        moved, turned = self.track.motion(start, end)
        return self.moving_commands_after(since), moved, turned

    def assert_still(self, case, since, watch, what):
        late, moved, turned = self.still_after(since, watch)
        case.assertEqual(late, [], '%s: motion commanded after %s' % (self.label, what))
        case.assertLess(moved, STILL_DISTANCE, '%s: the robot moved %.3f m after %s' % (self.label, moved, what))
        case.assertLess(turned, STILL_TURN, '%s: the robot turned %.3f rad after %s' % (self.label, turned, what))
        return moved, turned

    # --- the end ---------------------------------------------------------------------------
    def close(self, end_chain=True):
        """Stop the operator, unsubscribe; with ``end_chain`` also stop the layer (and the
        nodes started by hand) and remove the landmark directory."""
        if self.run is not None:
            self.run.stop_operator()
            self.run.close()
            if getattr(self.run, 'trigger', None) is not None:
                self.run.trigger.unregister()   # latched: the next mission's client would hear it
        for watched in (self.commands, self.rosout, self.status, self.diagnostics, self.track):
            watched.sub.unregister()
        for publisher in self.kept:
            publisher.unregister()
        if end_chain:
            self.chain.stop()
