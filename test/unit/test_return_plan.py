"""core/return_plan: the recording's checks before a return (landmarks lost while the
robot drove or turned, at the end or within; an untrusted odometry reset; a loss taken
standing still bridged), the gaps' warning, the goals in return order, the planned route
(built, and pruned only with prune)."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core import outcome
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.odometry_reset import UNTRUSTED
from blind_navigation.core.pruning import prune_route
from blind_navigation.core.return_plan import (NO_LOSS, STILL_LOSS_DISTANCE, STILL_LOSS_TURN,
                                               WriteLoss, plan_return, recording_problem,
                                               return_warning, still_loss)
from blind_navigation.core.route import build_route
from blind_navigation.core.store import load_landmarks


@pytest.fixture
def recorded(tmp_path):
    """load(labels): the landmark file of those label numbers, loaded by core/store."""
    def load(numbers):
        path = tmp_path / 'landmarks.yaml'
        path.write_text(''.join('landmark_%06d: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n' % n
                                for n in numbers))
        return load_landmarks(str(path), allow_empty=True)
    return load


def test_a_clean_recording_has_no_problem_and_no_warning(recorded):
    assert recording_problem(recorded([1, 2, 3])) is None
    assert return_warning(recorded([1, 2, 3])) == ''


def test_a_loss_taken_standing_still_is_bridged_anywhere(recorded):
    holes = recorded([1, 2, 5, 6])          # 3 and 4 lost: holes the return bridges
    still = WriteLoss(2, 0.0, 0.0, 'disk full')
    assert recording_problem(holes, still) is None
    assert return_warning(holes, still) == (
        'the recording has 1 gap(s) (2 landmark(s) lost): the return bridges them; 2 landmark(s) '
        'could not be written (disk full) while the robot stood still (0.000 m, 0.00 rad): the '
        'return bridges them')
    # the end lost too (the disk stayed full through the standstill), still standing still
    at_the_end = WriteLoss(5, STILL_LOSS_DISTANCE, STILL_LOSS_TURN, 'disk full')
    assert recording_problem(holes, at_the_end) is None
    assert recording_problem(recorded([]), at_the_end) is None      # nothing written yet


def test_a_loss_that_drove_or_turned_refuses_the_return_at_the_end_or_within(recorded):
    holes = recorded([1, 2, 5, 6])
    drove = WriteLoss(5, STILL_LOSS_DISTANCE + 0.001, 0.0, 'disk full')
    ending = recording_problem(holes, drove)
    problem = ending.reason
    assert ending.code == outcome.STORAGE
    assert problem.startswith('the last 3 landmark(s) of the recording could not be written '
                              '(disk full): 0.006 m and 0.00 rad of the path are in no file')
    assert problem.endswith('the way back from here is unknown; not travelling back')
    turned = WriteLoss(2, 0.0, STILL_LOSS_TURN + 0.01, 'EIO')
    problem = recording_problem(holes, turned).reason
    assert problem.startswith('2 landmark(s) within the recording could not be written (EIO): '
                              '0.000 m and 0.11 rad')
    assert 'the way back across them is unknown' in problem


def test_no_loss_and_a_resumed_return_are_not_judged_by_losses(recorded):
    holes = recorded([1, 2, 5, 6])
    assert recording_problem(holes, NO_LOSS) is None
    assert recording_problem(holes, None) is None     # a resumed return: judged before it started
    assert return_warning(holes, NO_LOSS) == return_warning(holes) == (
        'the recording has 1 gap(s) (2 landmark(s) lost): the return bridges them')
    assert return_warning(recorded([1, 2]), None) == ''


def test_still_loss_bounds_distance_and_turn():
    assert still_loss(NO_LOSS)
    assert still_loss(WriteLoss(3, STILL_LOSS_DISTANCE, STILL_LOSS_TURN, ''))
    assert not still_loss(WriteLoss(1, 0.17, 0.0, ''))
    assert not still_loss(WriteLoss(1, 0.0, 0.5, ''))


def test_an_untrusted_reset_refuses_the_return_naming_the_last():
    gaps = [SimpleNamespace(before='landmark_000002', reason=UNTRUSTED + ' a'),
            SimpleNamespace(before='landmark_000005', reason=UNTRUSTED + ' b')]
    ending = recording_problem(SimpleNamespace(gaps=gaps))
    problem = ending.reason
    assert ending.code == outcome.ODOMETRY
    assert 'could not carry across (%s b, before landmark_000005)' % UNTRUSTED in problem


def plan_route(landmarks, anchor, params, prune):
    """(route, log lines) of core/return_plan.plan_return."""
    route, result = plan_return(landmarks, anchor, params, prune)
    return route, result.describe() if result is not None else []


def test_the_route_is_pruned_only_with_prune():
    # out 2 m, a loop of radius 0.5 m, back: a loop pruning may cut
    landmarks = [Landmark(0.2, 0.0, 0.2, 1.0, 0.0)] * 10 + \
        [Landmark(0.2, 0.4, 0.2, 1.0, (0.4 * k) % (2 * math.pi)) for k in range(1, 17)]
    plain, lines = plan_route(landmarks, (0.0, 0.0), None, prune=False)
    assert lines == [] and plain.to_lists() == build_route(landmarks, (0.0, 0.0)).to_lists()
    pruned, lines = plan_route(landmarks, (0.0, 0.0), None, prune=True)
    expected = prune_route(build_route(landmarks, (0.0, 0.0)), landmarks, None, None)
    assert pruned.to_lists() == expected.route.to_lists() and lines == expected.describe()
    assert expected.cuts and pruned.length < plain.length - 3.0      # the loop was cut
