"""core/rotation.turn_problem: the owner's check that the robot really turned by pi."""
import math

from blind_navigation.core.rotation import turn_problem


def test_a_turn_by_pi_within_the_tolerance_is_no_problem():
    assert turn_problem(0.2, 0.2 + math.pi - 0.29, 0.3) is None
    assert turn_problem(3.0, 3.0 - math.pi + 0.1, 0.3) is None      # wrapped, either way


def test_a_short_turn_is_a_problem_naming_the_angle():
    assert turn_problem(0.0, math.pi - 0.31, 0.3) == \
        'the robot turned 2.83 rad since vision loss, not pi'


def test_missing_odometry_is_a_problem_a_missing_start_is_not():
    assert turn_problem(0.0, None, 0.3) == 'no odometry to check the turn'
    assert turn_problem(None, 1.0, 0.3) is None
