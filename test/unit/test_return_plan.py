"""core/return_plan: the recording's checks before a return (a lost end, an untrusted
odometry reset), the gaps' warning, the goals in return order, the planned route
(built, and pruned only with prune)."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core.landmark import Landmark
from blind_navigation.core.odometry_reset import UNTRUSTED
from blind_navigation.core.pruning import prune_route
from blind_navigation.core.return_plan import (gaps_warning, plan_route, recording_problem,
                                               return_goals)
from blind_navigation.core.route import build_route
from blind_navigation.core.store import load_landmarks


@pytest.fixture
def recorded(tmp_path):
    """load(labels): the landmark file of those label numbers, loaded by core/store."""
    def load(numbers):
        path = tmp_path / 'landmarks.yaml'
        path.write_text(''.join('landmark_%06d: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n' % n
                                for n in numbers))
        return load_landmarks(str(path))
    return load


def test_a_clean_recording_has_no_problem_and_no_warning(recorded):
    assert recording_problem(recorded([1, 2, 3])) is None
    assert gaps_warning(recorded([1, 2, 3])) == ''


def test_holes_are_bridged_and_lost_landmarks_at_the_end_refuse_the_return(recorded):
    holes = recorded([1, 2, 5, 6])          # 3 and 4 lost: holes the return bridges
    assert recording_problem(holes, reported_lost=2) is None
    assert gaps_warning(holes).startswith('the recording has 1 gap(s) (2 landmark(s) lost)')
    problem = recording_problem(holes, reported_lost=5, loss_error='disk full')
    assert problem.startswith('the last 3 landmark(s) of the recording could not be written '
                              '(disk full)')


def test_an_untrusted_reset_refuses_the_return_naming_the_last():
    gaps = [SimpleNamespace(before='landmark_000002', reason=UNTRUSTED + ' a'),
            SimpleNamespace(before='landmark_000005', reason=UNTRUSTED + ' b')]
    problem = recording_problem(SimpleNamespace(gaps=gaps))
    assert 'could not carry across (%s b, before landmark_000005)' % UNTRUSTED in problem


def test_goals_go_in_return_order():
    assert return_goals(['a', 'b', 'c'], [1, 2, 3]) == [('c', 3), ('b', 2), ('a', 1)]


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
