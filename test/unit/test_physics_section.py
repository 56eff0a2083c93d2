"""evaluation/physics.py: the physics-base section's jobs, summary and target check."""
from blind_navigation.evaluation import physics


def test_every_mission_and_seed_runs_on_both_bases():
    jobs = physics.jobs_for(table6_seeds=2, paths=7, first_seed=10, trajectory_seeds=1, loop_paths=3)
    missions = sorted({job[:3] for job in jobs})
    assert len(jobs) == 2 * len(missions)
    for mission in missions:
        assert sorted(job[3] for job in jobs if job[:3] == mission) == ['kinematic', 'mujoco']
    counts = {group: len({m for m in missions if m[0] == group}) for group in physics.GROUPS}
    assert counts[physics.GROUPS[0]] == 6 * 2 and counts[physics.GROUPS[1]] == 7
    assert counts[physics.GROUPS[3]] == 3 and counts[physics.GROUPS[2]] >= 3


def _row(group, base, status='home', error_pct=0.5, floor_pct=0.5):
    return {'group': group, 'base': base, 'status': status, 'error_pct': error_pct, 'floor_pct': floor_pct,
            'ratio': error_pct / floor_pct, 'wall': 1.0}


def test_the_targets_need_every_run_home_and_the_numbers_in_bounds():
    good = [_row(physics.GROUPS[1], 'mujoco') for _ in range(10)] + [_row(physics.GROUPS[2], 'mujoco')]
    text, met = physics.verdict(good + [_row(physics.GROUPS[1], 'kinematic', 'aborted')])
    assert met, text
    text, met = physics.verdict(good + [_row(physics.GROUPS[2], 'mujoco', 'aborted')])
    assert not met and 'home' in text and 'NOT met' in text
    text, met = physics.verdict([_row(physics.GROUPS[1], 'mujoco', error_pct=1.2, floor_pct=1.0)] * 5)
    assert not met, text
    assert physics.verdict([]) == ('no physics-base runs of random paths or real trajectories', False)
    assert '| random real-like paths | mujoco | 10 | 100 |' in physics.table(good)
