"""The back-travel client: the paper's action client (3.3.7, Figure 6) and the owner of
the mission's state, a thin ROS shell over its rooms.

It publishes ``blind_navigation/state`` and ``/status`` (every change through
core/mission_state.MissionState); the pi turn's start: ros/turn_start.py; the return:
ros/return_runner.py; progress: ros/return_progress.py; services: ros/mission_services.py;
a fault of any role ends the mission ``aborted`` (docs/safety.md, "One state machine").
"""
import threading
import time

import rospy
from std_msgs.msg import Empty, String

from blind_navigation import names
from blind_navigation.core import mission_state as state, outcome
from blind_navigation.core.back_travel import BACK_TRAVEL_DEFAULTS
from blind_navigation.core.landmark import Limits
from blind_navigation.core.mission_limits import rotation_timeout
from blind_navigation.core.return_plan import damage_warning, nothing_to_retrace
from blind_navigation.core.role_params import BACK_TRAVEL_CLIENT
from blind_navigation.core.rotation import turn_problem
from blind_navigation.core.safety import is_contact
from blind_navigation.msg import MissionStatus
from blind_navigation.ros import clock, faults
from blind_navigation.ros.common import shutting_down, subscribe, wait_wall
from blind_navigation.ros.landmark_saving import landmark_file
from blind_navigation.ros.mission_diagnostics import add_mission_diagnostics
from blind_navigation.ros.mission_services import MissionServices
from blind_navigation.ros.paper_adapter import RemoteRecording, RemoteTurn, write_loss
from blind_navigation.ros.return_paths import ReturnPaths
from blind_navigation.ros.return_progress import ProgressKeeper
from blind_navigation.ros.return_runner import ReturnRunner
from blind_navigation.ros.turn_start import TurnStart


class BackTravelClient(object):
    """Mission state machine and goal sender (module docstring)."""

    ROLE = 'back_travel_client'
    SCHEMA = BACK_TRAVEL_CLIENT

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.SCHEMA)
        self.log = layer.logger(self.ROLE)
        self.layer = layer
        self.odometry = layer.odometry
        self.landmark_file = landmark_file(p.landmark_file)
        self.rotation_timeout = rotation_timeout(p, p.rotation_margin, p.vision_back_grace)
        self.limits = Limits(p.max_v, p.max_w)
        self.machine = state.MissionState()
        self.warnings = ''              # the recording's: damaged, gaps bridged
        self.space_warning = ''         # the recorder's: little free space left
        self._return = threading.Event()
        self.trip = None
        self.takeover = layer.takeover(p)    # its pauses count against no allowance
        self.lost = None           # an untrusted odometry reset during the turn or the return
        self.turn_start = None          # raw odometry yaw where recording stopped
        self.recording_ended = None     # its stamp (s): the corrected frame's time (return_runner)
        self.recorded = 0.0             # m of path the recorder has stored (its StorageUsage)
        self.start_position = None      # odometry [x, y] where the recording began
        self.correction = layer.heading_correction() if p.heading_correction else None
        self.keeper = ProgressKeeper(self.landmark_file, self.correction, self.log,
                                     changed=self.publish_status)
        self.state_pub = rospy.Publisher(names.STATE, String, queue_size=1, latch=True)
        self.status_pub = rospy.Publisher(names.STATUS, MissionStatus, queue_size=1, latch=True)
        self.paths = ReturnPaths(p.path_spacing)
        self.runner = ReturnRunner(self)
        guard = self.guard = layer.guard(self.ROLE)
        self.remote_turn = RemoteTurn(guard, self._on_rotation_done)
        self.turn = TurnStart(self)
        self._start()
        layer.safety.on_trip(guard(self._on_trip))
        faults.on_fault(self._on_fault)
        self.odometry.on_reanchor(guard(self._on_reset))
        clock.on_moved_back(guard(self._on_time_moved_back))
        subscribe(names.ROLE_FAILURE, String, guard(self._on_failure_report), queue_size=10)
        self.recording = RemoteRecording(guard, self._on_storage)
        subscribe(names.VISION_LOST, Empty, guard(self._on_vision_lost), queue_size=1)
        self.services = MissionServices(self)
        add_mission_diagnostics(self)
        rospy.on_shutdown(self._on_shutdown)

    # --- state ---------------------------------------------------------------------------------
    @property
    def state(self):
        return self.machine.state

    @property
    def reason(self):
        return self.machine.reason

    def move(self, expected, new_state, reason='', code=outcome.NONE):
        """``expected -> new_state`` (core/mission_state; ``code``: a terminal state's core/outcome
        cause), announced if it moved. False if the state was another (the event is late)."""
        if not self.machine.transition(expected, new_state, reason, code):
            return False
        self._announce(expected, new_state, reason)
        return True

    def abort(self, reason, code):
        """Any unfinished state -> ``aborted`` (core/outcome ``code``); False if it had ended."""
        moved, old = self.machine.abort(reason, code)
        if moved:
            self._announce(old, state.ABORTED, reason)
        return moved

    def _announce(self, old, new_state, reason):
        if self.keeper.progress is not None and self.keeper.progress.unfinished and new_state in state.TERMINAL:
            self.keeper.save(self.keeper.progress.finish(new_state, reason, time.time(),
                                                     self.position()))  # before it is announced
        (self.log.error if new_state == state.ABORTED else self.log.info)(
            'state %s -> %s%s', old, new_state, ': ' + outcome.phrase(self.machine.outcome, reason) if reason else '')
        if new_state == state.IDLE:
            self.recorded, self.start_position = 0.0, None     # a new mission
        self.layer.mission.set_local(new_state)
        self.state_pub.publish(String(data=new_state))
        self.publish_status()
        if new_state in (state.IDLE, state.RECORDING, state.ROTATING, state.RETURNING):
            self.odometry.acquire(self.ROLE)
        elif new_state in state.TERMINAL:
            self.odometry.release(self.ROLE)
        self.layer.diagnostics.now()

    def all_warnings(self):
        """What is degraded or paused though the mission goes on: the recording, the free
        space, the progress file, the return's takeovers and contacts."""
        pauses = self.runner.pauses.describe(rospy.get_time()) if self.state == state.RETURNING else ''
        return '; '.join(w for w in (self.warnings, self.space_warning, self.keeper.warning, pauses)
                         if w)

    def publish_status(self):
        msg = MissionStatus(state=self.state or '', reason=self.reason, warnings=self.all_warnings(),
                            landmarks=self.keeper.progress.landmarks if self.keeper.progress else 0,
                            completed=self.keeper.progress.completed if self.keeper.progress else 0,
                            outcome=self.machine.outcome)
        msg.header.stamp = rospy.Time.now()
        self.status_pub.publish(msg)

    def _start(self):
        """The first state, from the progress a previous run left (ros/return_progress.py)."""
        first, reason = self.keeper.first_state(self._wait_for_position, self.layer.mission_id,
                                                self.params, self.limits)
        if self.move(None, first, reason, outcome.RESUME) and first == state.RETURNING:
            self._return.set()

    def position(self):
        odom = self.odometry.wait_fresh(self.params.odom_timeout)
        return [odom.x, odom.y] if odom is not None else None

    # --- events --------------------------------------------------------------------------------
    def _on_storage(self, msg):
        if msg.lost or msg.error:
            warning = damage_warning(write_loss(msg), msg.file)
            if warning != self.warnings:
                self.warnings = warning
                self.log.error('%s', warning)
                self.publish_status()
                self.layer.diagnostics.now()
        self.recorded = msg.distance
        if msg.space_warning != self.space_warning:
            self.space_warning = msg.space_warning
            self.publish_status()
        self.move(state.IDLE, state.RECORDING)

    def _on_vision_lost(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        current = self.state
        if current != state.RECORDING:
            if current not in (state.ROTATING, state.RETURNING):   # repeats are simply idempotent
                self.log.warn('vision_lost from %s ignored in state %s', sender, current)
            return
        self.begin_return('vision lost (%s)' % sender, vision=True)

    def begin_return(self, reason, vision=False):
        """Recording -> rotating for ``reason`` (``vision``: a vision loss; go_home otherwise),
        the turn begun by ros/turn_start.py; ``home`` if the robot has not moved. True if it moved."""
        here = self.odometry.latest()
        if nothing := nothing_to_retrace(self.recorded, self.start_position, here and [here.x, here.y],
                                         BACK_TRAVEL_DEFAULTS['finish_tolerance']):
            return self.move(state.RECORDING, state.HOME, '%s: %s' % (reason, nothing), outcome.NOTHING_TO_RETRACE)
        return self.turn.begin(reason, vision)

    def _on_rotation_done(self, ok):
        if self.state != state.ROTATING:
            return
        lost = self.lost or self.odometry.lost
        if lost:
            self.move(state.ROTATING, state.ABORTED, 'the pi rotation: %s; not travelling back'
                       % lost, outcome.ODOMETRY)
            return
        if not ok:
            safety = self.trip or ', '.join(self.layer.safety.active)
            self.move(state.ROTATING, state.ABORTED, 'the pi rotation failed%s; not travelling '
                       'back' % (' (safety stop: %s)' % safety if safety else ''), _failed_turn(safety))
            return
        latest = self.odometry.latest()
        problem = 'the pi turn has not begun (the recording goes on)' if not self.turn.begun \
            else turn_problem(self.turn_start, latest.yaw if latest is not None else None,
                              self.params.turn_tolerance)
        if problem:
            self.log.error('rotation_done true refused: %s', problem)
            return
        if self.move(state.ROTATING, state.RETURNING):
            self._return.set()
        else:
            self.log.warn('rotation_done true ignored in state %s', self.state)

    def _on_fault(self, reason):
        """A fault of this process (ros/wiring.py: a refused topic, a role's exception,
        ros/faults.py) or of another (``blind_navigation/role_failure``): the mission
        ends ``aborted`` with ``reason`` (its code: ros/faults.code_of)."""
        if not self.abort(reason, faults.code_of(reason)):
            self.log.error('%s (the mission had ended %s)', reason, self.state)

    def _on_failure_report(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        if sender != rospy.get_name():          # this process's roles report at once
            self._on_fault('%s (%s)' % (msg.data, sender))

    def _on_trip(self, reason):
        if self.state == state.ROTATING or (self.state == state.RETURNING and not is_contact(reason)):
            self.trip = reason          # a contact during the return: the server's Contacts decide

    def _on_reset(self, reason, trusted):
        """An untrusted odometry reset: the frame of the turn and the route is lost
        (the feed is never fresh again: the server and rotate_pi hold)."""
        if not trusted and self.state in (state.ROTATING, state.RETURNING):
            self.lost = reason

    def _on_time_moved_back(self, jump, before, now):
        """The ROS time moved back: a turn or a return cannot go on (their times and
        odometry stamps are of the old clock)."""
        current = self.state
        if current not in (state.ROTATING, state.RETURNING):
            return
        self.lost = '%s during %s' % (clock.describe(jump, before, now), 'the pi turn'
                                      if current == state.ROTATING else 'the return')
        if self.move(current, state.ABORTED, '%s: its times and odometry are of the old clock; '
                     'not travelling back' % self.lost, outcome.CLOCK) and current == state.RETURNING:
            self.runner.cancel()

    def _on_odom(self, raw):
        if self.state == state.RECORDING and self.start_position is None:
            self.start_position = [raw.x, raw.y]     # the frame of odometry.latest()
        if self.state != state.RETURNING:
            return
        odom = self.odometry.fresh(self.params.odom_timeout)
        if odom is not None:
            self.paths.driven(raw.stamp, self.odometry.frame_id, odom)

    def _on_shutdown(self):
        if self.state == state.RETURNING:
            self.runner.cancel()

    # --- the return ----------------------------------------------------------------------------
    def run(self):
        """Drive returns when the state says so (blocks until shutdown)."""
        self.odometry.add_listener(self.guard(self._on_odom))
        rospy.on_shutdown(self._return.set)
        while True:
            self._return.wait()         # a return to drive, or shutdown
            if shutting_down():
                return
            self._return.clear()
            code, reason = self.runner.travel_back()
            if not rospy.is_shutdown():
                self.move(state.RETURNING, state.HOME if code == outcome.HOME else state.ABORTED, reason, code)

    def _wait_for_position(self):
        """The robot's odometry [x, y], waiting (wall-bounded) for it; None if none came."""
        self.odometry.acquire(self.ROLE)
        wait_wall(lambda: self.position() is not None, self.params.server_timeout)
        return self.position()


def _failed_turn(safety):
    """The core/outcome code of a pi rotation that failed, ``safety``: the safety stop behind
    it ('' if none)."""
    return outcome.TURN if not safety else outcome.CONTACTS if is_contact(safety) else \
        outcome.SAFETY_EVENT
