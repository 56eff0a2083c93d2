"""The mission's recording, stepped on each odometry state: the two-rate sampling
schedule, the path recorder, the optional motion-event samples, the landmarks requested
(core/landmark_request) and, with heading correction, the gyro/visual fit; landmarks go
to an injected store. Then the standstill after the loss that fixes the heading
correction. Used by core/mission.Mission.
"""
from .battery import BatteryWatch
from .gyro_bias import StandstillBias, standstill_complete, standstill_timeout
from .gyro_fit import GyroVisualFit
from .heading_correction import estimate_correction, no_correction, visual_bias
from .motion_events import EventSampler
from .recorder import OdometryHistory, PathRecorder
from .segment import SamplingSchedule


class MissionRecording(object):
    """One recording into ``store`` (``append(landmark)`` -> its label, None: not written);
    ``config``: straight_period, curved_period, deadband, event_sampling, heading_correction;
    ``recorder``: what makes the landmarks (core/sample_log.Ticks: the ticks themselves)."""
    reported = False        # a saver elsewhere has stored landmarks (core/mission_remote)

    def __init__(self, store, config, recorder=None):
        self.store = store
        self.schedule = SamplingSchedule(config.straight_period, config.curved_period, config.deadband)
        self.recorder = recorder or PathRecorder()
        self.events = EventSampler() if config.event_sampling else None
        self.latency = self.events.latency if self.events else 0.0
        # a tick looks back a period and the events' latency at least
        self.history = OdometryHistory(max(config.straight_period, config.curved_period)
                                       + max(2.0, 2.0 * self.latency))
        self.fit = GyroVisualFit() if config.heading_correction else None
        self.period = self.next_tick = self.last_tick = None
        self.landmarks = []         # as appended, recording order
        self.start = None           # odometry (x, y) where it began
        self.lost = None            # an untrusted odometry reset while recording: why
        self.battery = BatteryWatch(getattr(config, 'battery_low', 0.0))    # fed while recording
        self.requested = []         # core/landmark_request.LandmarkRequest handed in, not taken

    @property
    def started(self):
        return self.period is not None

    def begin(self, odom):
        """The recording starts at ``odom`` (the first state)."""
        self.recorder.start(odom)
        self.start = (odom.x, odom.y)
        self.period = self.schedule.update(odom.yaw)
        self.next_tick, self.last_tick = odom.stamp + self.period, odom.stamp
        if self.events:
            self.events.start(odom.stamp)

    def feed(self, odom, visual):
        """The fit's data: ``odom`` then the visual samples ``[(stamp, yaw)]``."""
        if self.fit is not None:
            if odom is not None:
                self.fit.add_odometry(odom.stamp, odom.yaw)
            for stamp, yaw in visual:
                self.fit.add_visual(stamp, yaw)

    def step(self, odom, now):
        """Sample ``odom`` (every state, in order) at ``now``; returns the landmarks taken."""
        taken = []
        if odom.stamp < self.last_tick - 1e-9:      # the clock moved back
            self._clock_back(odom.stamp)
        self.history.append(odom)       # the ticks' (event sampling) and the requests' states
        if self.events is not None:
            self.events.odometry(odom)
        self._take_requested(odom, now, self.next_tick, taken)
        if now >= self.next_tick + self.latency - 1e-9:
            # with event sampling: latency s late, the odometry at the tick's stamp
            state = self.history.at(self.next_tick + 1e-9) if self.latency else odom
            self._take_events(state.stamp, taken)
            period = self.events.tick(state.stamp, self.period) if self.events else self.period
            self._take(state, period, taken)
            self.period = self.schedule.update(state.yaw)
            self.next_tick = state.stamp + self.period
        self._take_requested(odom, now, float('inf'), taken)
        return taken

    def end(self, odom, now):
        """Vision is lost at ``odom`` (``now``): the events left, then a final landmark over the
        partial cycle; returns the landmarks taken. Recording may go on (:meth:`resume`)."""
        taken = []
        self._refuse_requested('the recording ended (vision lost or go_home) before it was taken')
        self._take_events(now + 1.0, taken)
        if now - self.last_tick > 1e-9:
            self._take(odom, now - self.last_tick, taken)
        return taken

    def reset(self, odom, reason):
        """An untrusted odometry reset (``reason``) at ``odom`` (the new frame): a gap in the
        store, d counts from ``odom``, the old frame's states dropped; the way back is lost."""
        self.lost = self.lost or reason
        self._refuse_requested('an odometry reset (%s) came before it was taken' % reason)
        if self.started:
            self.store.note_gap(reason)
            self.recorder.restart(odom)
            self.history.clear()

    def _clock_back(self, now):
        """The odometry's clock moved back to ``now`` (a restarted simulator): start over."""
        self.next_tick, self.last_tick = now + self.period, now
        self.history.clear()
        self._refuse_requested('the clock moved back before it was taken')
        if self.events is not None:
            self.events.start(now)

    def resume(self):
        """Vision came back before the turn: the next tick one period after the last landmark."""
        self.next_tick = self.last_tick + self.period

    def _take_events(self, before, taken):
        for state, period in self.events.before(before, self.history.at) if self.events else ():
            self._take(state, period, taken)

    def _take(self, state, period, taken, yaw=None):
        landmark = self.recorder.take(state, state.yaw if yaw is None else yaw, period)
        taken.append(landmark)
        self.landmarks.append(landmark)
        self.last_tick = state.stamp
        return self.store.append(landmark)

    def _take_requested(self, odom, now, before, taken):
        """Take (and answer) the requests stamped before ``before`` whose state is known at
        ``odom`` (``now``), in time order, each after the events before it."""
        for request in self.requested:
            if request.stamp is None:       # unstamped: this state
                request.stamp = odom.stamp
        due = sorted((r for r in self.requested if r.stamp < before and r.stamp <= odom.stamp
                      and now >= r.stamp + self.latency - 1e-9), key=lambda r: r.stamp)
        for request in due:
            self.requested.remove(request)
            self._take_events(request.stamp, taken)
            state = self.history.at(max(request.stamp, self.last_tick) + 1e-9)
            try:
                label = self._take(state, request.period, taken, request.yaw)
            except ValueError as error:
                request.reply('', 'refused: bad sample: %s' % error)
                continue
            request.reply(label, 'not written: the landmark file failed (the status says why)')

    def _refuse_requested(self, why):
        for request in self.requested:
            request.reply('', 'not taken: ' + why)
        self.requested = []

    @property
    def distance(self):
        """m of path recorded (the landmarks' d)."""
        return self.recorder.total_distance


class Standstill(object):
    """After the loss at ``reference``: the gyro bias measured standing still
    (core/gyro_bias, ``params``), then the correction (core/heading_correction) from
    ``fit`` (None: heading correction off, no standstill) and ``scale_prior``."""

    def __init__(self, fit, reference, params, scale_prior):
        self.fit, self.params, self.scale_prior = fit, params, scale_prior
        self.measurement = StandstillBias(params)
        if fit is not None:
            self.visual, _ = visual_bias(fit, scale_prior)
            self.recording_time = fit.recording_time(reference.stamp)
        self.deadline = reference.stamp + standstill_timeout(params)

    def correction(self, now, odom=None):
        """The GyroCorrection once the standstill is over at ``now`` (``odom``: a new
        state, None: none), else None."""
        if self.fit is None:
            return no_correction('heading correction off')
        if odom is not None:
            self.measurement.add_odometry(odom)
        if not standstill_complete(self.visual, self.measurement, self.recording_time, self.params) \
                and now < self.deadline:
            return None
        return estimate_correction(self.fit, self.measurement.estimate(), self.scale_prior)
