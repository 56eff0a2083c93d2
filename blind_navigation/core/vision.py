"""Vision-loss detectors with debounce (camera stall, dark images, VO lost or stalled,
RTAB-Map's ``lost`` flag, manual) bundled by :class:`VisionLossMonitor`; :class:`VisionBack`
says when vision is back (docs/detection.md)."""
import math
import struct
from collections import namedtuple

import numpy

Loss = namedtuple('Loss', 'detector reason t since')
Loss.__doc__ = 'A detector fired at ``t`` (s); ``since``: when the failure it saw began.'
#: RTAB-Map's odometry sets pose/twist covariance diagonals to 9999 when lost.
LOST_COVARIANCE = 9999.0
DETECTORS = ('stall', 'dark', 'vo_lost', 'vo_stall', 'odom_info', 'manual')


class Debounce(object):
    """A condition holding ``hold`` s and ``min_count`` updates fires, once until it clears."""

    def __init__(self, hold, min_count=1):
        if hold < 0 or min_count < 1:
            raise ValueError('Debounce: hold must be >= 0 and min_count >= 1, got %r, %r'
                             % (hold, min_count))
        self.hold, self.min_count = hold, min_count
        self.reset()

    def update(self, t, bad, onset=None):
        """The condition at ``t`` (``onset``: a new bad run's start); True exactly when it fires."""
        if not bad:
            self.reset()
            return False
        if self.onset is None:
            self.onset = t if onset is None else onset
        self.count += 1
        if self.fired or self.count < self.min_count or t - self.onset < self.hold:
            return False
        self.fired = True
        return True

    def reset(self):
        """Forget the current run (onset, count of bad updates, fired)."""
        self.onset, self.count, self.fired = None, 0, False


class HostFlow(object):
    """The wheel odometry's arrivals: a silence over ``gap`` s is the host's, no vision loss."""

    def __init__(self, gap):
        if not gap > 0:
            raise ValueError('host flow gap must be > 0 s, got %r' % (gap,))
        self.gap, self.last, self.resumed = gap, None, None   # resumed: end of the last outage

    def arrived(self, t):
        if self.last is not None and t - self.last > self.gap:
            self.resumed = t
        self.last = t

    def flowing(self, t):
        return self.last is None or t - self.last <= self.gap


class StallDetector(object):
    """Fires after ``timeout`` s (+ debounce) without a message, once armed by the first one."""

    def __init__(self, name, timeout, debounce, what='message'):
        if timeout <= 0:
            raise ValueError('%s: timeout must be > 0 s, got %r' % (name, timeout))
        self.name, self.timeout, self.what, self.last = name, timeout, what, None
        self.debounce = Debounce(debounce)

    def seen(self, t):
        """A message arrived at ``t`` (clears the stall)."""
        self.last = t
        self.debounce.update(t, False)

    def check(self, t, host=None):
        """Periodic check at ``t`` (``host``: a :class:`HostFlow` or None); a ``Loss`` or None."""
        if self.last is None or (host is not None and not host.flowing(t)):
            return None
        since = self._since(self.last, host)
        silent = t - since
        if not self.debounce.update(t, silent >= self.timeout, onset=since + self.timeout):
            return None
        return Loss(self.name, 'no %s for %.2f s (timeout %.2f s + debounce %.2f s)'
                    % (self.what, t - self.last, self.timeout, self.debounce.hold), t, self.last)

    def due(self, now, host=None):
        """When this stall could fire next (unarmed: as if armed ``now``; a silent host: gap)."""
        if host is not None and not host.flowing(now):
            return now + host.gap
        return self._since(now if self.last is None else self.last, host) + self.timeout + self.debounce.hold

    @staticmethod
    def _since(last, host):
        """Where the silence counts from: the last message, or the host's resumption if later."""
        if host is not None and host.resumed is not None:
            return max(last, host.resumed)
        return last


class ConditionDetector(object):
    """Fires when the messages report a bad condition for ``debounce`` s and ``min_count`` messages."""

    def __init__(self, name, debounce, min_count=1):
        self.name, self.debounce = name, Debounce(debounce, min_count)

    def update(self, t, why):
        """A message at ``t``; ``why`` says what is wrong with it (None when fine)."""
        if not self.debounce.update(t, why is not None):
            return None
        return Loss(self.name, '%s for %.2f s (%d messages, debounce %.2f s)'
                    % (why, t - self.debounce.onset, self.debounce.count, self.debounce.hold),
                    t, self.debounce.onset)


_CHANNELS = {'mono8': 1, '8UC1': 1, 'rgb8': 3, 'bgr8': 3, '8UC3': 3, 'rgba8': 4, 'bgra8': 4, '8UC4': 4,
             'mono16': 1, '16UC1': 1, 'rgb16': 3, 'bgr16': 3, 'rgba16': 4, 'bgra16': 4}
_BAYER_PREFIX = 'bayer_'
#: Pixels sampled per image (evenly strided).
MAX_SAMPLES = 20000


def image_mean_intensity(encoding, height, width, step, data, is_bigendian=False):
    """Mean intensity (0..255) of a raw sensor_msgs/Image; ValueError for its encoding or size."""
    if encoding.startswith(_BAYER_PREFIX):
        channels, depth = 1, 2 if encoding.endswith('16') else 1
    elif encoding in _CHANNELS:
        channels, depth = _CHANNELS[encoding], 2 if '16' in encoding else 1
    else:
        raise ValueError('image encoding %r not supported for the dark detector' % encoding)
    row_bytes = width * channels * depth
    if height <= 0 or width <= 0 or step < row_bytes or len(data) < step * (height - 1) + row_bytes:
        raise ValueError('image %dx%d %s: step %d / %d data bytes do not match'
                         % (width, height, encoding, step, len(data)))
    dtype = numpy.dtype('>u2' if is_bigendian else '<u2') if depth == 2 else numpy.uint8
    stride = max(1, int(math.sqrt(height * width / float(MAX_SAMPLES))))
    rows = numpy.frombuffer(data, dtype=numpy.uint8, count=step * (height - 1) + row_bytes)
    rows = numpy.lib.stride_tricks.as_strided(rows, shape=(height, row_bytes), strides=(step, 1))
    pixels = rows[::stride].copy().view(dtype).reshape(-1, width, channels)[:, ::stride, :3]
    mean = float(pixels.mean())
    return mean / 257.0 if depth == 2 else mean


def wire_lost_reason(wire):
    """Why a visual-odometry message (core/odometry_wire.WireOdometry) means lost (non-finite,
    null quaternion, covariance), or None."""
    orientation = (wire.qx, wire.qy, wire.qz, wire.qw)
    values = (wire.x, wire.y) + orientation
    if not all(math.isfinite(v) for v in values):
        return 'VO pose not finite %r' % (values,)
    if sum(q * q for q in orientation) < 1e-12:
        return 'VO null quaternion'
    worst = max(tuple(wire.pose_covariance) + tuple(wire.twist_covariance))
    if not worst < LOST_COVARIANCE:  # also catches NaN
        return 'VO covariance %g >= %g' % (worst, LOST_COVARIANCE)
    return None


_HEADER = struct.Struct('<III')  # std_msgs/Header: seq, stamp.secs, stamp.nsecs; then frame_id


def odom_info_lost(buff):
    """The ``lost`` flag of a serialised rtabmap OdomInfo; ValueError when too short."""
    offset = _HEADER.size
    if len(buff) < offset + 4:
        raise ValueError('odom_info message of %d bytes is shorter than its header' % len(buff))
    (frame_id_length,) = struct.unpack_from('<I', buff, offset)
    offset += 4 + frame_id_length
    if len(buff) <= offset:
        raise ValueError('odom_info message of %d bytes ends before its lost flag' % len(buff))
    return bytearray(buff[offset:offset + 1])[0] != 0


class VisionLossMonitor(object):
    """The ``enabled`` detectors (names from DETECTORS) behind one vision-loss signal."""

    def __init__(self, enabled, image_timeout=1.0, vo_timeout=1.0, debounce=0.5,
                 dark_threshold=10.0, dark_frames=3, host_gap=0.5):
        unknown = set(enabled) - set(DETECTORS)
        if unknown:
            raise ValueError('unknown vision detectors %s (known: %s)'
                             % (sorted(unknown), ', '.join(DETECTORS)))
        self.enabled = frozenset(enabled)
        self.dark_threshold = dark_threshold
        self.stall = StallDetector('stall', image_timeout, debounce, 'image')
        self.vo_stall = StallDetector('vo_stall', vo_timeout, debounce, 'VO odometry')
        self.dark = ConditionDetector('dark', debounce, dark_frames)
        self.vo_lost = ConditionDetector('vo_lost', debounce)
        self.odom_info = ConditionDetector('odom_info', debounce)
        self._stalls = (self.stall, self.vo_stall)
        self._all = (self.stall, self.vo_stall, self.dark, self.vo_lost, self.odom_info)
        self.host, self.last_t = HostFlow(host_gap), None

    def _clock(self, t):
        """Reset every detector when time jumps backwards."""
        if self.last_t is not None and t < self.last_t:
            for detector in self._all:
                detector.debounce.reset()
            for stall in self._stalls:
                stall.last = None
            self.host = HostFlow(self.host.gap)
        self.last_t = t

    def _fired(self, *losses):
        return [loss for loss in losses if loss is not None and loss.detector in self.enabled]

    def image(self, t, mean_intensity):
        """An image arrived at ``t`` (its mean intensity, None when unknown)."""
        self._clock(t)
        self.stall.seen(t)
        if mean_intensity is None:
            return []
        dark = mean_intensity < self.dark_threshold
        why = 'mean intensity %.1f < %.1f' % (mean_intensity, self.dark_threshold) if dark else None
        return self._fired(self.dark.update(t, why))

    def vo_odometry(self, t, lost_reason):
        """A VO odometry message at ``t`` (``lost_reason``: wire_lost_reason's)."""
        self._clock(t)
        self.vo_stall.seen(t)
        return self._fired(self.vo_lost.update(t, lost_reason))

    def odom_info_flag(self, t, lost):
        """An RTAB-Map odom_info message at ``t`` with its ``lost`` flag."""
        self._clock(t)
        return self._fired(self.odom_info.update(t, 'odom_info lost flag set' if lost else None))

    def host_flow(self, t):
        """A wheel-odometry message arrived at ``t`` (:class:`HostFlow`)."""
        self.host.arrived(t)

    def check(self, t):
        """Periodic check of the stall detectors."""
        self._clock(t)
        return self._fired(*(stall.check(t, self.host) for stall in self._stalls))

    def manual(self, t, source):
        """Vision declared lost by hand: fires at once if enabled."""
        self._clock(t)
        return self._fired(Loss('manual', 'vision_lost published by %s' % source, t, t))

    def unhealthy(self, t):
        """Why vision is not healthy at ``t`` by the enabled detectors, or None."""
        watched = [stall for stall in self._stalls if stall.name in self.enabled]
        if 'dark' in self.enabled and self.stall not in watched:
            watched.append(self.stall)      # the dark detector reads the images themselves
        if not watched:
            return 'no camera or visual-odometry stream watched'
        for stall in watched:
            if stall.last is None or t - stall.last >= stall.timeout:
                return 'no %s' % stall.what
        for detector in (self.dark, self.vo_lost, self.odom_info):
            if detector.name in self.enabled and detector.debounce.onset is not None:
                return '%s still bad' % detector.name
        return None


class VisionBack(object):
    """Vision is back once ``monitor`` has been healthy for ``hold`` s without a break."""

    def __init__(self, monitor, hold):
        if not hold > 0:
            raise ValueError('vision_back_time must be > 0 s, got %r' % (hold,))
        self.monitor, self.debounce = monitor, Debounce(hold)

    def update(self, t):
        """True exactly once, when vision has been back for ``hold``."""
        return self.debounce.update(t, self.monitor.unhealthy(t) is None)
