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
  not used. Least squares of ``dpsi_gyro - dpsi_vo = s dpsi_vo + b dt``
  (visual-odometry drift is a random walk, so the increments of separate
  windows are independent), with one pass that drops windows whose residual is
  beyond ``outlier_k`` robust standard deviations (a VO jump), gives ``b``,
  ``s`` and their standard errors. A term is used only when it is
  significant (at least ``significance`` standard errors from zero; sqrt 2
  is the break-even: correcting by an estimate of standard error sigma leaves
  an error of variance sigma^2, not correcting leaves the term itself, whose
  square is estimated without bias by estimate^2 - sigma^2) and sane
  (``|b| <= max_bias``, ``|s| <= max_scale``); the scale also only when
  known to ``max_scale_std`` (pi x 0.003 = 0.01 rad, the pi turn's own
  tolerance: a path that hardly turns does not determine it).
  Without the scale the bias alone is fitted; without a usable bias, or with
  fewer than ``min_windows`` windows, there is no correction (the identity).
* :class:`HeadingCorrection` is the result (``status``: ``full``, ``bias`` or
  ``none``, with the reason).
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
    'significance': math.sqrt(2.0),  # a term is used only if |estimate| >= this many standard errors
    'max_scale_std': 0.003,      # scale used only if known to this (pi x 0.003 = the turn's 0.01 rad)
    'outlier_k': 5.0,            # windows beyond this many robust std of the residuals are dropped
}

#: How much odometry history is kept to interpolate at visual-odometry stamps, s.
HISTORY = 5.0
#: Visual-odometry samples kept while waiting for odometry to cover their stamps.
MAX_PENDING = 300


class HeadingCorrection(namedtuple('HeadingCorrection',
                                   'bias scale bias_std scale_std windows status reason')):
    """Estimated gyro ``bias`` (rad/s) and ``scale`` error (fraction) with their
    standard errors; ``windows`` used; ``status`` ``full`` | ``bias`` | ``none``;
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
        self._odom = deque()        # (stamp, unwrapped gyro yaw)
        self._pending = deque()     # (stamp, VO yaw or None) not yet covered by odometry
        self._last_vo = None        # (stamp, unwrapped VO yaw, wrapped VO yaw) of the last sample
        self._start = None          # (stamp, VO yaw, gyro yaw) where the current window began

    def add_odometry(self, stamp, yaw):
        """A raw odometry yaw (rad) at ``stamp`` (s)."""
        if self._odom and stamp <= self._odom[-1][0]:
            return
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

    def estimate(self):
        """The :class:`HeadingCorrection` the data support (see module docstring)."""
        rows = list(self.rows)
        if len(rows) < self.min_windows:
            return no_correction('only %d windows with valid visual odometry (need %d)'
                                 % (len(rows), int(self.min_windows)), len(rows))
        fit = _robust_fit(rows, True, self.outlier_k)
        reason = ''
        if fit is None:
            reason = 'scale not determined (no rotation seen)'
        else:
            bias, scale, bias_std, scale_std, used = fit
            if abs(scale) > self.max_scale:
                reason = 'scale estimate %+.4f beyond %.3f' % (scale, self.max_scale)
            elif scale_std > self.max_scale_std:
                reason = 'scale %+.4f not determined (std %.4f > %.4f)' % (scale, scale_std,
                                                                          self.max_scale_std)
            elif abs(scale) < self.significance * scale_std:
                reason = 'scale %+.4f not significant (std %.4f)' % (scale, scale_std)
            elif self._bias_problem(bias, bias_std) is None:
                return HeadingCorrection(bias, scale, bias_std, scale_std, used, 'full', '')
        bias, _, bias_std, _, used = _robust_fit(rows, False, self.outlier_k)
        problem = self._bias_problem(bias, bias_std)
        if problem:
            return no_correction('%s; %s' % (problem, reason) if reason else problem, used)
        return HeadingCorrection(bias, 0.0, bias_std, float('inf'), used, 'bias', reason)

    def _bias_problem(self, bias, bias_std):
        """Why the bias estimate is not used, or None."""
        if abs(bias) > self.max_bias:
            return 'bias estimate %.2e rad/s beyond %.2e' % (bias, self.max_bias)
        if abs(bias) < self.significance * bias_std:
            return 'bias %.2e rad/s not significant (std %.1e)' % (bias, bias_std)
        return None


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


def _robust_fit(rows, with_scale, outlier_k):
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
