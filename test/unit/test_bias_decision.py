"""Whether the measured gyro bias is applied (core/heading_correction.estimate_correction,
issue 29): a bias measured standing still is applied even below ``significance`` standard
errors (leaving it out cost 2.2 % of the path over ROS); a visual-odometry one alone is not;
a standing lead before the operator starts does not change the return when the bias is known."""
import random

import pytest

from blind_navigation.core.geometry import OdomState, wrap_angle
from blind_navigation.core.gyro_bias import BiasEstimate, StandstillBias
from blind_navigation.core.gyro_fit import GyroVisualFit
from blind_navigation.core.heading_correction import estimate_correction
from blind_navigation.evaluation.standing_lead import lead_row, table
from blind_navigation.sim.harness import run_mission
from blind_navigation.sim.kobuki import load_profile

NOISE, RATE, SECONDS = 0.003, 50.0, 20.0     # the paper profile's gyro noise at 50 Hz, 20 s still


def standstill(bias, rng):
    """The StandstillBias estimate of ``SECONDS`` s standing still on a gyro with ``bias``."""
    measurement, yaw = StandstillBias(), 0.0
    for k in range(int(SECONDS * RATE) + 1):
        rate = bias + rng.gauss(0.0, NOISE)
        yaw += rate / RATE
        measurement.add_odometry(OdomState(0.0, 0.0, wrap_angle(yaw), 0.0, rate, k / RATE))
    return measurement.estimate()


def test_a_bias_measured_standing_still_is_applied_below_the_significance():
    # over ROS (issue 29): 6.2e-5 +- 5.3e-5 from the standstill was left out; 1.17 std
    correction = estimate_correction(GyroVisualFit(), BiasEstimate(6.2e-5, 5.3e-5, 'standstill 64 s'))
    assert correction.status == 'bias', correction.describe()
    assert correction.bias == 6.2e-5 and correction.bias_std == 5.3e-5
    exact_zero = estimate_correction(GyroVisualFit(), BiasEstimate(0.0, 0.0, 'standstill 5 s'))
    assert exact_zero.status == 'none' and 'not significant' in exact_zero.reason


@pytest.mark.parametrize('in_std', [0.5, 1.5, 3.0])
def test_the_applied_standstill_bias_is_within_its_std_of_the_truth(in_std):
    """Ground truth over 150 standstills: a bias of 0.5-3 std is always applied, off by
    about its std (leaving it out, as the significance test did below 1.41 std, is off
    by the whole bias)."""
    rng, sigma = random.Random(29), NOISE / (SECONDS * RATE) ** 0.5
    true_bias = in_std * sigma
    errors = []
    for _ in range(150):
        correction = estimate_correction(GyroVisualFit(), standstill(true_bias, rng))
        assert correction.status == 'bias', correction.describe()
        assert correction.bias_std == pytest.approx(sigma, rel=0.1)
        errors.append(correction.bias - true_bias)
    rms = (sum(e * e for e in errors) / len(errors)) ** 0.5
    assert 0.8 * sigma < rms < 1.2 * sigma, (rms, sigma)


def test_a_standing_lead_leaves_the_return_alone_when_the_bias_is_known():
    """A noiseless gyro with a bias: the standstill measures it exactly; 0 or 12 s standing
    before the operator starts: the same correction and the same true end of the return."""
    profile = dict(load_profile('paper'), gyro_noise_std=0.0)
    runs = [run_mission('table6_test3', profile, 'closed_loop', 2, floor=False, start_delay=lead)
            for lead in (0.0, 12.0)]
    for run in runs:
        assert run.status == 'home', run.reason
        assert run.heading_correction.status == 'bias' and run.heading_correction.bias_std < 1e-8
    assert runs[1].heading_correction.bias == pytest.approx(runs[0].heading_correction.bias, abs=1e-8)
    assert runs[1].position_error == pytest.approx(runs[0].position_error, abs=0.005)   # m


def test_the_lead_evaluation_reports_the_bias_against_the_robots():
    row = lead_row('reversing', 'reversing', 5001, 5.0, 'kinematic')
    assert row['status'] == 'home' and row['applied'] and row['standstill_s'] >= 5.0
    assert abs(row['bias'] - row['true_bias']) <= 3.0 * row['bias_std'], row
    assert 'bias left out' in table([row])
