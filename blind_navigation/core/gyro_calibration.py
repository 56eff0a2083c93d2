"""One-off gyro scale calibration: :class:`SpinCalibration` spins both ways under visual
odometry; its :class:`GyroCalibration` is kept in a small YAML file (:func:`save_calibration`,
:func:`load_calibration`). docs/back_travel.md, "Gyro heading correction"."""
import datetime
import math
import os
from collections import namedtuple
from types import SimpleNamespace

import yaml

from .gyro_fit import GyroVisualFit, robust_fit
from .heading_correction import CORRECTION_DEFAULTS
from .rotation import Rotation
from .files import write_atomically

SPIN_DEFAULTS = {
    'turns': 5.0,          # full turns each way: scale std ~0.005 / sqrt(2 pi turns x 2)
    'max_w': 0.6,          # rad/s, cruise turn rate (as the pi turn)
    'pause': 3.0,          # s standing still before, between and after the spins
    'required_scale_std': 0.002,  # a calibration less certain than this is refused
}

#: Keys of the calibration file, in the order written.
FILE_KEYS = ('gyro_scale_error', 'gyro_scale_error_std', 'gyro_bias', 'gyro_bias_std',
             'windows', 'turns', 'calibrated')


class GyroCalibration(namedtuple('GyroCalibration', 'scale scale_std bias bias_std windows')):
    """Gyro ``scale`` error, its std, the ``bias`` seen (informative), its std, ``windows``."""

    __slots__ = ()

    def describe(self):
        return 'scale error %+.5f +- %.5f, bias %.2e +- %.1e rad/s over %d windows' % self


class CalibrationError(Exception):
    """A calibration that could not be made or a calibration file that cannot be used."""


class SpinCalibration(object):
    """Feed :attr:`fit`; :meth:`step` commands the spins; once :attr:`done`, :meth:`result`."""

    def __init__(self, params=None):
        for name, default in SPIN_DEFAULTS.items():
            setattr(self, name, float(getattr(params, name, default)))
        if self.turns <= 0 or self.max_w <= 0 or self.pause < 0:
            raise ValueError('gyro calibration: need turns > 0, max_w > 0, pause >= 0 '
                             '(turns %r, max_w %r, pause %r)' % (self.turns, self.max_w, self.pause))
        self.fit = GyroVisualFit(params)
        self.max_scale = float(getattr(params, 'max_scale', CORRECTION_DEFAULTS['max_scale']))
        angle = 2.0 * math.pi * self.turns
        self._allowance = 2.0 * angle / self.max_w + 20.0
        self._legs = [None, angle, None, -angle, None]     # None: stand still ``pause`` s; rad to turn
        self._leg, self._leg_started, self._rotation = -1, None, None
        self.done, self.failed = False, ''

    @property
    def progress(self):
        """What the routine is doing, for logs."""
        if self.done or self.failed:
            return 'finished' if self.done else 'failed'
        angle = self._legs[max(self._leg, 0)]
        return 'standing still' if angle is None else 'turning %+.1f rad' % angle

    def step(self, odom):
        """Command ``(v, w)`` for this cycle, given the latest OdomState."""
        if self.done or self.failed:
            return 0.0, 0.0
        if self._leg < 0 or (self._rotation.done if self._rotation is not None else
                             odom.stamp - self._leg_started >= self.pause - 1e-9):
            self._leg += 1
            if self._leg == len(self._legs):
                self.done = True
                return 0.0, 0.0
            self._leg_started, angle, self._rotation = odom.stamp, self._legs[self._leg], None
            if angle is not None:
                self._rotation = Rotation(SimpleNamespace(angle=angle, max_w=self.max_w,
                                                          time_allowance=self._allowance))
                self._rotation.start(odom)
        if self._rotation is None:
            return 0.0, 0.0
        command = self._rotation.step(odom)
        if self._rotation.failed:
            self.failed = 'turn of %.1f rad not finished within %.0f s (turned %.2f rad)' % (
                self._rotation.angle, self._rotation.time_allowance, self._rotation.turned)
        return command

    def result(self):
        """The :class:`GyroCalibration`; CalibrationError if not determined."""
        rows = list(self.fit.rows)
        if len(rows) < self.fit.min_windows:
            raise CalibrationError('only %d windows with valid visual odometry (need %d): is '
                                   'visual odometry running and tracking?'
                                   % (len(rows), int(self.fit.min_windows)))
        fit = robust_fit(rows, True, self.fit.outlier_k)
        if fit is None:
            raise CalibrationError('the scale is not determined: no rotation seen by visual odometry')
        bias, scale, bias_std, scale_std, used = fit
        calibration = GyroCalibration(scale, scale_std, bias, bias_std, used)
        if scale_std > self.required_scale_std or abs(scale) > self.max_scale:
            raise CalibrationError('%s: not usable (std above %.4f or |scale| above %.3f); '
                                   'more turns or a more textured scene' % (
                                       calibration.describe(), self.required_scale_std,
                                       self.max_scale))
        return calibration


def save_calibration(path, calibration, turns):
    """Write ``calibration`` to ``path`` atomically."""
    path = os.path.abspath(os.path.expanduser(path))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    values = {'gyro_scale_error': float(calibration.scale),
              'gyro_scale_error_std': float(calibration.scale_std),
              'gyro_bias': float(calibration.bias), 'gyro_bias_std': float(calibration.bias_std),
              'windows': int(calibration.windows), 'turns': float(turns),
              'calibrated': datetime.datetime.now().isoformat(timespec='seconds')}
    text = '# blind_navigation gyro calibration (roslaunch blind_navigation calibrate_gyro.launch)\n'
    text += ''.join('%s: %s\n' % (key, yaml.safe_dump(values[key], default_flow_style=True)
                                  .strip().replace('\n...', '')) for key in FILE_KEYS)
    write_atomically(path, text)


def load_calibration(path):
    """The :class:`GyroCalibration` in ``path``; CalibrationError naming file and key."""
    path = os.path.abspath(os.path.expanduser(path))
    try:
        with open(path) as stream:
            data = yaml.safe_load(stream)
    except (OSError, yaml.YAMLError) as error:
        raise CalibrationError('%s: cannot read the gyro calibration: %s' % (path, error))
    if not isinstance(data, dict):
        raise CalibrationError('%s: a gyro calibration is a mapping of %s' % (path, ', '.join(FILE_KEYS)))
    values = []
    for key, low, high in (('gyro_scale_error', -0.1, 0.1), ('gyro_scale_error_std', 0.0, 0.1),
                           ('gyro_bias', -0.1, 0.1), ('gyro_bias_std', 0.0, 0.1),
                           ('windows', 0, 1e9)):
        value = data.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                or not low <= value <= high:
            raise CalibrationError('%s: %s must be a number in [%g, %g], got %r'
                                   % (path, key, low, high, value))
        values.append(value)
    return GyroCalibration(*[float(value) for value in values[:4]], int(values[4]))
