"""The sampling publisher (paper 3.3.2, 3.4.1): the mission's sampling (core/mission_record)
stepped on each yaw; each tick a PathSample on ``sample``, the last ``final``; a restarted
saver's missed samples served (docs/recording.md).
"""
import math
import threading
from types import SimpleNamespace

import rospy
from geometry_msgs.msg import Pose2D
from std_msgs.msg import Empty

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.geometry import OdomState
from blind_navigation.core.mission_record import MissionRecording
from blind_navigation.core.sample_log import FINAL, SAMPLE, SampleLog, Ticks
from blind_navigation.core.role_params import SAMPLING_PUBLISHER
from blind_navigation.core.segment import period_of
from blind_navigation.msg import PathSample, StorageUsage
from blind_navigation.srv import RecordedSamples, RecordedSamplesResponse
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.mission import Role

#: The ticks' store (published, not kept).
UNKEPT = SimpleNamespace(append=lambda tick: None, note_gap=lambda reason: None)


class SamplingPublisher(Role):
    """Two-rate sampling publisher (module docstring)."""

    ROLE = 'sampling_publisher'
    SCHEMA = SAMPLING_PUBLISHER

    def __init__(self, layer):
        Role.__init__(self, layer)
        p, guard = self.params, self.guard
        self.config = SimpleNamespace(
            straight_period=period_of(p.straight_rate, '~straight_rate'), deadband=p.deadband,
            curved_period=period_of(p.curved_rate, '~curved_rate'),
            event_sampling=p.event_sampling, heading_correction=False)
        if p.event_sampling and p.yaw_source != 'odom':
            raise ValueError('~event_sampling needs ~yaw_source odom (the events come from odometry)')
        self._lock = threading.Lock()
        self._fresh()
        if self.rec.latency >= min(self.config.straight_period, self.config.curved_period):
            raise ValueError('~event_latency %.2f s must be shorter than the sampling periods'
                             % self.rec.latency)
        self.sample_pub = rospy.Publisher(names.SAMPLE, PathSample, queue_size=10)
        self.samples_service = rospy.Service(names.RECORDED_SAMPLES, RecordedSamples,
                                             guard(self._recorded_samples))
        if p.yaw_source == 'pose2d':
            self.source = rospy.resolve_name(names.POSE2D)
            subscribe(names.POSE2D, Pose2D, guard(self._on_pose2d), queue_size=10)
        else:
            self.source = rospy.resolve_name(names.ODOM)
            layer.odometry.add_listener(guard(self._on_yaw))
            layer.odometry.acquire(self.ROLE)
            subscribe(names.STORAGE, StorageUsage, guard(self._on_storage), queue_size=10)
        subscribe(names.RECORDING_END, Empty, guard(lambda _msg: self.stop('the pi turn begins')),
                  queue_size=1)
        self.follow('sampling')
        self.log.info('waiting for a valid yaw on %s and %d subscriber(s) of %s', self.source,
                      p.min_subscribers, rospy.resolve_name(names.SAMPLE))

    def _fresh(self):
        self.rec = MissionRecording(UNKEPT, self.config, Ticks())
        self.stopped = False
        self.last = None            # the newest yaw state (pose2d: x, y, v, w 0)
        self.recording, self.seq = 0.0, 0   # the recording's start (its id), the last sample's number
        self.samples = None         # SampleLog of the recording (yaw_source odom)

    def _diagnose(self, stat):
        stat.add('segment', self.rec.schedule.segment)
        stat.add('period (s)', '%.3g' % self.rec.schedule.period)
        if self.stopped:
            stat.summary(diagnostics.OK, 'recording stopped')
        elif not self.rec.started:
            stat.summary(diagnostics.WARN, 'waiting for a valid yaw on %s and the recorder' % self.source)
        else:
            stat.summary(diagnostics.OK, 'sampling: %s segment' % self.rec.schedule.segment)

    def _on_pose2d(self, msg):
        if math.isfinite(msg.theta):
            self._on_yaw(OdomState(0.0, 0.0, msg.theta, 0.0, 0.0, rospy.get_time()))
        else:
            self.log.warn_throttle(5.0, 'yaw from %s not used: theta is %r', self.source, msg.theta)

    def _on_storage(self, msg):
        """A recorder saved up to ``msg.sample``: the log keeps only what it could ask for."""
        with self._lock:
            if self.samples is not None and msg.sample and msg.recording == self.samples.recording:
                self.samples.confirm(msg.file, msg.sample)

    def _on_state(self, _old, new):
        if not mission_state.records(new):
            self.stop('mission state is %s' % new)

    def _new_mission(self):
        with self._lock:
            self._fresh()
        if self.params.yaw_source == 'odom':
            self.layer.odometry.acquire(self.ROLE)
        self.log.info('new mission: recording again')

    def _on_yaw(self, state):
        """Step the sampling (started once the mission records and the recorders listen)."""
        with self._lock:
            if self.stopped:
                return
            self.last = state
            if self.rec.started:
                period = self.rec.period
                self._publish(self.rec.step(state, state.stamp))
                if self.rec.period != period:
                    self.log.info('%s segment: period %.3g s -> %.3g s', self.rec.schedule.segment,
                                  period, self.rec.period)
            elif self.sample_pub.get_num_connections() >= self.params.min_subscribers \
                    and mission_state.records(self.layer.mission.state):
                self.recording = state.stamp
                if self.params.yaw_source == 'odom':
                    self.samples = SampleLog(self.recording, state)
                self.rec.begin(state)
                self.log.info('recording started; %s segment, period %.3g s',
                              self.rec.schedule.segment, self.rec.period)

    def stop(self, reason):
        """End the recording with its last samples (the last ``final``), until a new mission."""
        with self._lock:
            if self.stopped:
                return
            self.stopped = True
            if not self.rec.started:
                self.log.info('%s before recording started; nothing recorded', reason)
            else:
                ticks = self.rec.end(self.last, self.last.stamp)
                self._publish(ticks, final=True)
                self.log.info('%s: recording stopped (%s)', reason, 'final partial cycle %.3f s'
                              % ticks[-1][2] if ticks else 'no final sample: no time since the '
                              'last tick')
        if self.params.yaw_source == 'odom':
            self.layer.odometry.release(self.ROLE)

    def _publish(self, ticks, final=False):
        """Publish and log the ``ticks`` (state, yaw, period); ``final``: the last (lock held)."""
        for index, (state, yaw, period) in enumerate(ticks):
            command = FINAL if final and index == len(ticks) - 1 else SAMPLE
            self.seq += 1
            msg = PathSample(command=command, yaw=yaw, period=period, recording=self.recording,
                             seq=self.seq)
            msg.header.stamp = rospy.Time.from_sec(state.stamp)
            if self.samples is not None:
                self.samples.append(command, state.stamp, yaw, period, state)
            self.sample_pub.publish(msg)

    def _recorded_samples(self, request):
        """RecordedSamples: this recording's samples after ``request.after``."""
        with self._lock:
            response, logged = RecordedSamplesResponse(recording=self.recording), None
            if self.samples is None:
                response.message = 'no samples logged (%s)' % (
                    'yaw_source is not odom' if self.params.yaw_source != 'odom' else 'not recording yet')
            elif request.after and request.recording != self.recording:
                response.message = ('the caller follows recording %.3f, this is recording %.3f'
                                    % (request.recording, self.recording))
            else:
                logged = self.samples.since(request.after)
                response.message = '' if logged is not None else 'sample %d is not kept (%d to %d are)' % (
                    request.after, self.samples.first, self.samples.last)
            if logged is None:
                return response
        for entry in logged:
            sample = PathSample(command=entry.command, yaw=entry.yaw, period=entry.period,
                                recording=response.recording, seq=entry.seq)
            sample.header.stamp = rospy.Time.from_sec(entry.stamp)
            response.samples.append(sample)
            for name in ('x', 'y', 'v', 'w'):
                getattr(response, name).append(getattr(entry, name))
        self.log.info('sent samples %d to %d of recording %.3f to a restarted recorder',
                      request.after, self.seq, self.recording)
        return response

