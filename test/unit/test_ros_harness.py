"""evaluation/ros_harness.py without ROS: the mission file the fake's operator plays is
the harness's mission, and the hand-over numbers are read from the probe as documented."""

import pytest

from blind_navigation.evaluation import ros_harness
from blind_navigation.evaluation.real_like import mission_of
from blind_navigation.sim.mission import load_mission

@pytest.mark.parametrize('group, key, seed', [('move_base_like', 'move_base_like', 1002),
                                              ('real:mrclam6_robot1_stopgo', 'mrclam6_robot1_stopgo', 1000)])
def test_the_mission_file_plays_the_harness_mission(tmp_path, group, key, seed):
    mission = mission_of(group, key, seed)
    played = load_mission(ros_harness.write_mission(mission, str(tmp_path / 'mission.yaml')))
    assert played.segments == mission.segments and played.rate == mission.rate
    for k in range(int(mission.duration * 10) - 1):      # at every operator tick but the last
        t = k / 10.0 + 0.05
        assert played.command_at(t) == mission.command_at(t), t
    assert played.command_at(mission.duration + 0.1) is None

def test_handover_gaps_run_from_each_result_to_the_next_goal():
    probe = {'goal_stamps': [10.0, 11.05, 12.3, 12.9], 'result_stamps': [11.0, 12.0, 12.5, 13.4]}
    assert ros_harness.handover_gaps(probe) == pytest.approx([0.05, 0.3, 0.4])
    assert ros_harness.handover_gaps({}) == []

def test_stops_count_zeros_between_moves_and_the_final_hold_ends_at_the_first_zero():
    commands = [(1.0, 0.0, 0.0), (1.02, 0.1, 0.0), (1.04, 0.0, 0.0), (1.06, 0.0, 0.0), (1.08, 0.1, 0.2),
                (1.10, 0.0, 0.3), (1.12, 0.0, 0.0), (1.14, 0.1, 0.0), (1.16, 0.1, 0.0), (1.30, 0.0, 0.0),
                (1.32, 0.0, 0.0)]
    probe = {'return_commands': commands}
    assert ros_harness.handover_stops(probe) == 2         # the zeros before the start and at the end do not count
    assert ros_harness.final_hold(probe) == pytest.approx(0.14)
    assert ros_harness.handover_stops({}) is None and ros_harness.final_hold({}) is None

def test_table_has_a_row_per_run_and_the_medians():
    row = {'path': 'p', 'seed': 1, 'harness_length': 2.0, 'harness_error_pct': 0.5, 'harness_min': 0.4,
           'harness_max': 0.7, 'ros5_error_pct': 0.6, 'ros5_rtf': 4.9, 'ros5_state': 'home'}
    failed = dict(row, seed=2, ros5_error_pct=None, ros5_failed='no result')
    text = ros_harness.table([row, failed])
    lines = [line for line in text.splitlines() if line.startswith('| ')]
    assert len(lines) == 4 and '| p | 1 |' in lines[1] and 'no result' in lines[2]
    assert lines[1].count('|') == lines[0].count('|') == lines[3].count('|')
    assert '| yes |' in lines[1] and '| 1.20 |' in lines[1]       # within 0.4..0.7; 0.6 / 0.5
    assert '1 ROS runs at rtf 5: median error 0.60 %' in text
