"""Gyro heading correction (core/gyro_fit.py, core/heading_correction.py): the estimator recovers a
known bias and scale from synthetic gyro + visual-odometry yaw, refuses what the
data cannot determine, and the corrected frame / corrected landmarks are right."""
import math
import random

import pytest

from blind_navigation.core.geometry import OdomState, wrap_angle
from blind_navigation.core.gyro_calibration import GyroCalibration
from blind_navigation.core.gyro_fit import GyroVisualFit, WindowRows
from blind_navigation.core.heading_correction import (CorrectedOdometry, GyroCorrection,
                                                       correct_landmarks, estimate_correction,
                                                       no_correction)
from blind_navigation.core.landmark import Landmark
from blind_navigation.sim.harness import run_mission, simulate_gyro_calibration
from blind_navigation.sim.kobuki import SimulatedKobuki, load_profile

ODOM_DT = 0.02
VO_DT = 1.0 / 30.0


def feed(calibrator, turn_rate, duration, bias, scale, vo_noise=1e-4, lost=lambda t: False, seed=0):
    """Feed ``duration`` s of a robot turning at ``turn_rate(t)``: gyro yaw at 50 Hz with
    ``bias``/``scale``, visual-odometry yaw (random-walk error) at 30 Hz, None while ``lost(t)``."""
    rng = random.Random(seed)
    true_yaw = gyro_yaw = vo_error = 0.0
    t, next_vo = 0.0, 0.0
    steps = int(round(duration / ODOM_DT))
    for _ in range(steps):
        rate = turn_rate(t)
        t += ODOM_DT
        true_yaw += rate * ODOM_DT
        gyro_yaw += ((1.0 + scale) * rate + bias) * ODOM_DT
        calibrator.add_odometry(t, wrap_angle(gyro_yaw))
        while next_vo <= t + 1e-9:
            vo_error += rng.gauss(0.0, vo_noise)
            calibrator.add_visual(next_vo, None if lost(next_vo) else
                                  wrap_angle(true_yaw - rate * (t - next_vo) + vo_error))
            next_vo += VO_DT
    return estimate_correction(calibrator)


def weaving(t):
    return 0.4 * math.sin(2.0 * math.pi * t / 20.0)


def test_recovers_the_bias_and_takes_the_calibrated_scale():
    prior = GyroCalibration(0.005, 0.0006, 0.0, 0.0, 60)
    calibrator = GyroVisualFit()
    feed(calibrator, weaving, 300.0, bias=4e-4, scale=0.005)
    correction = estimate_correction(calibrator, scale_prior=prior)
    assert correction.status == 'full', correction.describe()
    assert correction.bias == pytest.approx(4e-4, abs=max(4 * correction.bias_std, 1e-5))
    assert correction.scale == 0.005 and correction.bias_std < 5e-5


def test_a_mission_does_not_set_the_scale_by_itself():
    # the weaving turns would fit the scale; without a calibration it is not corrected
    correction = feed(GyroVisualFit(), weaving, 300.0, bias=4e-4, scale=0.005)
    assert correction.status == 'bias' and correction.scale == 0.0
    assert 'no gyro calibration' in correction.reason


def test_bias_only_when_the_path_does_not_turn():
    correction = feed(GyroVisualFit(), lambda t: 0.0, 120.0, bias=-3e-4, scale=0.005)
    assert correction.status == 'bias', correction.describe()
    assert correction.scale == 0.0
    assert 'scale' in correction.reason
    assert correction.bias == pytest.approx(-3e-4, abs=4 * correction.bias_std)


def test_no_visual_odometry_no_correction():
    correction = feed(GyroVisualFit(), weaving, 100.0, bias=4e-4, scale=0.005, lost=lambda t: True)
    assert correction.status == 'none' and correction.windows == 0
    assert correction.bias == 0.0 and correction.scale == 0.0
    assert estimate_correction(GyroVisualFit(), ).status == 'none'


def test_too_little_data_no_correction():
    correction = feed(GyroVisualFit(), weaving, 15.0, bias=4e-4, scale=0.0)
    assert correction.status == 'none'
    assert 'windows' in correction.reason


def test_absurd_bias_rejected():
    correction = feed(GyroVisualFit(), weaving, 100.0, bias=0.05, scale=0.0)
    assert correction.status == 'none'
    assert 'beyond' in correction.reason


def test_lost_stretches_break_windows_and_a_jump_is_dropped():
    # vision lost in every third 10 s stretch: no window may span a lost message
    lost = lambda t: int(t // 10.0) % 3 == 2  # noqa: E731
    calibrator = GyroVisualFit()
    feed(calibrator, weaving, 300.0, bias=2e-4, scale=0.004, lost=lost)
    prior = GyroCalibration(0.004, 0.0005, 0.0, 0.0, 60)
    correction = estimate_correction(calibrator, scale_prior=prior)
    assert correction.status == 'full'
    # 200 s of the 300 s are seen, in 10 s stretches: at most 5 windows of 2 s each
    assert 80 <= correction.windows <= 100
    assert all(dt < 2.0 + 2 * VO_DT for _, _, dt in calibrator.rows)
    assert correction.bias == pytest.approx(2e-4, abs=max(4 * correction.bias_std, 1e-5))
    # one visual-odometry jump of 0.3 rad (a relocalisation) is an outlier, not a bias
    rows, calibrator.rows = list(calibrator.rows), WindowRows()
    for index, (gyro, vo, dt) in enumerate(rows):
        calibrator.rows.append((gyro, vo + (0.3 if index == 5 else 0.0), dt))
    jumped = estimate_correction(calibrator, scale_prior=prior)
    assert jumped.windows == correction.windows - 1
    assert jumped.bias == pytest.approx(correction.bias, abs=2 * correction.bias_std)


def test_windows_are_packed_and_bounded_keeping_the_newest():
    rows = WindowRows(capacity=6)
    for i in range(8):
        rows.append((i, -i, 2.0))
    # at the 7th the oldest 3 went; the 8th fits
    assert len(rows) == 5
    assert list(rows) == [(i, -i, 2.0) for i in range(3, 8)]
    with pytest.raises(ValueError):
        WindowRows(capacity=1)


def test_a_long_recording_keeps_a_bounded_number_of_windows():
    fit = GyroVisualFit()
    fit.rows = WindowRows(capacity=50)
    correction = feed(fit, weaving, 300.0, bias=4e-4, scale=0.005)   # about 150 windows
    assert 25 <= len(fit.rows) <= 50
    assert correction.bias == pytest.approx(4e-4, abs=max(4 * correction.bias_std, 1e-5))


def test_bad_params_refused():
    with pytest.raises(ValueError, match='window'):
        GyroVisualFit(type('P', (), {'window': 0.0})())


def unicycle_odometry(bias, scale, seconds=60.0):
    """(truth, raw odometry) of a weaving unicycle whose odometry heading is a biased gyro."""
    x = y = yaw = gyro = ox = oy = 0.0
    truth, raw = [], [OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)]
    for k in range(1, int(seconds / ODOM_DT) + 1):
        v, w = 0.1, weaving(k * ODOM_DT)
        x += v * ODOM_DT * math.cos(yaw + w * ODOM_DT / 2)
        y += v * ODOM_DT * math.sin(yaw + w * ODOM_DT / 2)
        previous = gyro
        yaw += w * ODOM_DT
        gyro += ((1 + scale) * w + bias) * ODOM_DT
        ox += v * ODOM_DT * math.cos((previous + gyro) / 2)
        oy += v * ODOM_DT * math.sin((previous + gyro) / 2)
        truth.append((x, y, yaw))
        raw.append(OdomState(ox, oy, wrap_angle(gyro), v, (1 + scale) * w + bias, k * ODOM_DT))
    return truth, raw


def test_corrected_odometry_follows_the_truth():
    truth, raw = unicycle_odometry(bias=5e-3, scale=0.02)
    corrector = CorrectedOdometry(GyroCorrection(5e-3, 0.02, 0, 0, 10, 'full', ''))
    states = [corrector.update(state) for state in raw]
    x, y, yaw = truth[-1]
    assert states[-1].yaw == pytest.approx(wrap_angle(yaw), abs=1e-6)
    assert math.hypot(states[-1].x - x, states[-1].y - y) < 1e-3
    assert math.hypot(raw[-1].x - x, raw[-1].y - y) > 0.3   # what the raw odometry got wrong
    assert states[-1].w == pytest.approx(weaving(60.0), abs=1e-9)


def test_identity_correction_changes_nothing():
    _, raw = unicycle_odometry(bias=5e-3, scale=0.02, seconds=10.0)
    corrector = CorrectedOdometry(no_correction('off'))
    for state in raw:
        out = corrector.update(state)
        assert out.yaw == pytest.approx(state.yaw, abs=1e-9)
        assert (out.x, out.y) == pytest.approx((state.x, state.y), abs=1e-9)
    landmarks = [Landmark(0.1, 0.2, 0.1, 1.0, 0.5), Landmark(0.1, 0.0, 0.2, 2.0, 0.6)]
    assert correct_landmarks(landmarks, no_correction('off')) == landmarks


def test_landmarks_get_the_correction_of_their_time():
    bias, scale = 1e-3, 0.01
    correction = GyroCorrection(bias, scale, 0, 0, 10, 'full', '')
    # true headings 0.0 -> 0.5 -> 0.5 -> 3.0 (crossing pi in raw yaw), T = 1, 2, 1, 2 s
    periods = [1.0, 2.0, 1.0, 2.0]
    true_psi = [0.0, 0.5, 0.5, 3.0]
    times = [sum(periods[:k + 1]) for k in range(4)]
    raw_psi = [wrap_angle((1 + scale) * p + bias * t) for p, t in zip(true_psi, times)]
    landmarks = [Landmark(0.1, (1 + scale) * 0.2 + bias, 0.1, T, psi) for T, psi in zip(periods, raw_psi)]
    corrected = correct_landmarks(landmarks, correction)
    # the corrected frame equals the raw one at the last landmark: compare differences
    for lm, p in zip(corrected, true_psi):
        assert wrap_angle(lm.psi - corrected[-1].psi) == pytest.approx(wrap_angle(p - true_psi[-1]), abs=1e-9)
        assert lm.w == pytest.approx(0.2, abs=1e-12)
    assert corrected[-1].psi == pytest.approx(landmarks[-1].psi)


def test_landmarks_recorded_after_the_reference_do_not_turn_the_route():
    # issue 29: over ROS the recording goes on while the bias is measured standing still
    # after the loss (the reference); the landmarks' times count from the reference, not
    # from the last landmark, else every heading is off by bias x the standstill
    bias, scale, standstill = 3e-4, 0.005, 65.0
    correction = GyroCorrection(bias, scale, 0, 0, 10, 'full', '')
    periods = [2.0] * 10 + [5.0] * 13            # 20 s driving north-east, then 65 s standing
    times = [sum(periods[:k + 1]) for k in range(len(periods))]
    raw_psi = [wrap_angle((1 + scale) * 0.8 + bias * t) for t in times]
    landmarks = [Landmark(0.2 if k < 10 else 0.0, bias, 0.4 if k < 10 else 0.0, T, psi)
                 for k, (T, psi) in enumerate(zip(periods, raw_psi))]
    reference_yaw = raw_psi[9]                   # the raw yaw where vision was lost
    corrected = correct_landmarks(landmarks, correction, reference_yaw, recorded_after=standstill)
    for lm in corrected:                         # the robot never turned: one heading throughout
        assert lm.psi == pytest.approx(reference_yaw, abs=1e-9)
    stale = correct_landmarks(landmarks, correction, reference_yaw)
    assert stale[0].psi - reference_yaw == pytest.approx(bias * standstill / (1 + scale), abs=1e-9)


def test_insignificant_bias_is_not_applied():
    correction = feed(GyroVisualFit(), weaving, 100.0, bias=0.0, scale=0.0, vo_noise=1e-3)
    assert correction.status == 'none'
    assert 'not significant' in correction.reason


def test_harness_estimates_the_fake_gyro_bias_and_uses_the_calibration():
    """paper profile, seed 2: the fake Kobuki's gyro bias is 5.3e-4 rad/s; the
    calibration is made on another seed (another power-up, same gyro scale)."""
    true_bias = SimulatedKobuki(load_profile('paper'), seed=2)._gyro_bias
    calibration = simulate_gyro_calibration('paper', seed=102)
    on = run_mission('table6_test3', 'paper', 'closed_loop', 2, gyro_calibration=calibration)
    off = run_mission('table6_test3', 'paper', 'closed_loop', 2, heading_correction=False)
    assert off.heading_correction.status == 'none'
    assert on.heading_correction.status == 'full', on.heading_correction.describe()
    assert on.heading_correction.scale == calibration.scale
    assert on.heading_correction.bias == pytest.approx(true_bias, abs=3 * on.heading_correction.bias_std)
    assert on.forward_path == off.forward_path       # calibration only watches the recording
    assert on.status == off.status == 'home'
    # the standstill went on until bias std x the 65 s recording <= the 0.005 rad budget
    assert on.heading_correction.bias_std * 65.0 < 0.0055


def test_harness_on_ideal_stays_home_without_correction():
    on = run_mission('table6_test1', 'ideal', 'closed_loop', 0)
    assert on.heading_correction.status == 'none'   # the standstill shows no bias at all
    assert on.status == 'home' and on.position_error < 0.05
