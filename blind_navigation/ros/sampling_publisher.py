"""The sampling publisher: the paper's publisher of sampling ticks (3.3.2, 3.4.1).

Reads the yaw (shared ``odom`` feed, or ``pose2d``), ticks at the straight or curved rate
(core/segment.SamplingSchedule) and publishes a PathSample per tick on
``blind_navigation/sample``, plus motion-event samples with ``event_sampling``; ends with a
``final`` sample; serves a restarted saver its missed samples (docs/recording.md, "Roles").
"""
import math
import threading

import rospy
from geometry_msgs.msg import Pose2D
from std_msgs.msg import Empty

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.motion_events import EventSampler
from blind_navigation.core.sample_log import SampleLog
from blind_navigation.core.role_params import SAMPLING_PUBLISHER
from blind_navigation.core.segment import SamplingSchedule, period_of
from blind_navigation.msg import PathSample, StorageUsage
from blind_navigation.srv import RecordedSamples, RecordedSamplesResponse
from blind_navigation.ros import diagnostics
from blind_navigation.ros.clock import LoopClock
from blind_navigation.ros.common import subscribe

#: PathSample.command values: a regular tick, and the last partial cycle.
SAMPLE = 'sample'
FINAL = 'final'
COMMANDS = (SAMPLE, FINAL)
#: Shortest partial cycle worth a final landmark, s.
MIN_FINAL_PERIOD = 1e-3


class SamplingPublisher(object):
    """Two-rate sampling publisher (module docstring)."""

    ROLE = 'sampling_publisher'
    SCHEMA = SAMPLING_PUBLISHER

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.SCHEMA)
        self.log = layer.logger(self.ROLE)
        self._periods = (period_of(p.straight_rate, '~straight_rate'),
                         period_of(p.curved_rate, '~curved_rate'))
        if p.event_sampling and p.yaw_source != 'odom':
            raise ValueError('~event_sampling needs ~yaw_source odom (the events come from odometry)')
        self.layer = layer
        self._lock = threading.Lock()
        self._pose2d_yaw = None
        self._generation = 0        # the recordings started (each new_mission one more)
        self._restarted = threading.Event()
        self._fresh()
        if self.events is not None and self.events.latency >= min(self._periods):
            raise ValueError('~event_latency %.2f s must be shorter than the sampling periods'
                             % self.events.latency)
        self.sample_pub = rospy.Publisher(names.SAMPLE, PathSample, queue_size=10)
        guard = layer.guard(self.ROLE)
        self.samples_service = rospy.Service(names.RECORDED_SAMPLES, RecordedSamples,
                                             guard(self._recorded_samples))
        if p.yaw_source == 'pose2d':
            self.source = rospy.resolve_name(names.POSE2D)
            subscribe(names.POSE2D, Pose2D, guard(self._on_pose2d), queue_size=10)
        else:
            self.source = rospy.resolve_name(names.ODOM)
            layer.odometry.acquire(self.ROLE)
            subscribe(names.STORAGE, StorageUsage, guard(self._on_storage), queue_size=10)
        layer.mission.on_change(guard(self._on_state))
        subscribe(names.RECORDING_END, Empty, guard(lambda _msg: self.stop('the pi turn begins')),
                  queue_size=1)
        layer.mission.on_new_mission(guard(self._new_mission))
        layer.diagnostics.add('sampling', self._diagnose)

    def _fresh(self):
        """Nothing recorded yet: the schedule, the events and the counters start anew."""
        self.schedule = SamplingSchedule(self._periods[0], self._periods[1], self.params.deadband)
        self.events = EventSampler(self.params) if self.params.event_sampling else None
        self._last_tick = None      # rospy.Time of the last tick (or of the start)
        self._events_fed = None     # stamp (s) of the last odometry state fed to the events
        self.stopped = False
        self.recording = 0.0        # the recording's id: when it started (s), 0 before
        self.seq = 0                # the number of the last sample published
        self.samples = None         # SampleLog of the recording (yaw_source odom)
        self._generation += 1

    def _diagnose(self, stat):
        stat.add('segment', self.schedule.segment)
        stat.add('period (s)', '%.3g' % self.schedule.period)
        if self.stopped:
            stat.summary(diagnostics.OK, 'recording stopped')
        elif self._last_tick is None:
            stat.summary(diagnostics.WARN, 'waiting for a valid yaw on %s and the recorder' % self.source)
        else:
            stat.summary(diagnostics.OK, 'sampling: %s segment' % self.schedule.segment)

    # -- inputs -------------------------------------------------------------
    def _on_pose2d(self, msg):
        if math.isfinite(msg.theta):
            self._pose2d_yaw = msg.theta
        else:
            self.log.warn_throttle(5.0, 'yaw from %s not used: theta is %r', self.source, msg.theta)

    def _on_storage(self, msg):
        """A recorder saved up to sample ``msg.sample``: the log keeps only what a restart of
        it could still ask for (core/sample_log.SampleLog.confirm)."""
        with self._lock:
            if self.samples is not None and msg.sample and msg.recording == self.samples.recording:
                self.samples.confirm(msg.file, msg.sample)

    def _yaw(self, at=None):
        """The newest yaw, or with ``at`` (s) the odometry's yaw at that stamp."""
        if self.params.yaw_source == 'pose2d':
            return self._pose2d_yaw
        odometry = self.layer.odometry
        state = odometry.latest() if at is None else odometry.state_at(at)
        return None if state is None else state.yaw

    def _on_state(self, _old, new):
        if not mission_state.records(new):
            self.stop('mission state is %s' % new)

    def _new_mission(self):
        with self._lock:
            self._fresh()
        if self.params.yaw_source == 'odom':
            self.layer.odometry.acquire(self.ROLE)
        self.log.info('new mission: recording again')
        self._restarted.set()

    # -- the sampling loop ----------------------------------------------------
    def stop(self, reason):
        """Publish the final partial-cycle sample (if recording) and stop (until a new mission)."""
        with self._lock:
            if self.stopped:
                return
            self.stopped = True
            if self._last_tick is None:
                self.log.info('%s before recording started; nothing recorded', reason)
            else:
                now = rospy.Time.now()
                if self.events is not None:
                    self._publish_events(now.to_sec())
                elapsed = (now - self._last_tick).to_sec()
                if elapsed >= MIN_FINAL_PERIOD:
                    self._publish(FINAL, self._yaw(now.to_sec()), elapsed, now)
                self.log.info('%s: recording stopped (%s)', reason, 'final partial cycle %.3f s'
                              % elapsed if elapsed >= 0 else 'no final sample: the ROS time moved '
                              'back since the last tick')
        if self.params.yaw_source == 'odom':
            self.layer.odometry.release(self.ROLE)

    def _publish(self, command, yaw, period, stamp=None):
        """Publish one sample (lock held) stamped ``stamp`` (rospy.Time, default now)
        and mark the tick."""
        self.seq += 1
        msg = PathSample(command=command, yaw=yaw, period=period, recording=self.recording,
                         seq=self.seq)
        msg.header.stamp = stamp or rospy.Time.now()
        if self.samples is not None:
            seconds = msg.header.stamp.to_sec()
            state = self.layer.odometry.state_at(seconds)
            if state is None:
                self.samples = None
                self.log.warn('no odometry to log sample %d with: a recorder restarted from now '
                              'on cannot catch up', self.seq)
            else:
                self.samples.append(command, seconds, yaw, period, state)
        self.sample_pub.publish(msg)
        self._last_tick = msg.header.stamp

    def _recorded_samples(self, request):
        """The RecordedSamples service: the samples after ``request.after`` of this recording."""
        with self._lock:
            response = RecordedSamplesResponse(recording=self.recording)
            if self.samples is None:
                response.message = ('no samples logged (%s)' % ('not recording yet' if not self.seq
                                    else 'yaw_source is not odom' if self.params.yaw_source != 'odom'
                                    else 'the log stopped'))
                return response
            if request.after and request.recording != self.recording:
                response.message = ('the caller follows recording %.3f, this is recording %.3f'
                                    % (request.recording, self.recording))
                return response
            logged = self.samples.since(request.after)
            if logged is None:
                response.message = 'sample %d is not kept (%d to %d are)' % (
                    request.after, self.samples.first, self.samples.last)
                return response
        add_logged(response, logged)
        self.log.info('sent samples %d to %d of recording %.3f to a restarted recorder',
                      request.after, self.seq, self.recording)
        return response

    def _feed_events(self):
        """Feed the event sampler the odometry states accepted since it was last fed,
        in order (lock held)."""
        odometry = self.layer.odometry
        latest = odometry.latest()
        if latest is not None and latest.stamp < self._events_fed:
            self._events_fed = float('-inf')     # the clock went back: every state kept is new
        for state in odometry.states_after(self._events_fed):
            self.events.odometry(state)
            self._events_fed = state.stamp

    def _publish_events(self, before):
        """Publish the motion-event samples stamped before ``before`` (s; lock held)."""
        self._feed_events()
        for state, period in self.events.before(before, self.layer.odometry.state_at):
            self._publish(SAMPLE, state.yaw, period, rospy.Time.from_sec(state.stamp))

    def _wait_for_start(self, clock):
        """Until a valid yaw arrives and the state allows recording; False if stopped."""
        logged = False
        while not rospy.is_shutdown():
            with self._lock:
                if self.stopped:
                    return False
                yaw = self._yaw()
                ready = self.sample_pub.get_num_connections() >= self.params.min_subscribers
                if ready and yaw is not None and mission_state.records(self.layer.mission.state):
                    self._last_tick = rospy.Time.now()
                    self.recording = self._last_tick.to_sec()
                    if self.params.yaw_source == 'odom':
                        self.samples = SampleLog(self.recording, self.layer.odometry.latest())
                    self.schedule.update(yaw)
                    if self.events is not None:
                        self.events.start(self._last_tick.to_sec())
                        # the events see the states accepted from now on, as a listener would
                        self._events_fed = self.layer.odometry.latest().stamp
                    return True
            if not logged:
                self.log.info('waiting for a valid yaw on %s and %d subscriber(s) of %s', self.source,
                              self.params.min_subscribers, rospy.resolve_name(names.SAMPLE))
                logged = True
            try:
                clock.sleep(0.05)
            except rospy.ROSInterruptException:
                return False
        return False

    def run(self):
        """Record, and again at each new mission (blocks until shutdown)."""
        rospy.on_shutdown(self._restarted.set)
        while not rospy.is_shutdown():
            self._record(self._generation)
            self._restarted.wait()      # a new mission, or shutdown
            self._restarted.clear()

    def _record(self, generation):
        """The sampling loop of one recording (until it stops, a new one starts, or shutdown)."""
        clock = LoopClock('sampling', self.log, then='the sampling goes on')
        if not self._wait_for_start(clock):
            return
        period = self.schedule.period
        self.log.info('recording started; %s segment, period %.3g s', self.schedule.segment, period)
        rate = clock.rate(1.0 / period)
        while not rospy.is_shutdown():
            try:
                rate.sleep()
                tick = rospy.Time.now()
                if self.events is not None:   # taken late: motion events before the tick first
                    if clock.sleep(self.events.latency):
                        tick = rospy.Time.now()     # the time moved back meanwhile: the tick is now
            except rospy.ROSInterruptException:
                return
            with self._lock:
                if self.stopped or self._generation != generation:
                    return
                if self.events is None:
                    yaw = self._yaw()
                    self._publish(SAMPLE, yaw, period)
                else:
                    state = self.layer.odometry.state_at(tick.to_sec())
                    yaw = state.yaw if state is not None else self._yaw()
                    self._publish_events(tick.to_sec())
                    self._publish(SAMPLE, yaw, self.events.tick(tick.to_sec(), period), tick)
                next_period = self.schedule.update(yaw)
            if next_period != period:
                self.log.info('%s segment: period %.3g s -> %.3g s', self.schedule.segment, period,
                              next_period)
                rate.switch(1.0 / next_period)    # the next cycle: exactly next_period from this tick
                period = next_period


def add_logged(response, logged):
    """Add the ``logged`` samples (core/sample_log entries) to a RecordedSamples ``response``."""
    for entry in logged:
        sample = PathSample(command=entry.command, yaw=entry.yaw, period=entry.period,
                            recording=response.recording, seq=entry.seq)
        sample.header.stamp = rospy.Time.from_sec(entry.stamp)
        response.samples.append(sample)
        response.x.append(entry.x)
        response.y.append(entry.y)
        response.v.append(entry.v)
        response.w.append(entry.w)
