"""Missions as command series (sim/command_series.py), the seeded random path
generator (sim/random_paths.py) and the real trajectories in config/paths:
deterministic, within the Kobuki's limits, each category what it says."""
import math
import os

import pytest

from blind_navigation.sim.command_series import (PATHS_DIR, CommandSeries, load_trajectory,
                                                 trajectory_names)
from blind_navigation.sim.random_paths import CATEGORIES, random_mission


def test_command_series_looks_commands_up_by_time():
    series = CommandSeries([(0.1, 0.0, 1.0), (0.0, 0.5, 0.5), (-0.2, 0.0, 2.0)])
    assert series.command_at(0.0) == (0.1, 0.0)
    assert series.command_at(0.99) == (0.1, 0.0)
    assert series.command_at(1.0) == (0.0, 0.5)
    assert series.command_at(3.49) == (-0.2, 0.0)
    assert series.command_at(3.5) is None
    assert series.nominal_length() == pytest.approx(0.5)
    with pytest.raises(ValueError, match='beyond the Kobuki limits'):
        CommandSeries([(0.8, 0.0, 1.0)])
    with pytest.raises(ValueError, match='lasts'):
        CommandSeries([(0.1, 0.0, 0.0)])


def seeded_within_category(categories, category, seeds):
    """The missions of ``category`` (in ``categories``) of seeds 0 .. seeds - 1, checked:
    the same seed gives the same path and another seed another, each within the
    category's length and the Kobuki's limits, in pieces of whole tenths of a second."""
    a, b = random_mission(category, 7), random_mission(category, 7)
    assert a.segments == b.segments
    assert random_mission(category, 8).segments != a.segments
    (low, high), _ = categories[category]
    missions = [random_mission(category, seed) for seed in range(seeds)]
    for mission in missions:
        assert low <= mission.nominal_length() <= high * 1.3
        assert all(abs(v) <= 0.7 + 1e-9 and abs(w) <= math.pi + 1e-9 for v, w, _ in mission.segments)
        assert all(abs(d / 0.1 - round(d / 0.1)) < 1e-6 for _, _, d in mission.segments)
    return missions


@pytest.mark.parametrize('category', sorted(CATEGORIES))
def test_random_paths_are_seeded_and_within_their_category(category):
    seeded_within_category(CATEGORIES, category, 5)


def _moving(mission):
    return [(v, w, d) for v, w, d in mission.segments if v != 0.0]


def test_categories_have_their_features():
    turns = lambda m: [s for s in m.segments if s[0] == 0.0 and s[1] != 0.0]
    reversing = [random_mission('reversing', s) for s in range(5)]
    assert all(any(v < 0 for v, _, _ in _moving(m)) for m in reversing)
    creeping = [random_mission('creeping', s) for s in range(5)]
    assert all(0.02 <= abs(v) <= 0.05 for m in creeping for v, _, _ in _moving(m))
    fast = [random_mission('fast_long', s) for s in range(5)]
    assert max(abs(v) for m in fast for v, _, _ in m.segments) > 0.6
    for seed in range(5):
        mission = random_mission('move_base_like', seed)
        first_turn = sum(w * d for v, w, d in mission.segments[:40] if v == 0.0 and w != 0.0
                         and mission.segments.index((v, w, d)) < 40)
        assert turns(mission)
        assert mission.segments[0][0] == 0.0 and mission.segments[0][1] != 0.0  # starts turning in place
        assert abs(first_turn) > 0.0
        last_turn = [s for s in mission.segments if s[0] != 0.0][-1]
        assert mission.segments.index(last_turn) < len(mission.segments) - 2   # ends turning in place
    spins = [random_mission('turns_in_place', s) for s in range(5)]
    assert all(len(turns(m)) >= 2 for m in spins)
    assert max(abs(w) for m in spins for _, w, _ in turns(m)) > 2.0


def test_unknown_category_is_refused():
    with pytest.raises(ValueError, match='unknown path category'):
        random_mission('teleporting', 0)


def test_shipped_trajectories_keep_their_citation_and_replay():
    names = trajectory_names()
    assert {'tuc_corridor_uturn', 'tuc_lecture_hall_loop', 'mrclam6_robot1_stopgo'} <= set(names)
    for name in names:
        mission = load_trajectory(name)
        assert 'Licence' in mission.description and 'Paper' in mission.description
        assert mission.duration > 30.0 and mission.nominal_length() > 2.0
    corridor = load_trajectory('tuc_corridor_uturn')
    assert corridor.nominal_length() == pytest.approx(44.28, abs=0.05)
    assert 'CC BY-NC-SA' in open(os.path.join(PATHS_DIR, 'README.md')).read()


def test_malformed_trajectory_files_are_refused_naming_the_line(tmp_path):
    bad = tmp_path / 'bad.csv'
    bad.write_text('# header\nt,v,w\n0.0,0.1,0.0\n0.1,zero,0.0\n')
    with pytest.raises(ValueError, match=r'bad.csv:4'):
        load_trajectory(str(bad))
    bad.write_text('t,v,w\n0.0,0.1,0.0\n0.0,0.1,0.0\n')
    with pytest.raises(ValueError, match='does not increase'):
        load_trajectory(str(bad))
    bad.write_text('time,speed\n0,0\n')
    with pytest.raises(ValueError, match='t,v,w'):
        load_trajectory(str(bad))
    with pytest.raises(ValueError, match='not found'):
        load_trajectory('no_such_trajectory')
