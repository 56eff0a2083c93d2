"""Physics base: the default launch on the MuJoCo Kobuki beside the kinematic one, same seeds.

    /usr/bin/python3 -m blind_navigation.evaluation.physics [--table6-seeds 3] [--paths 100]
        [--first-seed 1000] [--trajectory-seeds 2] [--loop-paths 12] [--loops-seed 2000]
        [--processes 2] [--out results/physics]

Per group and base: % home, error and floor (% of the path); docs/evaluation.md.
"""
import argparse
import os
import time

from ..sim.harness import run_mission
from ..sim.mujoco_kobuki import BASES
from ..sim.random_paths import CATEGORIES, LOOP_CATEGORIES
from ..sim.command_series import trajectory_names
from . import montecarlo
from .montecarlo import settings_for
from .paper import TABLE6
from .real_like import REAL, mission_of, percentile
from .report import markdown_table, median, num, write_run

GROUPS = ('Table VI', 'random real-like paths', 'real trajectories', 'loop paths (pruned)')
#: issue 24's targets on the physics base (random paths and real trajectories together)
TARGETS = {'home_pct': 100.0, 'median': 1.0, 'p95': 2.5, 'ratio': 1.3}


def jobs_for(table6_seeds=3, paths=100, first_seed=1000, trajectory_seeds=2, loop_paths=12, loops_seed=2000):
    """(group, mission key, seed, base) per run, every mission and seed on each base."""
    def spread(categories, count, first):
        names = sorted(categories)
        return [(names[k % len(names)], first + k) for k in range(count)]
    missions = [(GROUPS[0], m, s) for m in sorted(TABLE6) for s in range(table6_seeds)]
    missions += [(GROUPS[1], c, s) for c, s in spread(CATEGORIES, paths, first_seed)]
    missions += [(GROUPS[2], n, first_seed + s) for n in trajectory_names() for s in range(trajectory_seeds)]
    missions += [(GROUPS[3], c, s) for c, s in spread(LOOP_CATEGORIES, loop_paths, loops_seed)]
    return [(group, key, seed, base) for group, key, seed in missions for base in BASES]


def run_job(job):
    """One mission on one base -> [row]."""
    group, key, seed, base = job
    started = time.time()
    if group == GROUPS[0]:
        mission = key
    else:
        mission = mission_of(REAL + key if group == GROUPS[2] else group, key, seed)
    settings = dict(settings_for('paper', seed, base)('closed_loop'), event_sampling=True, prune_loops=True)
    r = run_mission(mission, 'paper', 'closed_loop', seed, **settings)
    length = r.distance
    error_pct = 100.0 * r.position_error / length if length else float('nan')
    floor_pct = 100.0 * r.floor_error / length if length and r.floor_error is not None else float('nan')
    return [{'group': group, 'mission': r.mission, 'seed': seed, 'base': base, 'status': r.status,
             'reason': r.reason, 'length': length, 'error': r.position_error, 'error_pct': error_pct,
             'floor_pct': floor_pct, 'ratio': error_pct / floor_pct if floor_pct > 0 else float('nan'),
             'wall': time.time() - started}]


def summary(rows):
    """Numbers of one group of rows (one base)."""
    home = sum(r['status'] == 'home' for r in rows)
    return {'runs': len(rows), 'home_pct': 100.0 * home / len(rows) if rows else float('nan'),
            'median': median([r['error_pct'] for r in rows]),
            'p95': percentile([r['error_pct'] for r in rows], 0.95),
            'floor': median([r['floor_pct'] for r in rows]), 'ratio': median([r['ratio'] for r in rows]),
            'wall': sum(r['wall'] for r in rows)}


def table(rows):
    """Markdown: per group, the two bases side by side (same missions and seeds)."""
    lines = []
    for group in GROUPS:
        for base in BASES:
            s = summary([r for r in rows if r['group'] == group and r['base'] == base])
            if s['runs']:
                lines.append([group, base, s['runs'], num(s['home_pct'], 0), num(s['median'], 2),
                              num(s['p95'], 2), num(s['floor'], 2), num(s['ratio'], 2), num(s['wall'], 0)])
    return markdown_table(['paths', 'base', 'runs', '% home', 'median error % of path', 'p95 error %',
                           'median floor %', 'median error / floor', 'harness wall s'], lines)


def verdict(rows):
    """(text, met) for issue 24's targets: random paths and real trajectories on the physics base."""
    s = summary([r for r in rows if r['base'] == 'mujoco' and r['group'] in GROUPS[1:3]])
    if not s['runs']:
        return 'no physics-base runs of random paths or real trajectories', False
    checks = [('home', s['home_pct'] >= TARGETS['home_pct'], '%s %% home (target 100 %%)' % num(s['home_pct'], 1)),
              ('median', s['median'] <= TARGETS['median'], 'median %s %% (<= 1.0 %%)' % num(s['median'], 2)),
              ('p95', s['p95'] <= TARGETS['p95'], 'p95 %s %% (<= 2.5 %%)' % num(s['p95'], 2)),
              ('ratio', s['ratio'] <= TARGETS['ratio'], 'median error / floor %s (<= 1.3)' % num(s['ratio'], 2))]
    text = '%d runs: %s' % (s['runs'], '; '.join('%s %s' % (t, 'met' if ok else 'NOT met') for _, ok, t in checks))
    return text, all(ok for _, ok, _ in checks)


NOTE = ('Both bases run the same missions and seeds (the same sensor-error draws) in '
        'blind_navigation.launch\'s default configuration; the floor is the ideal follower on '
        'the same base (sim/harness). The physics base is sim/mujoco_kobuki.py on the tile floor: '
        'slip comes from the wheel contacts (most in turns), the castors drag, and kobuki_driver\'s '
        'acceleration limiter is on; docs/evaluation.md says why the bases differ.\n')


def section(args, log=print):
    """The bench's physics-base section: (markdown, rows)."""
    jobs = jobs_for(args.physics_table6_seeds, args.physics_paths, args.real_like_seed,
                    args.physics_trajectory_seeds, args.physics_loop_paths, args.loops_seed)
    started = time.time()
    rows = montecarlo.run_jobs(jobs, args.processes,
                               lambda done, total: log('physics base %d/%d runs (%.0f s)'
                                                       % (done, total, time.time() - started))
                               if done % 20 == 0 or done == total else None, run_job)
    text, _ = verdict(rows)
    return ('%s\n%s\n**Targets** (issue 24, physics base, random paths and real trajectories): %s\n'
            % (table(rows), NOTE, text)), rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--table6-seeds', dest='physics_table6_seeds', type=int, default=3)
    parser.add_argument('--paths', dest='physics_paths', type=int, default=100)
    parser.add_argument('--first-seed', dest='real_like_seed', type=int, default=1000)
    parser.add_argument('--trajectory-seeds', dest='physics_trajectory_seeds', type=int, default=2)
    parser.add_argument('--loop-paths', dest='physics_loop_paths', type=int, default=12)
    parser.add_argument('--loops-seed', type=int, default=2000)
    parser.add_argument('--processes', type=int, default=2)
    parser.add_argument('--out', default='results/physics')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    started = time.time()
    text, rows = section(args)
    write_run(args.out, 'physics', argv, started, rows, text)
    return rows


if __name__ == '__main__':
    main()
