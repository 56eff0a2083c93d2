"""The return's heading correction: :func:`estimate_correction` (a :class:`GyroCorrection`),
:class:`CorrectedOdometry` (the frame the pi turn and the return drive on) and
:func:`correct_landmarks`. docs/back_travel.md, "Gyro heading correction"."""
import math
from collections import namedtuple

from .geometry import OdomState, wrap_angle
from .gyro_bias import BiasEstimate, fuse_bias
from .gyro_fit import robust_fit
from .period_model import period_turn

CORRECTION_DEFAULTS = {
    'max_bias': 0.01,            # rad/s, a larger bias estimate is rejected (Kobuki gyro: ~6e-4)
    'max_scale': 0.05,           # a larger |scale error| estimate is rejected
    'significance': math.sqrt(2.0),  # a visual-odometry bias alone is used beyond this many stds
    'scale_significance': 3.0,   # the calibrated scale is used beyond this many stds
}


class GyroCorrection(namedtuple('GyroCorrection',
                                 'bias scale bias_std scale_std windows status reason')):
    """Gyro ``bias``, ``scale``, their stds, ``windows``, ``status``, the ``reason`` for a term left out."""

    __slots__ = ()

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
    return GyroCorrection(0.0, 0.0, float('inf'), float('inf'), windows, 'none', reason)


def calibrated_scale(prior, notes):
    """(scale, std) of the calibrated ``prior`` when significant, else (0, inf) and a note in ``notes``."""
    if prior is None:
        notes.append('no gyro calibration: scale not corrected (calibrate_gyro.launch)')
        return 0.0, float('inf')
    if abs(prior.scale) <= CORRECTION_DEFAULTS['scale_significance'] * prior.scale_std:
        notes.append('calibrated scale %+.4f not significant (std %.4f)'
                     % (prior.scale, prior.scale_std))
        return 0.0, float('inf')
    return prior.scale, prior.scale_std


def visual_bias(fit, scale_prior=None):
    """(BiasEstimate or None, windows used) of ``fit`` (a GyroVisualFit), the scale held at the
    calibrated one (none: fitted along, held at 0 if that is singular)."""
    rows = list(fit.rows)
    if len(rows) < fit.min_windows:
        return None, len(rows)
    fixed = None if scale_prior is None else calibrated_scale(scale_prior, [])[0]
    found = robust_fit(rows, True, fit.outlier_k) if fixed is None else None
    if found is None:
        scale = fixed or 0.0
        found = robust_fit([(g - scale * v, v, dt) for g, v, dt in rows], False, fit.outlier_k)
    bias, _, std, _, used = found
    return BiasEstimate(bias, std, 'visual odometry'), used


def estimate_correction(fit, standstill=None, scale_prior=None):
    """The :class:`GyroCorrection` that ``fit``, the ``standstill`` and ``scale_prior`` support: no
    bias beyond ``max_bias``, nor a visual-odometry one alone within ``significance`` stds."""
    notes = []
    scale, scale_std = calibrated_scale(scale_prior, notes)
    visual, used = visual_bias(fit, scale_prior)
    if visual is None:
        notes.append('only %d windows with valid visual odometry (need %d)'
                     % (used, int(fit.min_windows)))
    bias, bias_std = fuse_bias([e for e in (visual, standstill) if e is not None])
    max_bias, significance = CORRECTION_DEFAULTS['max_bias'], CORRECTION_DEFAULTS['significance']
    problem = None
    if not math.isfinite(bias_std):
        problem = 'no bias measurement'
    elif abs(bias) > max_bias:
        problem = 'bias estimate %.2e rad/s beyond %.2e' % (bias, max_bias)
    elif bias == 0.0 or (standstill is None and abs(bias) <= significance * bias_std):
        problem = 'bias %.2e rad/s not significant (std %.1e)' % (bias, bias_std)
    if problem:
        notes.insert(0, problem)
        bias, bias_std = 0.0, float('inf')
        status = 'scale' if scale != 0.0 else 'none'
    else:
        status = 'full' if scale != 0.0 else 'bias'
    return GyroCorrection(bias, scale, bias_std, scale_std, used, status, '; '.join(notes))


class CorrectedOdometry(object):
    """Raw odometry in ``correction``'s frame, equal to the raw one at the first :meth:`update`."""

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

    def snapshot(self):
        """The frame's state as plain numbers (kept by a return's progress), None before the first update."""
        last = self._last
        return None if last is None else {'raw': [last.x, last.y, last.yaw, last.stamp],
                                          'raw_yaw': self._raw_yaw, 'pose': [self._x, self._y, self._yaw]}

    @classmethod
    def started(cls, correction, reference, latest=None, snapshot=None):
        """The frame equal to the raw one at ``reference`` (or a :meth:`snapshot`'s), up to ``latest``."""
        frame = cls(correction)
        if snapshot is None:
            frame.update(reference)
        else:
            try:
                values = [float(v) for v in [*snapshot['raw'], snapshot['raw_yaw'], *snapshot['pose']]]
            except (KeyError, TypeError, ValueError):
                raise ValueError('corrected-frame snapshot must hold raw [x, y, yaw, stamp], raw_yaw '
                                 'and pose [x, y, yaw], got %r' % (snapshot,))
            if len(values) != 8 or not all(math.isfinite(v) for v in values):
                raise ValueError('corrected-frame snapshot must hold 8 finite numbers, got %r' % (values,))
            frame._last = OdomState(values[0], values[1], values[2], 0.0, 0.0, values[3])
            frame._raw_yaw, (frame._x, frame._y, frame._yaw) = values[4], values[5:]
            frame.state = OdomState(frame._x, frame._y, wrap_angle(frame._yaw), 0.0, 0.0, values[3])
        if latest is not None and latest.stamp > reference.stamp:
            frame.update(latest)
        return frame


def correct_landmarks(landmarks, correction, reference_yaw=None, recorded_after=0.0):
    """``landmarks`` in the corrected frame equal to the raw one at yaw ``reference_yaw`` (default
    the last ``psi``), ``recorded_after`` s before the last landmark."""
    landmarks = list(landmarks)
    if correction.status == 'none' or not landmarks:
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
            turned -= period_turn(landmark, newer)   # not wrapped: turns beyond pi per period
        # raw yaw relative to the reference = turned; corrected = increment(turned, -before)
        psi = landmark.psi - turned + correction.increment(turned, recorded_after - before)
        corrected.append(landmark._replace(w=correction.rate(landmark.w), psi=wrap_angle(psi)))
    return corrected[::-1]
