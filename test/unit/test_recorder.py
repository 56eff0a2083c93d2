"""PathRecorder and the plain-Python recording loop: the paper's two sampling
rates switching along a straight/arc/straight path, the +-pi seam, distances;
the low-space warning against the recording's rate."""
import math
import os
import sys

import pytest

from blind_navigation.core.geometry import OdomState, distance, wrap_angle
from blind_navigation.core.recorder import (ASSUMED_BYTES_PER_MINUTE, LOW_SPACE_MINUTES, RATE_WINDOW,
                                           OdometryHistory, PathRecorder, SpaceWatch, free_bytes)
from blind_navigation.core.segment import SamplingSchedule

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..'))
from scripted_path import ASV, LSV, STRAIGHT_ARC_STRAIGHT, ScriptedPath  # noqa: E402
from unicycle import record_path  # noqa: E402

STRAIGHT_T, CURVED_T = 2.0, 1.0


def run(path, duration=None):
    schedule = SamplingSchedule(STRAIGHT_T, CURVED_T)
    return record_path(path.state, path.duration if duration is None else duration, schedule)


def chord_shortfall_bound(path, ticks):
    """Upper bound of (arc - chord) summed over the cycles: a cycle of arc length
    s that turns monotonically by theta has a chord of at least s * cos(theta / 2)."""
    total, t0, yaw0 = 0.0, 0.0, path.state(0.0).yaw
    for t, landmark in ticks:
        theta = abs(wrap_angle(landmark.psi - yaw0))
        total += path.length(t0, t) * (1.0 - math.cos(theta / 2.0))
        t0, yaw0 = t, landmark.psi
    return total


def test_rate_switches_straight_curve_straight():
    path = ScriptedPath(STRAIGHT_ARC_STRAIGHT)          # arc from 12 s to 28 s
    ticks = run(path)
    # Vision is lost at 40 s, one second into a straight cycle: the final landmark
    # covers that partial cycle; every other period is a configured one.
    (final_t, final), ticks = ticks[-1], ticks[:-1]
    assert (final_t, final.T) == (40.0, 1.0)
    periods = [landmark.T for _, landmark in ticks]
    assert set(periods) == {STRAIGHT_T, CURVED_T}
    # Straight before the arc, curved on it, straight again after it, in that order.
    runs = [periods[0]]
    for period in periods[1:]:
        if period != runs[-1]:
            runs.append(period)
    assert runs == [STRAIGHT_T, CURVED_T, STRAIGHT_T]
    arc_start, arc_end = 12.0, 28.0
    for t, landmark in ticks:
        if landmark.T == CURVED_T:
            # A curved cycle ends on the arc, or one curved cycle after it (the
            # switch takes effect at the next cycle).
            assert arc_start < t <= arc_end + CURVED_T, (t, landmark)
        if t <= arc_start:
            assert landmark.T == STRAIGHT_T, (t, landmark)
    # Four yaws need three changes: the curve is seen at most 3 straight cycles into the arc;
    # after that every cycle on the arc is curved.
    detected = arc_start + 3 * STRAIGHT_T
    on_arc = [landmark.T for t, landmark in ticks if detected + CURVED_T <= t <= arc_end]
    assert on_arc and all(T == CURVED_T for T in on_arc)
    # Ticks follow their periods exactly.
    times = [0.0] + [t for t, _ in ticks]
    for (t0, t1), (_, landmark) in zip(zip(times, times[1:]), ticks):
        assert t1 - t0 == pytest.approx(landmark.T)


@pytest.mark.parametrize('turn', [ASV, -ASV])
def test_turn_across_the_pi_seam_stays_curved(turn):
    # Start heading just short of the seam and turn through it (left: +pi -> -pi).
    yaw0 = math.pi - 1.0 if turn > 0 else -math.pi + 1.0     # seam ~10 s into the arc
    path = ScriptedPath(((6.0, LSV, 0.0), (14.0, LSV, turn), (6.0, LSV, 0.0)), yaw=yaw0)
    ticks = run(path)
    psis = [landmark.psi for _, landmark in ticks]
    assert all(-math.pi <= psi < math.pi for psi in psis)
    assert max(psis) > 2.5 and min(psis) < -2.5            # the yaw did wrap
    seam = [t for (_, a), (t, b) in zip(ticks, ticks[1:]) if abs(b.psi - a.psi) > math.pi]
    assert len(seam) == 1
    # Once the curve is detected, the wrap does not interrupt it: curved until the arc ends.
    curved = [t for t, landmark in ticks if landmark.T == CURVED_T]
    assert curved and curved[0] < seam[0] < curved[-1]
    assert all(landmark.T == CURVED_T for t, landmark in ticks if curved[0] <= t <= 20.0)
    # psi is the odometry yaw at the tick.
    for t, landmark in ticks:
        assert landmark.psi == pytest.approx(path.state(t).yaw)


def test_distances_sum_to_the_odometry_path_length():
    path = ScriptedPath(STRAIGHT_ARC_STRAIGHT)
    ticks = run(path, duration=path.duration - 0.5)      # vision lost mid-cycle
    total = sum(landmark.d for _, landmark in ticks)
    # d is the chord between landmark positions: exactly the chord sum ...
    points = [path.state(0.0)] + [path.state(t) for t, _ in ticks]
    chords = sum(distance(a.x, a.y, b.x, b.y) for a, b in zip(points, points[1:]))
    assert total == pytest.approx(chords, rel=1e-12)
    # ... which is the odometry path length less at most the chord/arc shortfall on the arc.
    length = path.length(0.0, path.duration - 0.5)
    shortfall = chord_shortfall_bound(path, ticks)
    assert shortfall > 0.0                       # the path does curve
    assert length - shortfall <= total <= length + 1e-12
    # The final landmark covers the partial cycle up to vision loss.
    last_t, last = ticks[-1]
    assert last_t == path.duration - 0.5 and 0.0 < last.T < STRAIGHT_T
    # v and w are the odometry twist at the tick.
    for t, landmark in ticks:
        state = path.state(t)
        assert (landmark.v, landmark.w) == (state.v, state.w)


def test_first_distance_counts_from_where_recording_started():
    recorder = PathRecorder()
    recorder.start(OdomState(1.0, 2.0, 0.0, 0.0, 0.0, 0.0))
    recorder.start(OdomState(9.0, 9.0, 0.0, 0.0, 0.0, 1.0))      # ignored: already started
    first = recorder.take(OdomState(4.0, 6.0, 0.3, 0.1, 0.0, 8.0), 0.3, 8.0)
    second = recorder.take(OdomState(4.0, 7.0, 0.3, 0.1, 0.0, 10.0), 0.3, 2.0)
    assert (first.d, second.d) == (5.0, 1.0)
    assert recorder.count == 2 and recorder.total_distance == 6.0


def test_without_start_the_first_landmark_starts_at_itself():
    recorder = PathRecorder()
    assert recorder.take(OdomState(3.0, 3.0, 0.0, 0.0, 0.0, 0.0), 0.0, 1.0).d == 0.0


def test_yaw_is_stored_wrapped():
    recorder = PathRecorder()
    landmark = recorder.take(OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), 3 * math.pi / 2, 1.0)
    assert landmark.psi == pytest.approx(-math.pi / 2)


@pytest.mark.parametrize('v, yaw, period, field', [
    (0.1, 0.0, 0.0, 'T'), (0.1, 0.0, -1.0, 'T'), (5.0, 0.0, 1.0, 'v'),
    (float('nan'), 0.0, 1.0, 'v'), (0.1, float('nan'), 1.0, 'psi')])
def test_bad_tick_raises_and_keeps_the_previous_position(v, yaw, period, field):
    recorder = PathRecorder()
    recorder.start(OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match=field):
        recorder.take(OdomState(1.0, 0.0, 0.0, v, 0.0, 1.0), yaw, period)
    assert recorder.count == 0
    assert recorder.take(OdomState(2.0, 0.0, 0.0, 0.1, 0.0, 4.0), 0.0, 4.0).d == 2.0


def test_odometry_history_reads_the_state_at_a_stamp():
    history = OdometryHistory(span=1.0)
    assert history.at(5.0) is None and history.latest is None
    states = [OdomState(0.1 * i, 0.0, 0.0, 0.1, 0.0, 10.0 + 0.02 * i) for i in range(100)]
    for state in states:
        history.append(state)
    assert history.latest == states[-1]
    assert history.at(11.0) == states[50]                 # stamped exactly at the tick
    assert history.at(11.01) == states[50]                # the latest not after the tick
    assert history.at(99.0) == states[-1]                 # newer than all: the latest
    assert history.at(0.0) == states[49]                  # older than kept (1 s): the oldest kept
    assert history.after(11.95) == states[98:]            # the states stamped after a stamp
    assert history.after(11.98) == [] and history.after(0.0) == states[49:]
    history.append(OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 1.0))   # sim time reset
    assert history.at(11.0).stamp == 1.0
    history.clear()
    assert history.latest is None and history.after(0.0) == []
    with pytest.raises(ValueError):
        OdometryHistory(span=0.0)


# --- the low-space warning ---------------------------------------------------------------

def test_the_rate_is_assumed_until_the_recording_measured_it():
    watch = SpaceWatch('/d', free=lambda directory: 1000)
    assumed = 'at %.0f bytes/min' % ASSUMED_BYTES_PER_MINUTE
    assert assumed in watch.update(0.0, 100, 1)[0]                    # from the first landmark
    assert assumed in watch.update(RATE_WINDOW - 1, 5100, 2)[0]       # not measured yet
    assert 'at 2100 bytes/min' in watch.update(RATE_WINDOW, 2200, 3)[0]
    assert 'at 2100 bytes/min' in watch.update(2 * RATE_WINDOW, 4300, 4)[0]


def test_space_warning_says_how_many_minutes_the_free_space_holds():
    free = [LOW_SPACE_MINUTES * ASSUMED_BYTES_PER_MINUTE]
    watch = SpaceWatch('/d', free=lambda directory: free[0])
    assert watch.update(0.0, 0, 0) == ('', False)
    free[0] = 2400
    warning, appeared = watch.update(1.0, 0, 0)
    assert appeared and warning.startswith('LOW SPACE: 2400 bytes free on /d hold 0.5 min of '
                                           'recording at 4800 bytes/min (less than 10 min)')
    free[0] = 0
    assert watch.update(2.0, 0, 0)[0].startswith('LOW SPACE: 0 bytes free')


def test_space_watch_warns_early_and_once_then_measures():
    free = [5 * ASSUMED_BYTES_PER_MINUTE]
    watch = SpaceWatch('/d', free=lambda directory: free[0])
    warning, appeared = watch.update(0.0, 200, 0)        # at start, before any landmark: assumed
    assert appeared and 'hold 5.0 min of recording at %.0f bytes/min' % ASSUMED_BYTES_PER_MINUTE in warning
    assert watch.update(1.0, 270, 1) == (warning, False)     # said once
    # measured from the first landmark: 70 bytes every 2 s = 2100 bytes/min: 11.7 min, enough
    assert watch.update(1.0 + RATE_WINDOW, 270 + 70 * 30, 31) == ('', False)
    free[0] = 1000
    assert watch.update(2.0 + RATE_WINDOW, 270 + 70 * 31, 32)[1]
    assert free_bytes(os.path.dirname(__file__)) > 0 and free_bytes('/nonexistent/dir') is None
