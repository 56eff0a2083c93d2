"""Motion events, where an extra landmark makes the recorded path unambiguous (docs/recording.md,
"Motion events"): :class:`MotionEvents` reports when the robot starts or stops moving, reverses
or turns; :class:`EventSampler` interleaves a landmark at each event with the periodic ticks."""
from collections import deque

#: The motion events' constants (core/role_params: fixed).
EVENT_DEFAULTS = {
    'event_speed': 0.01,       # m/s; averaged |v| above this: translating
    'event_hysteresis': 0.5,   # below event_speed x this: not translating any more
    'event_window': 0.2,       # s of odometry averaged
    'event_debounce': 0.1,     # s a new state must hold before it is an event
    'event_turn_rate': 0.15,   # rad/s; averaged |w| crossing this is an event too
    'event_latency': 0.5,      # s periodic ticks wait, so that an event dated back comes first
}

STILL, FORWARD, BACKWARD = 'still', 'forward', 'backward'
_OPPOSITE = {FORWARD: BACKWARD, BACKWARD: FORWARD}


class MotionEvents(object):
    """Feed every odometry state to :meth:`update`; it returns an event's stamp."""

    def __init__(self):
        for name, value in EVENT_DEFAULTS.items():
            setattr(self, name, value)
        self.state = STILL
        self._recent = deque()
        self._sum = self._sum_w = 0.0
        self.turning = False
        self._candidate = None      # (state, since)
        self._left_old = None       # stamp of the first raw sample of the current run off the old state
        self._crossed = None        # ... and of its first raw sample in the opposite direction

    def _classify(self, speed, rate, state, turning):
        on, off = self.event_speed, self.event_speed * self.event_hysteresis
        if state == STILL:
            moving = FORWARD if speed > on else BACKWARD if speed < -on else STILL
        elif state == FORWARD:
            moving = BACKWARD if speed < -on else FORWARD if speed > off else STILL
        else:
            moving = FORWARD if speed > on else BACKWARD if speed < -off else STILL
        limit = self.event_turn_rate * (self.event_hysteresis if turning else 1.0)
        return moving, abs(rate) > limit

    def update(self, odom_state):
        """Add one OdomState; the stamp of a motion event just confirmed, else None (dated back
        to where the raw speed left the old state; a reversal: its first state the new way)."""
        stamp = odom_state.stamp
        self._recent.append((stamp, odom_state.v, odom_state.w))
        self._sum += odom_state.v
        self._sum_w += odom_state.w
        while self._recent and self._recent[0][0] < stamp - self.event_window + 1e-9:
            _, v, w = self._recent.popleft()
            self._sum -= v
            self._sum_w -= w
        current = (self.state, self.turning)
        raw = self._classify(odom_state.v, odom_state.w, *current)
        if raw == current:
            self._left_old = self._crossed = None
        elif self._left_old is None:
            self._left_old = stamp
        if self._crossed is None and raw[0] == _OPPOSITE.get(self.state):
            self._crossed = stamp
        count = len(self._recent)
        new = self._classify(self._sum / count, self._sum_w / count, *current)
        if new == current:
            self._candidate = None
            return None
        if self._candidate is None or self._candidate[0] != new:
            self._candidate = (new, stamp)
        if stamp - self._candidate[1] >= self.event_debounce - 1e-9:
            reversal = new[0] == _OPPOSITE.get(self.state) and self._crossed is not None
            since = self._crossed if reversal else self._left_old
            (self.state, self.turning), self._candidate = new, None
            self._left_old = self._crossed = None
            return since if since is not None else stamp
        return None


class EventSampler(object):
    """The motion-event samples of one recording, in time order with the periodic ticks: feed
    every odometry state to :meth:`odometry`; before the tick stamped ``t`` (``latency`` s after
    it) take :meth:`before`'s samples, then the tick with :meth:`tick`'s period (never negative).
    A clock going back restarts the events."""

    def __init__(self):
        self.events = MotionEvents()
        self.latency = self.events.event_latency
        self.pending = []          # event stamps not taken yet
        self.last = None           # stamp of the last sample taken (event or tick)
        self._split = False        # an event sample was taken since the last tick
        self._fed = None           # stamp of the last odometry state fed

    def start(self, stamp):
        """The recording starts at ``stamp`` (s)."""
        self.last = stamp

    def odometry(self, state):
        """One odometry state (every one, in order)."""
        if self._fed is not None and state.stamp < self._fed:   # the clock went back
            self.events, self.pending = MotionEvents(), []
        self._fed = state.stamp
        event = self.events.update(state)
        if event is not None:
            self.pending.append(event)

    def before(self, stamp, state_at):
        """[(state, s since the previous sample)]: the event samples before one at ``stamp``,
        oldest first; ``state_at(t)``: the odometry state at ``t`` (the latest no later)."""
        taken = []
        while self.pending and self.pending[0] < stamp - 1e-9:
            state = state_at(self.pending.pop(0) + 1e-9)
            if state is not None and state.stamp > self.last + 1e-9:
                taken.append((state, state.stamp - self.last))
                self.last, self._split = state.stamp, True
        return taken

    def tick(self, stamp, period):
        """The period to record for the periodic tick at ``stamp`` whose own period
        is ``period``: the time since the last event sample if one came between."""
        if self._split and stamp > self.last:
            period = stamp - self.last
        self.last, self._split = stamp, False
        return period
