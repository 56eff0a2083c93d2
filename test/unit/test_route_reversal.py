"""A short reversed stretch between two reversal events (core/motion_events.py,
core/period_model.py, core/route.py): recorded by the mission's recording with event
sampling on a ground-truth path whose speed ramps through zero (the base's acceleration
limit), both ends of the stretch are reversal samples; each reads the new direction,
so the route lays the stretch backward and runs back through the true path. An event
just after a tick is read at its own stamp."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core.geometry import OdomState
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.mission_record import MissionRecording
from blind_navigation.core.period_model import period_shape
from blind_navigation.core.route import build_route

DT = 0.02
ACCEL = 0.6          # m/s^2, kobuki_driver's acceleration limiter
CONFIG = SimpleNamespace(straight_period=2.0, curved_period=1.0, deadband=0.01,
                         event_sampling=True, heading_correction=False)


class Store(object):
    def append(self, landmark):
        return 'landmark'


def ground_truth(legs, w=0.0):
    """50 Hz OdomStates of a base ramping at ACCEL to each leg's speed (m/s) over the
    leg's seconds, turning at ``w`` rad/s."""
    x = y = yaw = v = t = 0.0
    states = [OdomState(x, y, yaw, v, 0.0, t)]
    for target, seconds in legs:
        for _ in range(int(round(seconds / DT))):
            v += max(-ACCEL * DT, min(ACCEL * DT, target - v))
            x, y, yaw, t = x + v * DT * math.cos(yaw), y + v * DT * math.sin(yaw), yaw + w * DT, t + DT
            states.append(OdomState(x, y, yaw, v, w, t))
    return states


def recorded(states):
    recording = MissionRecording(Store(), CONFIG)
    recording.begin(states[0])
    for state in states[1:]:
        recording.step(state, state.stamp)
    recording.end(states[-1], states[-1].stamp)
    return recording.landmarks


def reversing(seconds):
    """Forward, back for ``seconds`` (crossing zero at 4.7 s, between the 2 s ticks at 4 and
    6 s), forward again."""
    return [(0.3, 4.2), (-0.15, seconds), (0.3, 3.0)]


REVERSED_STRETCH = reversing(1.2)         # back 0.10 m from 4.7 to 5.65 s


def test_each_end_of_the_reversed_stretch_reads_its_new_direction():
    landmarks = recorded(ground_truth(REVERSED_STRETCH))
    small = [k for k, lm in enumerate(landmarks) if k and abs(lm.v) < 0.05]
    assert len(small) == 2, landmarks       # the two reversal samples, nothing else slow
    first, second = small
    assert second == first + 1              # no tick between: one period holds the stretch
    assert landmarks[first].v < 0 < landmarks[second].v
    # the stretch's chord points backward (the robot faced about +x the whole time)
    a, b = landmarks[first], landmarks[second]
    direction = period_shape(a, b, b.d, 8)[0]
    assert math.cos(direction - a.psi) < -0.9


def test_an_event_just_after_a_tick_is_read_where_it_happened():
    # setting off at 0.02 s: taken with the tick at 2 s, 2.5 s later (the events' latency);
    # the recording's odometry history reaches back that far (it kept 2 s: read at 0.5 s)
    first = recorded(ground_truth(REVERSED_STRETCH))[0]
    assert first.T == pytest.approx(0.02) and first.v == pytest.approx(ACCEL * 0.02)


def test_the_route_runs_back_through_a_reversed_stretch():
    states = ground_truth(REVERSED_STRETCH)
    landmarks = recorded(states)
    end = states[-1]
    route = build_route(landmarks, (end.x, end.y))
    assert math.hypot(route.x[-1], route.y[-1]) < 0.01       # the true start (was 0.21 m off)
    worst = max(min(math.hypot(x - s.x, y - s.y) for s in states) for x, y in zip(route.x, route.y))
    assert worst < 0.01, worst


@pytest.mark.parametrize('seconds', [0.9, 1.4])
def test_longer_and_shorter_reversed_stretches_end_on_the_start(seconds):
    states = ground_truth(reversing(seconds))
    end = states[-1]
    route = build_route(recorded(states), (end.x, end.y))
    assert math.hypot(route.x[-1], route.y[-1]) < 0.01


def test_a_period_from_standing_into_reversing_goes_its_ends_way():
    # the start reads a standing base (+0.004 m/s, noise), the end reverses at 0.145 m/s
    # and d / T exceeds the ends' mean: the speed made up goes backward the whole period
    stood = Landmark(0.004, 0.0, 0.046, 1.0, 0.0)
    backing = Landmark(-0.145, 0.0, 0.2, 1.0, 0.0)
    direction, points, _, _ = period_shape(stood, backing, backing.d, 8)
    assert math.cos(direction) < -0.99
    xs = [0.0] + [x for x, _ in points]
    assert all(later <= earlier + 1e-9 for earlier, later in zip(xs, xs[1:])), xs


def test_a_period_ended_by_a_reversal_goes_the_start_way_to_its_end():
    # backing up 2 cm while turning in place at 1 rad/s (the kinematic base in a loop path's
    # corner), the end the first state reading forward: the chord is the backward motion's,
    # not a half-back, half-forward one turned a quarter away
    turn, seconds = 1.0, 0.98
    x = y = 0.0
    for k in range(49):
        heading = turn * (k + 0.5) * DT
        x, y = x - 0.017 * DT * math.cos(heading), y - 0.017 * DT * math.sin(heading)
    start = Landmark(-0.017, turn, 0.0, 1.0, 0.0)
    end = Landmark(0.013, turn, math.hypot(x, y), seconds, turn * seconds)
    direction = period_shape(start, end, end.d, 8)[0]
    assert abs(math.remainder(direction - math.atan2(y, x), 2 * math.pi)) < 0.15   # linear to b.v: 0.64


def test_a_one_step_period_goes_its_end_way():
    # dense odometry (one 20 ms step): the end's v is the step's own speed
    moving = Landmark(0.008, 0.0, 0.0, 1.0, 0.0)
    step = Landmark(-0.012, 0.0, 0.012 * DT, DT, 0.0)
    assert math.cos(period_shape(moving, step, step.d, 2)[0]) < -0.99
