"""The return's final approach (core/final_approach.py): played in the harness through
core/mission.Mission (the object the ROS layer drives) on a 2.4 m straight recorded at 0.4 m/s,
its final stop overshot by late commands (sim/harness.py's ``command_lag``, a loaded machine's
late control cycles); checked on ground truth. Then the approach's own rules."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core import outcome
from blind_navigation.core.back_travel import BACK_TRAVEL_DEFAULTS
from blind_navigation.core.allowance import ABORT, HOLD
from blind_navigation.core.final_approach import (APPROACH, APPROACH_DEFAULTS, FinalApproach,
                                                  ReturnEnding)
from blind_navigation.core.mission_drive import ZERO
from blind_navigation.core.mission_state import ABORTED
from blind_navigation.core.geometry import OdomState
from blind_navigation.sim import harness
from blind_navigation.sim.kobuki import load_profile
from blind_navigation.sim.mission import Mission as Script

FAST_STRAIGHT = Script([(0.0, 0.0, 1.0), (0.4, 0.0, 6.0)], name='fast_straight')
#: s of command lag that makes this return's final stop overshoot (seed 0: 0.09 m past on the
#: kinematic base, 0.14 m on MuJoCo); a stop commanded reaches the robot this late
LAG = 0.5
TOLERANCE = APPROACH_DEFAULTS['approach_tolerance']


def past_end(route, odom):
    """m the robot at ``odom`` is past ``route``'s end along its last segment (negative: short)."""
    heading = route.direction(route.vertices - 2)
    return (odom.x - route.x[-1]) * math.cos(heading) + (odom.y - route.y[-1]) * math.sin(heading)


def _play(approach=True, lag=LAG, events=(), mission=FAST_STRAIGHT, **settings):
    settings = dict(floor=False, command_lag=lag, events=events, **settings)
    params = harness.default_params(harness._settings(settings), load_profile('paper'))
    if not approach:
        params.approach_tolerance = float('inf')
    return harness.play(mission, 'paper', 'closed_loop', 0, params=params, **settings)


def _states(played):
    return [new for _, _, new, _ in played.mission.transitions]


def _moved_between(played, start, end):
    """m the robot moved (ground truth) between sim times ``start`` and ``end``."""
    run = played.run
    points = [p for p, t in zip(run.path, run.path_times) if start <= t <= end]
    return max([math.hypot(p[0] - points[0][0], p[1] - points[0][1]) for p in points] or [0.0])


@pytest.fixture(scope='module', params=['kinematic', 'mujoco'])
def overshoot(request):
    """(without the approach, with it): the same recording, seed and late commands, on each base."""
    if request.param == 'mujoco':
        pytest.importorskip('mujoco')
    return _play(approach=False, base=request.param), _play(base=request.param)


def test_an_overshot_final_stop_is_driven_back_and_ends_closer_to_the_start(overshoot):
    without, with_approach = overshoot
    mission = without.mission
    assert past_end(mission.route, mission.odom()) > 1.5 * TOLERANCE     # it did overshoot
    assert without.result.status == 'home'          # within home_tolerance: today's verdict
    ending = with_approach.mission.ending
    assert ending.approach is not None and ending.approach.ended == 'at the end'
    assert with_approach.result.status == 'home' and 'final approach: backed' in with_approach.mission.reason
    assert with_approach.result.position_error < 0.5 * without.result.position_error, (
        with_approach.result.position_error, without.result.position_error)
    assert abs(past_end(with_approach.mission.route, with_approach.mission.odom())) < TOLERANCE
    assert _states(with_approach) == ['idle', 'recording', 'rotating', 'returning', 'home']
    v, w = with_approach.run.base.true_twist
    assert abs(v) <= BACK_TRAVEL_DEFAULTS['stopped_v'] and abs(w) <= BACK_TRAVEL_DEFAULTS['stopped_w']


def test_the_approach_reverses_slowly(overshoot):
    _, played = overshoot
    started = played.run.events.origins['approach']
    fastest = max(_moved_between(played, t, t + 1.0) for t in played.run.path_times if t >= started)
    assert 0.0 < fastest <= 1.1 * APPROACH_DEFAULTS['approach_v'], fastest     # m in any 1 s


def test_a_cancel_in_the_approach_aborts_with_the_robot_still():
    played = _play(events=[('cancel', 'approach', 0.5)])
    cancelled = played.run.events.origins['approach'] + 0.5
    assert played.result.status == 'aborted' and played.mission.machine.outcome == outcome.CANCELLED
    assert 'home' not in _states(played)
    assert _moved_between(played, cancelled + LAG + 0.3, played.run.base.t) < 0.002


def test_a_bumper_in_the_approach_stops_it_and_a_held_one_aborts_it_never_home():
    pressed = _play(events=[('bumper', 'approach', 0.5, 15.0)])
    start = pressed.run.events.origins['approach'] + 0.5
    assert pressed.result.status == 'aborted' and pressed.mission.machine.outcome == outcome.CONTACTS
    assert 'home' not in _states(pressed) and 'the final approach' in pressed.mission.reason
    assert _moved_between(pressed, start + LAG + 0.3, pressed.run.base.t) < 0.002
    brief = _play(events=[('bumper', 'approach', 0.5, 1.0)])     # released: it goes on, as the return
    start = brief.run.events.origins['approach'] + 0.5
    assert _moved_between(brief, start + LAG + 0.3, start + 2.5) < 0.002     # + contact_wait
    assert brief.result.status == 'home' and '1 bumper contact' in brief.mission.reason


def test_a_takeover_in_the_approach_is_the_operators_then_it_goes_on_home():
    played = _play(events=[('takeover', 'approach', 0.5, 1.0, (0.0, 0.0))])
    start = played.run.events.origins['approach'] + 0.5
    assert _moved_between(played, start + LAG + 0.3, start + 1.0 + 1.5) < 0.002    # + takeover_wait
    assert played.result.status == 'home' and 'final approach: backed' in played.mission.reason
    assert played.result.position_error < 0.05


@pytest.mark.parametrize('mission', ['table6_test1', 'test_left_arc'])
def test_a_normal_stop_has_no_approach_and_the_same_ending(mission):
    normal, without = _play(lag=0.0, mission=mission), _play(approach=False, lag=0.0, mission=mission)
    assert normal.mission.ending.approach is None
    assert normal.result.status == without.result.status == 'home'
    assert normal.mission.reason == without.mission.reason
    assert normal.result.position_error == without.result.position_error
    assert normal.run.path == without.run.path


class _Route(object):
    """A straight route along +x ending at (0, 0)."""
    x, y, vertices = [-2.0, 0.0], [0.0, 0.0], 2

    @staticmethod
    def direction(segment):
        return 0.0


def _odom(x, y=0.0, yaw=0.0):
    return OdomState(x, y, yaw, 0.0, 0.0, 0.0)


@pytest.mark.parametrize('odom, planned', [
    (_odom(-0.2), False),                        # short of the end: the follower's business
    (_odom(0.5 * TOLERANCE), False),             # a normal stop
    (_odom(2.0 * TOLERANCE), True),
    (_odom(0.2, 0.05, 0.1), True),               # a little aside: it steers onto the end
    (_odom(0.6), False),                         # beyond route_max_offset: not its track
    (_odom(0.2, 0.0, math.pi), False),           # turned round: the end ahead, not behind
    (_odom(0.1, 0.3), False),                    # abeam: reversing does not reach it
])
def test_when_the_approach_runs(odom, planned):
    assert (FinalApproach.planned(_Route, odom, SimpleNamespace(), 0.0) is not None) == planned


def test_its_command_reverses_capped_and_stops_at_the_end_or_its_time_limit():
    approach = FinalApproach.planned(_Route, _odom(0.2, 0.02), SimpleNamespace(), 0.0)
    v, w = approach.step(0.1, _odom(0.2, 0.02))
    assert v == -APPROACH_DEFAULTS['approach_v'] and 0.0 < abs(w) <= 0.3
    assert w > 0.0      # the end right of the tail (seen backing up): the tail swings to it
    assert approach.step(0.2, _odom(-0.001)) is None and approach.ended == 'at the end'
    late = FinalApproach.planned(_Route, _odom(0.2), SimpleNamespace(), 0.0)
    assert late.step(late.limit + 0.1, _odom(0.2)) is None and late.ended.startswith('not there')


@pytest.mark.parametrize('decision, ended', [(HOLD, None), (ABORT, outcome.ODOMETRY)])
def test_stale_odometry_holds_the_approach_and_lost_odometry_aborts_it(decision, ended):
    odom = _odom(0.2)
    ending = ReturnEnding(0.0, SimpleNamespace(), SimpleNamespace(settle_time=2.0, mode='closed_loop'),
                          _Route, 3, '', lambda cycle: (decision, odom, 'odometry stale'), lambda: odom)
    assert ending.step(0.0) == (ZERO, None) and ending.phase == APPROACH    # it drives from the next cycle
    command, verdict = ending.step(0.1)
    assert command == ZERO and (verdict is None if ended is None else verdict[:2] == (ABORTED, ended))
