"""The low-battery watch (core/battery.py), the fake's battery (sim/battery.py) and the
mission's return on a low battery, played by the harness on core/mission.Mission."""
import math

import pytest

from blind_navigation.core.battery import BATTERY_DEFAULTS, BatteryWatch, reading_problem
from blind_navigation.sim.battery import FULL, SimBattery
from blind_navigation.sim.kobuki import MAX_V
from blind_navigation.sim.mission import load_mission
from test_mission_harness import _play, _speed, _states

THRESHOLD = 13.2
HOLD, WINDOW = BATTERY_DEFAULTS['battery_hold'], BATTERY_DEFAULTS['battery_window']
RATE = 10.0     # Hz, the fake's mobile_base/sensors/core


def feed(watch, readings, start=0.0, rate=RATE):
    """Each reading at ``rate``; [(time, reason)] after each."""
    return [(start + k / rate, watch.update(start + k / rate, volts)) for k, volts in enumerate(readings)]


def first_low(trace):
    return next((t for t, reason in trace if reason), None)


def test_off_never_low():
    watch = BatteryWatch(0.0)
    assert watch.threshold == 0
    assert first_low(feed(watch, [11.0] * 100)) is None


def test_below_for_the_hold_and_the_window_is_low_naming_voltage_and_threshold():
    watch = BatteryWatch(THRESHOLD)
    trace = feed(watch, [13.5] * 10 + [13.0] * 50)
    # the median is below once 3 of the 5 readings are (t 1.2 s), then held HOLD s
    assert first_low(trace) == pytest.approx(1.2 + HOLD)
    assert watch.low and watch.reason == 'battery low: 13.0 V below battery_low 13.2 V for 2.0 s'


def test_one_low_reading_or_a_short_dip_never_decides():
    watch = BatteryWatch(THRESHOLD)
    assert first_low(feed(watch, [13.5] * 10 + [11.0] + [13.5] * 50)) is None      # one reading
    dip = [13.0] * int(HOLD * RATE - 5)           # below for less than the hold
    assert first_low(feed(watch, ([13.5] * 10 + dip) * 5, start=10.0)) is None


def test_at_a_slow_rate_the_window_counts_readings_not_seconds():
    watch = BatteryWatch(THRESHOLD)
    trace = feed(watch, [13.0] * 10, rate=1.0)      # 1 Hz: the hold passes before 5 medians
    assert first_low(trace) == pytest.approx(WINDOW - 1 + WINDOW - 1)


@pytest.mark.parametrize('above, share', [(0.1, 0.05), (0.05, 0.12)])
def test_noisy_readings_near_the_threshold_never_trigger(above, share):
    """A battery 0.1 or 0.05 V above the threshold, read with 0.1 V std noise and the Kobuki's
    0.1 V rounding: one reading in 15 (in 6) is below; ten minutes at 10 Hz never trigger."""
    battery = SimBattery(THRESHOLD + above, drain=0.0, noise=0.1, seed=3)
    readings = [battery.reading() / 10.0 for _ in range(6000)]
    below = sum(volts < THRESHOLD for volts in readings)
    assert below > share * len(readings), below     # the noise does reach below the threshold
    assert first_low(feed(BatteryWatch(THRESHOLD), readings)) is None


def test_a_noisy_battery_below_the_threshold_triggers_within_seconds():
    battery = SimBattery(THRESHOLD - 0.2, drain=0.0, noise=0.1, seed=4)
    trace = feed(BatteryWatch(THRESHOLD), [battery.reading() / 10.0 for _ in range(300)])
    assert first_low(trace) is not None and first_low(trace) < 2 * HOLD


@pytest.mark.parametrize('bad, why', [(float('nan'), 'not a number'), (float('inf'), 'not a number'),
                                      ('13', 'not a number'), (0.0, 'no reading'),
                                      (25.5, 'outside'), (3.0, 'outside')])
def test_bad_readings_are_ignored_with_a_reason(bad, why):
    assert why in reading_problem(bad)
    watch = BatteryWatch(THRESHOLD)
    trace = feed(watch, [13.5] * 10 + [bad] * 50 + [13.5] * 10)
    assert first_low(trace) is None and watch.ignored == 50 and why in watch.problem
    assert reading_problem(13.0) is None and reading_problem(None)


def test_bad_readings_between_low_ones_neither_count_nor_break_the_run():
    watch = BatteryWatch(THRESHOLD)
    trace = feed(watch, [13.0, 0.0] * 40)
    assert first_low(trace) == pytest.approx(2 * (WINDOW - 1) / RATE + HOLD)


def test_readings_that_stop_drop_the_evidence():
    watch = BatteryWatch(THRESHOLD)
    feed(watch, [13.0] * 15)                        # 1.4 s below, not yet the hold
    trace = feed(watch, [13.0] * 15, start=10.0)    # 8.6 s later: the evidence is stale
    assert first_low(trace) is None


def test_low_holds_until_the_median_rises_the_hysteresis_above():
    watch = BatteryWatch(THRESHOLD)
    feed(watch, [13.0] * 40)
    assert watch.low
    feed(watch, [13.3] * 40, start=4.0)         # above the threshold, within the hysteresis
    assert watch.low and watch.reason
    feed(watch, [13.4] * 10, start=8.0)         # threshold + 0.2 V
    assert not watch.low and watch.reason is None


def test_the_fake_battery_drains_with_time_and_faster_with_motion():
    standing, driving = SimBattery(FULL, drain=36.0), SimBattery(FULL, drain=36.0, motion=2.0)
    for _ in range(1000):       # 10 s
        standing.step(0.01)
        driving.step(0.01, MAX_V, 0.0)
    assert FULL - standing.volts == pytest.approx(0.1)
    assert FULL - driving.volts == pytest.approx(0.3)
    assert standing.reading() == 164 and standing.charger == 0


def test_the_fake_battery_refuses_nonsense():
    with pytest.raises(ValueError):
        SimBattery(30.0)
    with pytest.raises(ValueError):
        SimBattery(FULL, noise=-1.0)


# --- the mission (harness) ----------------------------------------------------------------
def test_a_draining_battery_brings_the_robot_home():
    """table6_test1 (30 s of driving): the battery crosses 13.2 V while the robot stands
    recording after it; rotating names the voltage; home within 0.1 m, still."""
    duration = load_mission('table6_test1').duration
    # 13.5 V at 36 V/h (0.01 V/s standing, up to 1.3 x while driving at 0.1 m/s): below 13.2 V
    # after about 28 s, read below from 13.15 V (rounding): after the drive and its settle
    battery = dict(volts=13.5, drain=36.0)
    played = _play(settle_time=60.0, battery=battery, battery_low=THRESHOLD)
    assert played.result.status == 'home', played.result.reason
    assert _states(played) == ['idle', 'recording', 'rotating', 'returning', 'home']
    (at, _, _, reason), = [t for t in played.mission.transitions if t[2] == 'rotating']
    assert reason.startswith('battery low: 13.1 V below battery_low 13.2 V'), reason
    assert duration < at < duration + 30.0
    assert played.result.position_error < 0.1 and _speed(played) < 1e-3


def test_a_battery_above_the_threshold_changes_nothing():
    played = _play(battery=dict(volts=13.5, drain=0.0, noise=0.1), battery_low=THRESHOLD)
    assert played.result.status == 'home', played.result.reason
    reasons = [t[3] for t in played.mission.transitions if t[2] == 'rotating']
    assert reasons == ['vision lost']
    assert not math.isnan(played.result.position_error)
