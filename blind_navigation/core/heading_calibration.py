"""Gyro heading calibration against visual odometry, and the corrected odometry frame.

The back travel tracks the recorded route on wheel/gyro odometry, whose heading
is the integrated gyro: it turns with the gyro's bias ``b`` (rad/s) and its
scale error ``s`` (measured rate = (1 + s) true rate + b). While vision works,
visual odometry (RTAB-Map's) observes the same yaw without those errors (it
drifts with motion instead, not with time), so both can be estimated from the
recording period:

* :class:`HeadingCalibrator` cuts the recording into windows of ``window``
  seconds between visual-odometry samples, each giving the gyro's yaw increment
  (odometry yaw interpolated at the VO stamps) and VO's over the same interval;
  windows that contain a lost VO message or a gap longer than ``max_gap`` are
  not used. The model is ``dpsi_gyro - dpsi_vo = s dpsi_vo + b dt``
  (visual-odometry drift is a random walk, so the increments of separate
  windows are independent); least squares, with one pass that drops windows
  whose residual is beyond ``outlier_k`` robust standard deviations (a VO
  jump), gives ``b``, ``s`` and their standard errors.
* The scale ``s`` comes from the gyro's calibration (core/gyro_calibration.py,
  a one-off spin under visual odometry, both ways), not from the mission: its
  path turns too little, and visual odometry's drift in a few turns can pass
  for a scale error. Without a calibration the scale is not corrected.
* The bias ``b``: the visual-odometry windows (with ``s`` fixed to the
  calibrated value, or without a calibration fitted along as a nuisance
  parameter and not applied) and, after
  vision loss, :class:`StandstillBias` (the robot standing still: the gyro's
  heading change is its bias) are fused by inverse variance
  (:func:`fuse_bias`). Visual odometry drifts a little with every metre, which
  limits it on short missions; the standstill is limited by the gyro's white
  noise (std noise / sqrt(samples)).
* A term is used only when it is significant (more than ``significance``
  standard errors from zero; sqrt 2 is the break-even: correcting by an
  estimate of standard error sigma leaves an error of variance sigma^2, not
  correcting leaves the term itself, whose square is estimated without bias
  by estimate^2 - sigma^2) and the bias only when sane (``|b| <= max_bias``).
  The calibrated scale needs ``scale_significance`` (3) standard errors: it
  is one measurement applied to every mission until the next calibration, so a
  chance false positive would bias them all (sqrt 2 would pass one perfect
  gyro in six).
  Fewer than ``min_windows`` windows: no visual-odometry bias.
* :class:`HeadingCorrection` is the result (``status``: ``full``, ``bias``,
  ``scale`` or ``none``: which terms are used, with the reason for the others).
* :class:`CorrectedOdometry` turns the raw odometry stream into the corrected
  frame: heading increments ``(dpsi - b dt) / (1 + s)``, position increments
  rotated by the heading correction accumulated so far, turn rate
  ``(w - b) / (1 + s)``. The frame coincides with the raw one at its first
  sample (the reference: where the return starts, i.e. where recording stopped).
* :func:`correct_landmarks` expresses recorded landmarks in that same frame:
  each ``psi`` gets the correction the corrected frame would have had at the
  landmark's time (landmark times from the ``T`` chain, the last landmark at the
  reference), ``w`` the corrected rate. The landmark file is not changed.

Plain Python, used by the heading_correction node, back_travel_client and the
simulation harness alike.
"""
import math
from collections import deque, namedtuple

from .geometry import OdomState, wrap_angle

#: Defaults; the heading_correction node exposes each one as a ~private param.
HEADING_CALIBRATION_DEFAULTS = {
    'window': 2.0,               # s, length of one yaw-increment window
    'max_gap': 0.5,              # s, a longer gap between samples breaks the window
    'min_windows': 10,           # fewer usable windows: no correction
    'max_bias': 0.01,            # rad/s, a larger bias estimate is rejected (Kobuki gyro: ~6e-4)
    'max_scale': 0.05,           # a larger |scale error| estimate is rejected
    'significance': math.sqrt(2.0),  # a term is used only if |estimate| > this many standard errors
    'scale_significance': 3.0,   # the same for the calibrated scale (core/gyro_calibration.py)
    'outlier_k': 5.0,            # windows beyond this many robust std of the residuals are dropped
}

#: Defaults of the standstill bias measurement after vision loss (heading_correction node params).
STANDSTILL_DEFAULTS = {
    'standstill_time': 120.0,    # s, the longest standstill (0: none); bias std = gyro noise /
                                 # sqrt(samples): 0.003 rad/s at 50 Hz -> 3.9e-5 rad/s after 120 s
    'heading_budget': 0.005,     # rad: the standstill ends as soon as the bias is known so well
                                 # that its std x the recording's duration is within this
    'standstill_min': 5.0,       # s, the shortest: the gyro's noise, hence the std, is measured
                                 # on the standstill itself, which needs a few hundred samples
    'still_speed': 0.002,        # m/s, wheel speed below which the robot counts as still
    'still_rate': 0.03,          # rad/s, gyro rate below which it counts as not turning
    'still_settle': 0.5,         # s skipped at the start of each still spell
}

#: How much odometry history is kept to interpolate at visual-odometry stamps, s.
HISTORY = 5.0
#: Visual-odometry samples kept while waiting for odometry to cover their stamps.
MAX_PENDING = 300


class HeadingCorrection(namedtuple('HeadingCorrection',
                                   'bias scale bias_std scale_std windows status reason')):
    """Estimated gyro ``bias`` (rad/s) and ``scale`` error (fraction) with their
    standard errors; ``windows`` used; ``status`` ``full`` | ``bias`` | ``scale`` | ``none``;
    ``reason`` says why a term was left out."""

    __slots__ = ()

    @property
    def applied(self):
        return self.status != 'none'

    def increment(self, raw_increment, dt):
        """True yaw increment for a raw (gyro) one over ``dt`` seconds."""
        return (raw_increment - self.bias * dt) / (1.0 + self.scale)

    def rate(self, raw_rate):
        """True turn rate for a raw (gyro) one."""
        return (raw_rate - self.bias) / (1.0 + self.scale)

    def describe(self):
        text = '%s: bias %.2e +- %.1e rad/s, scale %+.4f +- %.4f over %d windows' % (
            self.status, self.bias, self.bias_std, self.scale, self.scale_std, self.windows)
        return text + ('; ' + self.reason if self.reason else '')


def no_correction(reason, windows=0):
    """The identity correction (status ``none``) with its reason."""
    return HeadingCorrection(0.0, 0.0, float('inf'), float('inf'), windows, 'none', reason)


def _param(params, name):
    return float(getattr(params, name, HEADING_CALIBRATION_DEFAULTS[name]))


class HeadingCalibrator(object):
    """Collects odometry and visual-odometry yaw during recording; :meth:`estimate`
    fits the gyro correction (module docstring). ``params``: any object with the
    attributes of :data:`HEADING_CALIBRATION_DEFAULTS` (missing ones default)."""

    def __init__(self, params=None):
        for name in HEADING_CALIBRATION_DEFAULTS:
            setattr(self, name, _param(params, name))
        if self.window <= 0 or self.max_gap <= 0 or self.min_windows < 3:
            raise ValueError('heading calibration: need window > 0, max_gap > 0, min_windows >= 3 '
                             '(window %r, max_gap %r, min_windows %r)'
                             % (self.window, self.max_gap, self.min_windows))
        self.rows = []              # (gyro increment, VO increment, dt) per window
        self._first_stamp = None    # of the first odometry
        self._odom = deque()        # (stamp, unwrapped gyro yaw)
        self._pending = deque()     # (stamp, VO yaw or None) not yet covered by odometry
        self._last_vo = None        # (stamp, unwrapped VO yaw, wrapped VO yaw) of the last sample
        self._start = None          # (stamp, VO yaw, gyro yaw) where the current window began

    def add_odometry(self, stamp, yaw):
        """A raw odometry yaw (rad) at ``stamp`` (s)."""
        if self._odom and stamp <= self._odom[-1][0]:
            return
        if self._first_stamp is None:
            self._first_stamp = stamp
        unwrapped = yaw if not self._odom else self._odom[-1][1] + wrap_angle(yaw - self._last_yaw)
        self._last_yaw = yaw
        self._odom.append((stamp, unwrapped))
        while len(self._odom) > 2 and self._odom[1][0] < stamp - HISTORY:
            self._odom.popleft()
        self._process()

    def add_visual(self, stamp, yaw):
        """A visual-odometry yaw (rad) at ``stamp``; ``yaw`` None when VO is lost."""
        self._pending.append((stamp, yaw))
        while len(self._pending) > MAX_PENDING:   # no odometry is covering them
            self._pending.popleft()
        self._process()

    def _gyro_at(self, stamp):
        """Gyro yaw interpolated at ``stamp``, None if not bracketed closely enough."""
        samples = self._odom
        if not samples or stamp < samples[0][0]:
            return None
        for (ta, ya), (tb, yb) in zip(reversed(list(samples)[:-1]), reversed(samples)):
            if ta <= stamp <= tb:
                if tb - ta > self.max_gap:
                    return None
                return ya if tb == ta else ya + (yb - ya) * (stamp - ta) / (tb - ta)
        return samples[-1][1] if stamp == samples[-1][0] else None

    def _process(self):
        while self._pending and self._odom and self._pending[0][0] <= self._odom[-1][0]:
            stamp, yaw = self._pending.popleft()
            self._visual_sample(stamp, yaw, self._gyro_at(stamp))

    def _visual_sample(self, stamp, yaw, gyro):
        last = self._last_vo
        if yaw is None or gyro is None or (last is not None and stamp <= last[0]):
            self._last_vo = self._start = None
            return
        if last is None or stamp - last[0] > self.max_gap:
            unwrapped, self._start = yaw, None
        else:
            unwrapped = last[1] + wrap_angle(yaw - last[2])
        self._last_vo = (stamp, unwrapped, yaw)
        if self._start is None:
            self._start = (stamp, unwrapped, gyro)
        elif stamp - self._start[0] >= self.window - 1e-9:
            t0, vo0, gyro0 = self._start
            self.rows.append((gyro - gyro0, unwrapped - vo0, stamp - t0))
            self._start = (stamp, unwrapped, gyro)

    def recording_time(self, until):
        """s from the first odometry fed (when the recording began) to ``until``; 0 before any."""
        return 0.0 if self._first_stamp is None else until - self._first_stamp

    def estimate(self, standstill=None, scale_prior=None):
        """The :class:`HeadingCorrection` the data support (see module docstring).

        ``standstill``: a :class:`BiasEstimate` from :class:`StandstillBias`
        (or None), fused with the visual-odometry bias by inverse variance.
        ``scale_prior``: the gyro's calibrated scale error (a
        core/gyro_calibration.GyroCalibration, or None): used instead of
        fitting the scale, when significant."""
        notes = []
        bias, bias_std, scale, scale_std, used = self._measure(standstill, scale_prior, notes)
        problem = self._bias_problem(bias, bias_std) if math.isfinite(bias_std) else \
            'no bias measurement'
        if problem:
            notes.insert(0, problem)
            bias, bias_std = 0.0, float('inf')
        status = {(True, True): 'full', (True, False): 'bias',
                  (False, True): 'scale', (False, False): 'none'}[(not problem, scale != 0.0)]
        return HeadingCorrection(bias, scale, bias_std, scale_std, used, status, '; '.join(notes))

    def visual_bias(self, scale_prior=None):
        """(:class:`BiasEstimate` from the visual-odometry windows, windows used);
        None with fewer than ``min_windows``. Without a calibration the scale is
        still fitted with the bias (as a nuisance: an uncorrected scale error in
        the turns would bias the bias), not applied."""
        rows = list(self.rows)
        if len(rows) < self.min_windows:
            return None, len(rows)
        fit = robust_fit(rows, True, self.outlier_k) if scale_prior is None else None
        if fit is None:
            scale, _ = self._scale(scale_prior, [])
            fit = robust_fit([(g - scale * v, v, dt) for g, v, dt in rows], False, self.outlier_k)
        bias, _, std, _, used = fit
        return BiasEstimate(bias, std, 'visual odometry'), used

    def _measure(self, standstill, scale_prior, notes):
        """(fused bias, its std, scale, scale std, windows used); reasons go to ``notes``."""
        scale, scale_std = self._scale(scale_prior, notes)
        visual, used = self.visual_bias(scale_prior)
        if visual is None:
            notes.append('only %d windows with valid visual odometry (need %d)'
                         % (used, int(self.min_windows)))
        bias, bias_std = fuse_bias([e for e in (visual, standstill) if e is not None])
        return bias, bias_std, scale, scale_std, used

    def _scale(self, prior, notes):
        """(scale, std) to correct by: the calibrated ``prior`` when significant, else
        (0, inf) with the reason appended to ``notes``. A mission's own turns do not
        give it: they are few, and visual odometry's drift in them passed for a
        scale error on a perfect gyro (an S-curve on the fake: -0.0093 +- 0.0024)."""
        if prior is None:
            notes.append('no gyro calibration: scale not corrected (calibrate_gyro.launch)')
            return 0.0, float('inf')
        if abs(prior.scale) <= self.scale_significance * prior.scale_std:
            notes.append('calibrated scale %+.4f not significant (std %.4f)'
                         % (prior.scale, prior.scale_std))
            return 0.0, float('inf')
        return prior.scale, prior.scale_std

    def _bias_problem(self, bias, bias_std):
        """Why the bias estimate is not used, or None."""
        if abs(bias) > self.max_bias:
            return 'bias estimate %.2e rad/s beyond %.2e' % (bias, self.max_bias)
        if abs(bias) <= self.significance * bias_std:
            return 'bias %.2e rad/s not significant (std %.1e)' % (bias, bias_std)
        return None


class BiasEstimate(namedtuple('BiasEstimate', 'bias std source')):
    """One measurement of the gyro bias (rad/s) with its standard error and where it came from."""

    __slots__ = ()


def fuse_bias(estimates):
    """Inverse-variance mean of :class:`BiasEstimate` s: (bias, std); (0, inf)
    for none. Exact ones (std 0, e.g. a noiseless gyro standing still) win."""
    exact = [e.bias for e in estimates if e.std == 0.0]
    if exact:
        return sum(exact) / len(exact), 0.0
    weights = [(1.0 / (e.std * e.std), e.bias) for e in estimates if math.isfinite(e.std)]
    if not weights:
        return 0.0, float('inf')
    total = sum(w for w, _ in weights)
    return sum(w * b for w, b in weights) / total, math.sqrt(1.0 / total)


class StandstillBias(object):
    """Gyro bias measured while the robot stands still (after vision loss,
    before the pi turn): the wheels say it is not moving (``|v| <=
    still_speed``) and the gyro that it is not turning (``|w| <=
    still_rate``), so any heading change is the bias. The first ``settle``
    seconds of each still spell are skipped (the base is still stopping).
    ``params``: any object with the attributes of :data:`STANDSTILL_DEFAULTS`.
    The estimate is the heading change over the time still; its standard
    error comes from the spread of the per-sample rates."""

    def __init__(self, params=None):
        self.still_speed, self.still_rate, self.settle = (
            float(getattr(params, name, STANDSTILL_DEFAULTS[name]))
            for name in ('still_speed', 'still_rate', 'still_settle'))
        self.duration = 0.0        # s counted so far
        self._turned = 0.0         # rad of heading change over that time
        self._rates = [0, 0.0, 0.0]  # per-interval rates: count, sum, sum of squares
        self._last = None          # last still OdomState
        self._still_since = None   # stamp the current still spell began

    def add_odometry(self, state):
        """One OdomState (stamp in s); motion ends the current spell."""
        if abs(state.v) > self.still_speed or abs(state.w) > self.still_rate:
            self._last = self._still_since = None
            return
        if self._still_since is None:
            self._still_since = state.stamp
        last, self._last = self._last, state
        if last is None or state.stamp <= last.stamp or last.stamp - self._still_since < self.settle:
            return
        dt = state.stamp - last.stamp
        turned = wrap_angle(state.yaw - last.yaw)
        self.duration += dt
        self._turned += turned
        rate = turned / dt
        self._rates = [self._rates[0] + 1, self._rates[1] + rate, self._rates[2] + rate * rate]

    def estimate(self):
        """:class:`BiasEstimate`, or None before two intervals were counted."""
        n, total, squares = self._rates
        if n < 2:
            return None
        spread = max(squares - total * total / n, 0.0) / (n - 1)
        return BiasEstimate(self._turned / self.duration, math.sqrt(spread / n),
                            'standstill %.1f s' % self.duration)


def standstill_complete(visual, standstill, recording_time, params=None):
    """True once the standstill after vision loss may end: it lasted
    ``standstill_time``, or at least ``standstill_min`` and the bias, the
    standstill's fused with ``visual`` (HeadingCalibrator.visual_bias at vision
    loss, or None), is known well enough for this mission: ``bias std x
    recording_time <= heading_budget`` (rad). The landmarks' headings are
    corrected back over the recording, and the return takes about as long (the
    standstill itself adds nothing: its drift is what it measures). A short
    mission needs little, a long one up to ``standstill_time``; a noiseless gyro
    none. ``params``: as :data:`STANDSTILL_DEFAULTS`."""
    longest, shortest, budget = (float(getattr(params, name, STANDSTILL_DEFAULTS[name]))
                                 for name in ('standstill_time', 'standstill_min', 'heading_budget'))
    if standstill.duration >= longest - 1e-9:
        return True
    measured = standstill.estimate()
    if standstill.duration < shortest - 1e-9 or measured is None:
        return False
    _, std = fuse_bias([e for e in (visual, measured) if e is not None])
    return std * max(recording_time, 0.0) <= budget


def standstill_timeout(params=None):
    """s after vision loss at which the standstill ends even if the robot kept
    moving: ``standstill_timeout`` when set, else 2 x ``standstill_time`` + 5."""
    timeout = getattr(params, 'standstill_timeout', None)
    if timeout is None:
        return 2.0 * float(getattr(params, 'standstill_time',
                                   STANDSTILL_DEFAULTS['standstill_time'])) + 5.0
    return float(timeout)


def _fit(rows, with_scale):
    """Least squares of ``gyro - vo = s vo + b dt``; (b, s, std_b, std_s, residuals)
    or None when singular. Without scale, s = 0 and std_s = inf."""
    n = len(rows)
    ys = [g - v for g, v, _ in rows]
    stt = sum(dt * dt for _, _, dt in rows)
    sty = sum(dt * y for (_, _, dt), y in zip(rows, ys))
    if not with_scale:
        bias = sty / stt
        residuals = [y - bias * dt for (_, _, dt), y in zip(rows, ys)]
        sigma2 = sum(r * r for r in residuals) / max(n - 1, 1)
        return bias, 0.0, math.sqrt(sigma2 / stt), float('inf'), residuals
    svv = sum(v * v for _, v, _ in rows)
    svt = sum(v * dt for _, v, dt in rows)
    svy = sum(v * y for (_, v, _), y in zip(rows, ys))
    det = svv * stt - svt * svt
    if det <= 1e-12 * svv * stt or svv <= 0.0:
        return None
    scale = (stt * svy - svt * sty) / det
    bias = (svv * sty - svt * svy) / det
    residuals = [y - scale * v - bias * dt for (_, v, dt), y in zip(rows, ys)]
    sigma2 = sum(r * r for r in residuals) / max(n - 2, 1)
    return bias, scale, math.sqrt(sigma2 * svv / det), math.sqrt(sigma2 * stt / det), residuals


def robust_fit(rows, with_scale, outlier_k):
    """:func:`_fit`, then again without the windows whose residual exceeds
    ``outlier_k`` x 1.4826 x the median absolute residual. Returns
    (b, s, std_b, std_s, windows used) or None when singular."""
    fit = _fit(rows, with_scale)
    if fit is None:
        return None
    residuals = fit[4]
    spread = 1.4826 * sorted(abs(r) for r in residuals)[len(residuals) // 2]
    if spread > 0.0:
        kept = [row for row, r in zip(rows, residuals) if abs(r) <= outlier_k * spread]
        if len(kept) < len(rows) and len(kept) >= 3:
            rows, fit = kept, _fit(kept, with_scale)
            if fit is None:
                return None
    return fit[0], fit[1], fit[2], fit[3], len(rows)


class CorrectedOdometry(object):
    """Raw odometry -> the corrected frame of ``correction`` (module docstring).
    The frame equals the raw one at the first state given to :meth:`update`."""

    def __init__(self, correction):
        self.correction = correction
        self._last = None
        self._raw_yaw = self._yaw = self._x = self._y = 0.0
        self.state = None

    def update(self, odom):
        """Corrected OdomState for the raw OdomState ``odom`` (stamps in s)."""
        last = self._last
        if last is None:
            self._raw_yaw, self._yaw, self._x, self._y = odom.yaw, odom.yaw, odom.x, odom.y
        else:
            turned = wrap_angle(odom.yaw - last.yaw)
            offset_before = self._yaw - self._raw_yaw
            self._raw_yaw += turned
            self._yaw += self.correction.increment(turned, odom.stamp - last.stamp)
            offset = (offset_before + self._yaw - self._raw_yaw) / 2.0
            dx, dy = odom.x - last.x, odom.y - last.y
            c, s = math.cos(offset), math.sin(offset)
            self._x += c * dx - s * dy
            self._y += s * dx + c * dy
        self._last = odom
        self.state = OdomState(self._x, self._y, wrap_angle(self._yaw), odom.v,
                               self.correction.rate(odom.w), odom.stamp)
        return self.state


def correct_landmarks(landmarks, correction, reference_yaw=None):
    """``landmarks`` (recording order, raw odometry frame) in the corrected frame
    whose reference is the last landmark (where recording stopped; raw yaw
    ``reference_yaw`` there, default the last landmark's ``psi``). Landmark k
    was taken ``sum(T of the landmarks after k)`` seconds before the reference;
    its heading gets the correction accumulated back to then."""
    landmarks = list(landmarks)
    if not correction.applied or not landmarks:
        return landmarks
    last = landmarks[-1]
    turned = wrap_angle(last.psi - (last.psi if reference_yaw is None else reference_yaw))
    before = 0.0                  # s between landmark k and the reference
    corrected = []
    for index in range(len(landmarks) - 1, -1, -1):
        landmark = landmarks[index]
        if index < len(landmarks) - 1:
            newer = landmarks[index + 1]
            before += newer.T
            turned += wrap_angle(landmark.psi - newer.psi)
        # raw yaw relative to the reference = turned; corrected = increment(turned, -before)
        psi = landmark.psi - turned + correction.increment(turned, -before)
        corrected.append(landmark._replace(w=correction.rate(landmark.w), psi=wrap_angle(psi)))
    return corrected[::-1]
