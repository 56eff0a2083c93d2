"""Gyro scale calibration (core/gyro_calibration.py) and the standstill bias
(core/gyro_bias.StandstillBias, fuse_bias, estimate with a calibrated
scale): the spin recovers the fake gyro's scale error, a spin without visual
odometry is refused, the file round-trips and bad files are named, a standing
robot's heading drift is its bias, and the estimate combines them."""
import math
import os
import random

import pytest

from blind_navigation.core.geometry import OdomState
from blind_navigation.core.gyro_calibration import (CalibrationError, GyroCalibration,
                                                    SpinCalibration, load_calibration,
                                                    save_calibration)
from blind_navigation.core.gyro_bias import (BiasEstimate, StandstillBias, fuse_bias,
                                              standstill_complete)
from blind_navigation.core.gyro_fit import GyroVisualFit
from blind_navigation.core.heading_correction import estimate_correction
from blind_navigation.sim.kobuki import load_profile
from blind_navigation.sim.harness import simulate_gyro_calibration


def test_spin_recovers_the_fake_gyro_scale_error():
    true_scale = load_profile('paper')['gyro_scale_error']
    calibration = simulate_gyro_calibration('paper', seed=3)
    assert calibration.scale_std < 0.002
    assert calibration.scale == pytest.approx(true_scale, abs=4 * calibration.scale_std)
    assert calibration.windows >= 30


def test_spin_on_a_perfect_gyro_finds_no_scale_error():
    calibration = simulate_gyro_calibration('ideal', seed=0)
    assert abs(calibration.scale) < 4 * calibration.scale_std


def test_spin_without_visual_odometry_is_refused():
    spin = SpinCalibration()
    stamp, yaw = 0.0, 0.0
    while not spin.done and stamp < 300.0:
        _, w = spin.step(OdomState(0.0, 0.0, yaw, 0.0, 0.0, stamp))
        stamp += 0.02
        yaw = math.remainder(yaw + w * 0.02, 2.0 * math.pi)
        spin.fit.add_odometry(stamp, yaw)
    assert spin.done and not spin.failed
    with pytest.raises(CalibrationError, match='visual odometry'):
        spin.result()


def test_spin_turns_both_ways_and_ends_still():
    spin = SpinCalibration(type('P', (), {'turns': 1.0, 'pause': 1.0})())
    stamp, yaw, turned, rates = 0.0, 0.0, 0.0, []
    while not spin.done and stamp < 100.0:
        _, w = spin.step(OdomState(0.0, 0.0, yaw, 0.0, w if rates else 0.0, stamp))
        rates.append(w)
        turned += w * 0.02
        yaw = math.remainder(yaw + w * 0.02, 2.0 * math.pi)
        stamp += 0.02
    assert spin.done
    assert max(rates) > 0.5 and min(rates) < -0.5
    assert abs(turned) < 0.05          # as many turns back
    assert spin.step(OdomState(0.0, 0.0, yaw, 0.0, 0.0, stamp)) == (0.0, 0.0)


def test_calibration_file_round_trip_is_atomic(tmp_path):
    path = str(tmp_path / 'robot' / 'gyro.yaml')
    calibration = GyroCalibration(0.00512, 0.0007, 3.1e-4, 2e-5, 63)
    save_calibration(path, calibration, turns=3)
    assert load_calibration(path) == calibration
    assert os.listdir(str(tmp_path / 'robot')) == ['gyro.yaml']


@pytest.mark.parametrize('text, key', [
    ('gyro_scale_error: 0.5\ngyro_scale_error_std: 0.001\ngyro_bias: 0.0\ngyro_bias_std: 0.0\n'
     'windows: 5\n', 'gyro_scale_error'),
    ('gyro_scale_error: 0.005\ngyro_scale_error_std: .nan\ngyro_bias: 0.0\ngyro_bias_std: 0.0\n'
     'windows: 5\n', 'gyro_scale_error_std'),
    ('gyro_scale_error: 0.005\ngyro_scale_error_std: 0.001\n', 'gyro_bias'),
    ('- just a list\n', 'mapping'),
    ('gyro_scale_error: [unclosed\n', 'cannot read'),
])
def test_bad_calibration_file_is_named(tmp_path, text, key):
    path = tmp_path / 'gyro.yaml'
    path.write_text(text)
    with pytest.raises(CalibrationError) as error:
        load_calibration(str(path))
    assert str(path) in str(error.value) and key in str(error.value)


def test_missing_calibration_file_is_named(tmp_path):
    with pytest.raises(CalibrationError, match='nothing.yaml'):
        load_calibration(str(tmp_path / 'nothing.yaml'))


def still_odometry(standstill, seconds, bias, noise, rng, start=0.0, yaw=0.0):
    """Feed ``seconds`` of a still robot whose gyro has ``bias`` and white ``noise`` at 50 Hz."""
    stamp = start
    for _ in range(int(round(seconds / 0.02))):
        rate = bias + rng.gauss(0.0, noise)
        yaw += rate * 0.02
        stamp += 0.02
        standstill.add_odometry(OdomState(0.0, 0.0, math.remainder(yaw, 2 * math.pi), 0.0, rate, stamp))
    return stamp, yaw


def test_standstill_measures_the_bias_within_its_standard_error():
    standstill = StandstillBias()
    still_odometry(standstill, 60.0, 4e-4, 0.003, random.Random(1))
    estimate = standstill.estimate()
    assert standstill.duration == pytest.approx(59.5, abs=0.03)    # first 0.5 s skipped
    assert estimate.std == pytest.approx(0.003 / math.sqrt(60 * 50), rel=0.1)
    assert estimate.bias == pytest.approx(4e-4, abs=4 * estimate.std)


def test_standstill_ignores_motion():
    standstill = StandstillBias()
    rng = random.Random(2)
    stamp, yaw = still_odometry(standstill, 10.0, 2e-4, 0.003, rng)
    counted = standstill.duration
    for _ in range(100):   # driving: a fast turn would look like a huge bias
        stamp += 0.02
        yaw += 0.5 * 0.02
        standstill.add_odometry(OdomState(0.0, 0.0, yaw, 0.1, 0.5, stamp))
    assert standstill.duration == counted
    still_odometry(standstill, 10.0, 2e-4, 0.003, rng, stamp, yaw)
    assert standstill.duration == pytest.approx(2 * counted, abs=0.03)
    assert abs(standstill.estimate().bias - 2e-4) < 4 * standstill.estimate().std
    assert StandstillBias().estimate() is None


def test_fuse_bias_weights_by_inverse_variance():
    bias, std = fuse_bias([BiasEstimate(1e-4, 1e-4, 'a'), BiasEstimate(4e-4, 1e-4, 'b')])
    assert bias == pytest.approx(2.5e-4) and std == pytest.approx(1e-4 / math.sqrt(2))
    assert fuse_bias([BiasEstimate(3e-4, 0.0, 'exact'), BiasEstimate(1e-3, 1e-5, 'b')]) == (3e-4, 0.0)
    assert fuse_bias([]) == (0.0, float('inf'))


def test_estimate_uses_the_calibrated_scale_and_the_standstill():
    standstill = StandstillBias()
    still_odometry(standstill, 60.0, 4e-4, 0.003, random.Random(3))
    prior = GyroCalibration(0.005, 0.0006, 0.0, 0.0, 60)
    correction = estimate_correction(GyroVisualFit(), standstill.estimate(), prior)
    assert correction.status == 'full', correction.describe()
    assert correction.scale == 0.005 and correction.scale_std == 0.0006
    assert correction.bias == pytest.approx(4e-4, abs=4 * correction.bias_std)
    assert 'windows' in correction.reason          # no visual odometry: standstill only


def test_insignificant_calibrated_scale_is_not_applied():
    standstill = StandstillBias()
    still_odometry(standstill, 60.0, 4e-4, 0.003, random.Random(4))
    prior = GyroCalibration(0.0003, 0.0006, 0.0, 0.0, 60)
    correction = estimate_correction(GyroVisualFit(), standstill.estimate(), prior)
    assert correction.status == 'bias' and correction.scale == 0.0
    assert 'calibrated scale' in correction.reason


def standstill_needed(recorded_seconds, noise, params=None):
    """s of standstill after a ``recorded_seconds`` recording without visual
    odometry before standstill_complete."""
    standstill = StandstillBias()
    rng, stamp, yaw = random.Random(5), recorded_seconds, 0.0
    while not standstill_complete(None, standstill, recorded_seconds, params):
        stamp, yaw = still_odometry(standstill, 0.02, 3e-4, noise, rng, stamp, yaw)
        assert stamp < recorded_seconds + 500.0, 'the standstill never ended'
    return stamp - recorded_seconds


def test_standstill_lasts_as_long_as_the_mission_needs():
    # bias std = 0.003 / sqrt(50 t) must reach 0.005 rad / recording: t = 50 (0.003 T / 0.005)^2 / 50^2
    short, longer = standstill_needed(30.0, 0.003), standstill_needed(80.0, 0.003)
    assert 5.0 <= short < 12.0 and 40.0 < longer < 75.0
    assert standstill_needed(300.0, 0.003) == pytest.approx(120.5, abs=0.1)   # the longest
    assert standstill_needed(300.0, 0.0) == pytest.approx(5.5, abs=0.1)       # noiseless: the shortest
    params = type('P', (), {'standstill_time': 0.0})()
    assert standstill_needed(300.0, 0.003, params) == 0.0
