"""The mission's owner: core/mission.Mission stepped by one loop thread (docs/DESIGN.md) on what
the callbacks put into an :class:`Inbox`; its services, ``record_landmark`` and ``back_travel``."""
import threading
from collections import ChainMap
from types import SimpleNamespace

import rospy
from std_msgs.msg import Empty, String
from std_srvs.srv import Trigger

from blind_navigation import names
from blind_navigation.core import mission_state as state, outcome
from blind_navigation.core.mission import RECORDING, Inputs, Mission
from blind_navigation.core.landmark_request import LandmarkRequest, hand_in, withdraw
from blind_navigation.core.mission_files import mission_number, next_mission_id, open_mission_file
from blind_navigation.core.role_params import (BACK_TRAVEL_CLIENT, BACK_TRAVEL_SERVER,
                                               HEADING_CORRECTION, MISSION_OWNER, ROTATE_PI,
                                               SAMPLING_PUBLISHER)
from blind_navigation.msg import BackTravelAction, BackTravelResult, MissionStatus, PathSample, StorageUsage
from blind_navigation.srv import RecordLandmark, RecordLandmarkResponse
from blind_navigation.ros.clock import LoopClock, action_server, describe
from blind_navigation.ros.common import ros_home_file, subscribe
from blind_navigation.ros.heading_correction import CALIBRATION_FILE, scale_prior
from blind_navigation.ros.landmark_saving import LANDMARK_FILE
from blind_navigation.ros.layer import MISSION_ID
from blind_navigation.ros.mission_outputs import MissionOutputs, add_diagnostics, reply
from blind_navigation.ros.mission_store import FileStore
from blind_navigation.ros.motion import DockingClient, MotionOutput, subscribe_battery
from blind_navigation.ros.odometry import visual_yaw
from blind_navigation.ros import faults


class Inbox(object):
    """What the callbacks observed since the loop last looked (thread-safe)."""

    def __init__(self):
        self._ready = threading.Condition()
        self._clear()

    def _clear(self):
        self.odoms, self.visual, self.events = [], [], {}
        self.reset_at = 0           # the first odometry state's index after an untrusted reset

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
        """(odometry states, visual frames, events, ``reset_at``), waiting at most ``timeout`` s."""
        with self._ready:
            if not self.odoms and not self.events:
                self._ready.wait(timeout)
            taken = self.odoms, self.visual, self.events, self.reset_at
            self._clear()
            return taken


def owner_params(layer):
    """(params, Mission settings, landmark file, turn max_w) from the roles' params (``~<role>/``)."""
    server = layer.params('back_travel_server', BACK_TRAVEL_SERVER)
    client = layer.params('back_travel_client', BACK_TRAVEL_CLIENT)
    rotate = layer.params('rotate_pi', ROTATE_PI)
    sampling = layer.params('sampling_publisher', SAMPLING_PUBLISHER)
    heading = layer.params('heading_correction', HEADING_CORRECTION)
    owner = layer.params('mission_owner', MISSION_OWNER)
    # the server's drive limits and timeouts first
    params = SimpleNamespace(**ChainMap(server._asdict(), client._asdict(), rotate._asdict()))
    params.straight_period = 1.0 / sampling.straight_rate
    params.listeners = max(0, sampling.min_subscribers - 1)     # besides this process's recorder
    correct = bool(rospy.get_param('~correct_heading', True))
    settings = dict(
        straight_period=params.straight_period, curved_period=1.0 / sampling.curved_rate,
        deadband=sampling.deadband, event_sampling=sampling.event_sampling,
        heading_correction=correct, standstill=heading, mode=server.control,
        scale_prior=scale_prior(ros_home_file(CALIBRATION_FILE, heading.gyro_calibration_file),
                                layer.logger('heading_correction')) if correct else None,
        prune_loops=client.prune_loops, handover_timeout=server.handover_timeout,
        handover_follow=server.handover_follow, on_vision_back=client.on_vision_back,
        turn_tolerance=client.turn_tolerance, vision_back_grace=client.vision_back_grace,
        limits=client, battery_low=owner.battery_low, dock_at_home=bool(owner.dock_at_home))
    return params, settings, ros_home_file(LANDMARK_FILE, client.landmark_file), rotate.max_w


#: s (wall) a record_landmark request waits for its answer; why every BackTravel goal is rejected.
ANSWER_WAIT = 2.0
REJECTED = ("the one-process layer drives its return itself (one mission object); landmark goals "
            "are served by paper.launch's back_travel_server (one_process:=false)")


class MissionOwner(object):
    """Hosts one core Mission and its loop (module docstring)."""

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
        self.lost = None                    # the feed's lost frame last seen (a reset)
        self.vo_heard, self.vo_since = None, rospy.get_time()   # the last visual odometry; the start
        self.state_pub = rospy.Publisher(names.STATE, String, queue_size=10, latch=True)
        self.status_pub = rospy.Publisher(names.STATUS, MissionStatus, queue_size=10, latch=True)
        self.storage_pub, self.sample_pub = (rospy.Publisher(names.STORAGE, StorageUsage, queue_size=10),
                                             rospy.Publisher(names.SAMPLE, PathSample, queue_size=10)) \
            if self.RECORDS else (None, None)
        self.store = self._open_store()
        self.mission = Mission(self.params, self.store, **settings)
        self.announced, self.progress = 0, None     # transitions published; (state, goal) in the status
        self.takeover = takeover = layer.takeover(self.params)
        self.drivers = {} if turn_w is None else {      # the MotionOutputs by state
            new: MotionOutput(state.MOTION_OWNER[new], v, w, layer.mission, layer.safety, takeover)
            for new, v, w in ((state.ROTATING, 0.0, turn_w),
                              (state.RETURNING, self.params.max_v, self.params.max_w))}
        self.docking = DockingClient(self.inbox, takeover, self.log) if settings.get('dock_at_home') else None
        self.outputs = MissionOutputs(self)
        self._subscribe()
        kept = self.outputs.first_state()   # a return a previous run left: resumed or aborted
        if kept is not None:
            self.mission = Mission(self.params, self.store, kept=kept, **settings)
        self.services = [rospy.Service(names.GO_HOME, Trigger, self.guard(self._on_go_home)),
                         rospy.Service(names.CANCEL, Trigger, self.guard(self._on_cancel)),
                         rospy.Service(names.NEW_MISSION, Trigger, self.guard(self._on_new_mission))]
        if self.RECORDS and self.recorder == 'service':     # the paper's names, in one process
            self.services.append(rospy.Service(names.RECORD_LANDMARK, RecordLandmark,
                                               self.guard(self._on_request)))
            self.log.info('serving %s: a request is one more landmark of the mission\'s recording',
                          rospy.resolve_name(names.RECORD_LANDMARK))
        if self.RECORDS:    # every goal rejected; actionlib publishes the status at each
            self.services.append(action_server(names.BACK_TRAVEL, BackTravelAction, self.guard,
                                               self._on_goal))
        add_diagnostics(self, settings)
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
        """A state, with the feed's frame if newly lost (an untrusted reset)."""
        lost = self.layer.odometry.lost
        reset, self.lost = (lost if lost != self.lost else None), lost
        self.inbox.odom(odom, reset)

    def _on_visual(self, wire):
        self.vo_heard, yaw = rospy.get_time(), visual_yaw(wire)
        if yaw is not None:
            self.inbox.frame(wire.stamp, yaw)

    def _open_store(self):
        writer = open_mission_file(self.landmark_file, self.layer.current_mission_id(), metadata={
            'recorder': self.recorder, 'owner': 'mission', 'odom_topic': rospy.resolve_name(names.ODOM),
            'started_ros_time': round(rospy.get_time(), 3)})
        self.log.info('recording path landmarks into %s', writer.path)
        return FileStore(writer)

    def run(self):
        """Step the mission until shutdown."""
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
            space = self.store.space.warning
            self.storage_pub.publish(self.store.storage(rospy.Time.now()))
            if self.store.space.warning != space:
                self.publish_status()
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
            self.outputs.progress.ending(new, reason)
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
        """What is degraded though the mission goes on, or ''."""
        m = self.mission
        return '; '.join(w for w in (m.warning or self.store.warning(), self.store.space.warning,
                                     self.outputs.progress.warning,
                                     m.pauses.describe(m.now or 0.0)) if w)

    def publish_status(self):
        m, self.progress, warnings = self.mission, self._progress(), self.warnings()
        goals = getattr(m.drive, 'goals', None)
        self.status_pub.publish(MissionStatus(
            header=rospy.Header(stamp=rospy.Time.now()), state=m.state or '', reason=m.reason or '',
            warnings=warnings, landmarks=len(m.landmarks or ()) if goals is None else len(goals),
            completed=getattr(m.drive, 'index', 0) if goals is not None else 0,
            outcome=m.machine.outcome))

    def _on_fault(self, reason):
        """A fault of this process (the loop's too): ``aborted`` naming it, from the reporting thread."""
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

    def _on_request(self, request):
        """``record_landmark``: hand the request in, wait for its answer."""
        done = threading.Event()
        asked = LandmarkRequest(request.command, request.yaw, request.period,
                                request.header.stamp.to_sec(), lambda _: done.set())
        with self.lock:
            hand_in(self.mission, asked)
        if not done.wait(ANSWER_WAIT):
            with self.lock:
                withdraw(self.mission, asked, ANSWER_WAIT)
        label, why_not = asked.answer
        if label:
            self.log.info('requested landmark %s saved (psi %.3f rad, T %.3f s)', label,
                          request.yaw, request.period)
        else:
            self.log.warn_throttle(1.0, '%s: request %r not saved: %s',
                                   rospy.resolve_name(names.RECORD_LANDMARK), request.command, why_not)
        return RecordLandmarkResponse(saved=bool(label), label=label, message=why_not)

    def _on_goal(self, handle):
        self.log.warn('%s goal %s rejected: %s', rospy.resolve_name(names.BACK_TRAVEL),
                      handle.get_goal_id().id, REJECTED)
        handle.set_rejected(BackTravelResult(), REJECTED)

    def _on_go_home(self, request):
        """Answered once the loop acted on it (at most ``server_timeout``)."""
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
