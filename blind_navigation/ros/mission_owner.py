"""The mission's owner in one process: core/mission.Mission stepped by one loop thread.

Callbacks (odometry, visual odometry, vision, safety, takeover, resets, the clock) only
put observations into an :class:`Inbox`; the loop steps the mission once per odometry
state (or once a control period without one) and publishes its command, state, status
and storage (paths, correction, progress, replies: ros/mission_outputs.py). The services ask the
mission under its lock: blind_navigation.launch's one process (docs/DESIGN.md).
"""
import os
import threading
from types import SimpleNamespace

import rospy
from std_msgs.msg import Empty, String
from std_srvs.srv import Trigger

from blind_navigation import names
from blind_navigation.core import mission_state as state, outcome
from blind_navigation.core.geometry import yaw_from_quaternion
from blind_navigation.core.mission import RECORDING, Inputs, Mission
from blind_navigation.core.mission_files import mission_number, next_mission_id, open_mission_file
from blind_navigation.core.role_params import (BACK_TRAVEL_CLIENT, BACK_TRAVEL_SERVER,
                                               HEADING_CORRECTION, MISSION_OWNER, ROTATE_PI,
                                               SAMPLING_PUBLISHER)
from blind_navigation.core.vision import wire_lost_reason
from blind_navigation.msg import MissionStatus, PathSample, StorageUsage
from blind_navigation.ros.battery import subscribe_battery
from blind_navigation.ros.clock import LoopClock, describe
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.docking import DockingClient
from blind_navigation.ros.heading_correction import (calibration_file, calibration_status,
                                                    scale_prior, vo_status)
from blind_navigation.ros.landmark_saving import landmark_file
from blind_navigation.ros.layer import MISSION_ID
from blind_navigation.ros.mission_outputs import (MissionOutputs, file_status, mission_summary,
                                                  odometry_status, reply)
from blind_navigation.ros.mission_store import FileStore
from blind_navigation.ros.motion import MotionOutput
from blind_navigation.ros.owner_paper_names import PaperNames
from blind_navigation.ros import faults


class Inbox(object):
    """What the callbacks observed since the loop last looked (thread-safe)."""

    def __init__(self):
        self._ready = threading.Condition()
        self._clear()

    def _clear(self):
        self.odoms, self.visual, self.events = [], [], {}
        self.reset_at = 0           # the index of the first odometry state after an untrusted reset

    def put(self, **events):
        """Events by Inputs field name (the first of each kind until taken is kept)."""
        with self._ready:
            for name, value in events.items():
                self.events.setdefault(name, value)
            self._ready.notify()

    def odom(self, odom, reset=None):
        """An odometry state; ``reset``: the untrusted reset it is the first state after."""
        with self._ready:
            if reset is not None and 'reset' not in self.events:
                self.events['reset'], self.reset_at = reset, len(self.odoms)
            self.odoms.append(odom)
            self._ready.notify()

    def frame(self, stamp, yaw):
        with self._ready:
            self.visual.append((stamp, yaw))

    def take(self, timeout):
        """(odometry states, visual frames, events, the index of the first state after a reset),
        waiting at most ``timeout`` wall s for any."""
        with self._ready:
            if not self.odoms and not self.events:
                self._ready.wait(timeout)
            taken = self.odoms, self.visual, self.events, self.reset_at
            self._clear()
            return taken


def owner_params(layer):
    """(controller params, Mission settings, the configured landmark file) from the
    roles' params in this process (``~<role>/name``, as blind_navigation.launch sets them)."""
    server = layer.params('back_travel_server', BACK_TRAVEL_SERVER)
    client = layer.params('back_travel_client', BACK_TRAVEL_CLIENT)
    rotate = layer.params('rotate_pi', ROTATE_PI)
    sampling = layer.params('sampling_publisher', SAMPLING_PUBLISHER)
    heading = layer.params('heading_correction', HEADING_CORRECTION)
    owner = layer.params('mission_owner', MISSION_OWNER)
    merged = rotate._asdict()
    for role in (client, server):      # the server's drive limits and timeouts last
        merged.update(role._asdict())
    params = SimpleNamespace(**merged)
    params.straight_period = 1.0 / sampling.straight_rate
    params.listeners = max(0, sampling.min_subscribers - 1)     # besides this process's recorder
    correct = bool(rospy.get_param('~correct_heading', True))
    settings = dict(
        straight_period=params.straight_period, curved_period=1.0 / sampling.curved_rate,
        deadband=sampling.deadband, event_sampling=sampling.event_sampling,
        heading_correction=correct, standstill=heading, mode=server.control,
        scale_prior=scale_prior(calibration_file(heading.gyro_calibration_file),
                                layer.logger('heading_correction')) if correct else None,
        prune_loops=client.prune_loops, handover_timeout=server.handover_timeout,
        handover_follow=server.handover_follow, on_vision_back=client.on_vision_back,
        turn_tolerance=client.turn_tolerance, vision_back_grace=client.vision_back_grace,
        limits=client, battery_low=owner.battery_low, dock_at_home=bool(owner.dock_at_home))
    return params, settings, landmark_file(client.landmark_file), rotate.max_w


def _drivers(layer, p, turn_w, takeover):
    """The owner's MotionOutputs by state (``turn_w`` None: none, the paper layout's nodes drive)."""
    if turn_w is None:
        return {}
    return {state.ROTATING: MotionOutput(state.MOTION_OWNER[state.ROTATING], 0.0, turn_w,
                                         layer.mission, layer.safety, takeover),
            state.RETURNING: MotionOutput(state.MOTION_OWNER[state.RETURNING], p.max_v, p.max_w,
                                          layer.mission, layer.safety, takeover)}


class MissionOwner(object):
    """Hosts one core Mission and its loop (module docstring); a role of ros/layer."""

    ROLE = 'mission_owner'
    SCHEMA = MISSION_OWNER
    RECORDS = True          # the recording is this process's (not the paper layout's savers')
    configure = staticmethod(owner_params)

    def __init__(self, layer):
        self.layer, self.log, self.guard = layer, layer.logger(self.ROLE), layer.guard(self.ROLE)
        self.params, settings, self.landmark_file, turn_w = self.configure(layer)
        self.recorder = str(rospy.get_param('~recorder', 'topic'))
        self.lock = threading.RLock()       # the mission: the loop, the services, a fault
        self.stepped = threading.Condition(self.lock)   # the loop has stepped (go_home waits)
        self.inbox = Inbox()
        self.lost = None                    # the odometry feed's lost frame last seen (a reset)
        self.vo_heard = None                # rospy time of the last visual odometry
        self.vo_since = rospy.get_time()    # ... of the mission's start (its vo_timeout counts)
        self.state_pub = rospy.Publisher(names.STATE, String, queue_size=10, latch=True)
        self.status_pub = rospy.Publisher(names.STATUS, MissionStatus, queue_size=10, latch=True)
        # the recording begins once ``min_subscribers`` - 1 other nodes take the samples (a rig's test)
        self.storage_pub, self.sample_pub = (rospy.Publisher(names.STORAGE, StorageUsage, queue_size=10),
                                             rospy.Publisher(names.SAMPLE, PathSample, queue_size=10)) \
            if self.RECORDS else (None, None)
        self.store = self._open_store()
        self.mission = Mission(self.params, self.store, **settings)
        self.announced = 0                  # transitions of the mission published
        self.progress = None                # (state, goal index) of the status published
        self.takeover = takeover = layer.takeover(self.params)
        self.drivers = _drivers(layer, self.params, turn_w, takeover)
        self.docking = DockingClient(self.inbox, takeover, self.log) if settings.get('dock_at_home') else None
        self.outputs = MissionOutputs(self)
        self._subscribe()
        kept = self.outputs.first_state()   # a return a previous run left: resumed or aborted
        if kept is not None:
            self.mission = Mission(self.params, self.store, kept=kept, **settings)
        self.services = [rospy.Service(names.GO_HOME, Trigger, self.guard(self._on_go_home)),
                         rospy.Service(names.CANCEL, Trigger, self.guard(self._on_cancel)),
                         rospy.Service(names.NEW_MISSION, Trigger, self.guard(self._on_new_mission))]
        self.paper_names = PaperNames(self) if self.RECORDS else None   # record_landmark, back_travel
        self._add_diagnostics(settings)
        rospy.on_shutdown(self._on_shutdown)
        with self.lock:     # the first state only: a restart's abort is never preceded by idle
            self.announced = len(self.mission.transitions) - 1
            self._announce()

    def _subscribe(self):
        guard, layer, inbox = self.guard, self.layer, self.inbox
        layer.odometry.acquire(self.ROLE)
        layer.odometry.add_listener(guard(self._on_odom))
        subscribe(names.VISION_LOST, Empty, guard(lambda msg: inbox.put(vision_lost=True)), queue_size=1)
        subscribe(names.VISION_BACK, String, guard(lambda msg: inbox.put(vision_back=True)), queue_size=5)
        faults.on_fault(self._on_fault)
        if self.RECORDS:        # the recording's visual odometry, the battery watch: this process's
            layer.visual_odometry.acquire(self.ROLE)
            layer.visual_odometry.add_listener(guard(self._on_visual), raw=True)
            subscribe_battery(self.mission.config.battery_low, inbox, guard, self.log)

    def _on_odom(self, odom):
        """A state; the feed's frame newly lost (an untrusted reset) comes in with it."""
        lost = self.layer.odometry.lost
        reset, self.lost = (lost if lost != self.lost else None), lost
        self.inbox.odom(odom, reset)

    def _on_visual(self, wire):
        self.vo_heard = rospy.get_time()
        if wire_lost_reason(wire) is None:
            self.inbox.frame(wire.stamp, yaw_from_quaternion(wire.qx, wire.qy, wire.qz, wire.qw))

    def _open_store(self):
        writer = open_mission_file(self.landmark_file, self.layer.current_mission_id(), metadata={
            'recorder': self.recorder, 'owner': 'mission', 'odom_topic': rospy.resolve_name(names.ODOM),
            'started_ros_time': round(rospy.get_time(), 3)})
        self.log.info('recording path landmarks into %s', writer.path)
        return FileStore(writer)

    # --- the loop ------------------------------------------------------------------------------
    def run(self):
        """Step the mission until shutdown (ros/layer.run_roles runs it in its own thread)."""
        clock = LoopClock(self.ROLE, self.log, then='a turn or a return ends aborted')
        period = 1.0 / self.params.control_rate
        while not rospy.is_shutdown():
            odoms, visual, events, reset_at = self.inbox.take(period)
            reset = {'reset': events.pop('reset')} if 'reset' in events else {}
            moved_back = clock.moved_back
            now = clock.now()
            if clock.moved_back > moved_back:
                events.setdefault('time_back', describe(*clock.last_jump))
            with self.lock:
                for index, odom in enumerate(odoms or [None]):
                    self._step(now, odom, visual if index == 0 else (), dict(
                        events if index == 0 else {}, **(reset if index == reset_at else {})))
                self.stepped.notify_all()

    def _step(self, now, odom, visual, events):
        if self.mission.phase == RECORDING and not self.mission.recording.started and \
                self.sample_pub is not None and self.sample_pub.get_num_connections() < self.params.listeners:
            odom = None
        active, terminal = self.layer.safety.active, self.layer.safety.terminal
        inputs = Inputs(odom=odom, visual=visual,
                        bumper=tuple(c for c in active if c not in terminal),
                        operator=self.takeover.active(),
                        tripped=', '.join(terminal) if terminal else None, **events)
        step = self.mission.step(now, inputs)
        if step.stored:
            self._publish_storage()
        self.outputs.stepped(step.stored)
        self._announce()
        if step.dock:               # after the announcement: the takeover watch knows it docks
            self.docking.start()
        if self._progress() != self.progress:      # a goal of the return done: its status
            self.publish_status()
        if step.command is not None and self.drivers:
            output = self.drivers.get(step.state)
            if output is not None:
                output.contact_over()   # the mission drives on: it has waited contact_wait
                output.publish(*step.command)
            else:
                self.drivers[state.RETURNING].stop()
        return step

    def _announce(self):
        """Publish the mission's transitions not yet published (lock held)."""
        while self.announced < len(self.mission.transitions):   # a fault may add one meanwhile
            _, old, new, reason = self.mission.transitions[self.announced]
            self.announced += 1
            code = self.mission.machine.outcome if new in state.TERMINAL else outcome.NONE
            (self.log.error if new == state.ABORTED else self.log.info)(
                'state %s -> %s%s', old, new, ': ' + outcome.phrase(code, reason) if reason else '')
            self.outputs.ending(new, reason)
            self.layer.mission.set_local(new)
            if self.docking is not None:
                self.docking.state(new)     # leaving docking: a pending goal cancelled
            if new in self.drivers and not self.layer.safety.terminal:
                self.drivers[new].release()     # a cliff or wheel drop keeps it halted
            self.state_pub.publish(String(data=new))
            self.publish_status()
            self.layer.diagnostics.now()

    def _progress(self):
        return self.mission.state, getattr(self.mission.drive, 'index', None)

    def warnings(self):
        """What is degraded though the mission goes on ('' if nothing)."""
        m = self.mission
        return '; '.join(w for w in (m.warning or self.store.warning(), self.store.space.warning,
                                     self.outputs.progress.keeper.warning,
                                     m.pauses.describe(m.now or 0.0)) if w)

    def publish_status(self):
        m, self.progress, warnings = self.mission, self._progress(), self.warnings()
        goals = getattr(m.drive, 'goals', None)
        msg = MissionStatus(state=m.state or '', reason=m.reason or '', warnings=warnings,
                            landmarks=len(m.landmarks or ()) if goals is None else len(goals),
                            completed=getattr(m.drive, 'index', 0) if goals is not None else 0,
                            outcome=m.machine.outcome)
        msg.header.stamp = rospy.Time.now()
        self.status_pub.publish(msg)

    def _publish_storage(self):
        before = self.store.space.warning
        self.storage_pub.publish(self.store.storage(rospy.Time.now())[0])
        if self.store.space.warning != before:
            self.publish_status()

    def _on_fault(self, reason):
        """A fault of this process (the loop's own included: it has ended): ``aborted``
        naming it, announced from the reporting thread; every output is zero for good."""
        with self.lock:
            self._cancel(reason, faults.code_of(reason))

    def _cancel(self, reason, code):
        self.mission.cancel(reason, code)
        self._announce()

    def _on_shutdown(self):
        if self.docking is not None:
            self.docking.cancel('node shutdown')
        for output in self.drivers.values():
            output.halt('node shutdown')
        self.store.close()

    def _add_diagnostics(self, settings):
        """The mission's statuses and, as the paper layout's roles name them, the odometry's,
        the landmark file's and the heading correction's (ros/mission_outputs.py,
        ros/heading_correction.py)."""
        add, client = self.layer.diagnostics.add, settings['limits']
        add('mission', self._diagnose)
        add('odometry', lambda stat: odometry_status(stat, self.layer.odometry, self.mission.state,
                                                     client.odom_timeout))
        add('landmark file', lambda stat: file_status(stat, self.landmark_file, self.mission.state))
        if not self.RECORDS:    # the paper layout's saver and heading_correction report the rest
            return
        add('recording', lambda stat: self.store.status(stat, self.mission.phase != RECORDING))
        if not settings['heading_correction']:
            return
        heading = settings['standstill']
        path = calibration_file(heading.gyro_calibration_file)
        add('heading correction: visual odometry', lambda stat: vo_status(
            stat, self.mission.phase != RECORDING, None if self.vo_heard is None else
            rospy.get_time() - self.vo_heard, rospy.get_time() - self.vo_since, heading.vo_timeout,
            len(getattr(self.mission.recording.fit, 'rows', ()))))
        add('heading correction: gyro calibration',
            lambda stat: calibration_status(stat, path, settings['scale_prior']))

    def _diagnose(self, stat):
        mission_id = self.layer.mission_id      # cached: no master call (an outage)
        stat.add('state', self.mission.state)
        stat.add('phase', self.mission.phase)
        stat.add('mission', mission_number(mission_id))     # in this launch
        stat.add('mission id', mission_id)
        stat.add('mission file', os.path.realpath(self.landmark_file))
        mission_summary(stat, self.mission.state, self.mission.reason, self.warnings())

    # --- services ------------------------------------------------------------------------------
    def _on_go_home(self, request):
        """Requested, then answered once the loop acted on it (at most ``server_timeout``)."""
        with self.stepped:
            refusal = self.mission.go_home()
            if refusal is None:
                self.stepped.wait_for(lambda: 'go_home' not in self.mission.requests,
                                      self.params.server_timeout)
            current = self.mission.state
        return reply(self.log, request, 'go_home', refusal, 'returning home: the mission is %s' % current)

    def _on_cancel(self, request):
        with self.lock:
            refusal = self.mission.cancel()
            if refusal is None:
                for output in self.drivers.values():
                    output.halt(state.CANCELLED)
                self._announce()
        return reply(self.log, request, 'cancel', refusal,
                     'stopped: the mission is aborted (%s)' % state.CANCELLED)

    def _on_new_mission(self, request):
        with self.lock:
            refusal = state.new_mission_refusal(self.mission.state)
            if refusal is None:
                rospy.set_param(MISSION_ID, next_mission_id(self.layer.current_mission_id()))
                self.store.close()
                self.store = self._open_store()
                refusal = self.mission.new_mission(self.store)
                self.vo_since = rospy.get_time()
                self.outputs.new_mission()
                self._announce()
        return reply(self.log, request, 'new_mission', refusal, 'mission %d: idle; recording into a '
                     'new file behind %s from the first landmark' % (
                         mission_number(self.layer.current_mission_id()), self.landmark_file))
