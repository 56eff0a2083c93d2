"""Loops: the closed-loop return with and without pruning (core/pruning.py) on paths that
come back to where they have been.

    /usr/bin/python3 -m blind_navigation.evaluation.loops [--paths 120] [--first-seed 2000]
        [--trajectory-seeds 1] [--wheel-error-per-m K] [--processes 2] [--out results/loops]

Each mission recorded once, returned unpruned and pruned; the table: docs/pruning.md.
"""
import argparse
import bisect
import math
import os
import time

from ..core.pruning import PRUNE_DEFAULTS
from ..sim.harness import default_params, run_modes
from ..sim.kobuki import load_profile
from ..sim.random_paths import LOOP_CATEGORIES
from .forward import harness_settings
from .montecarlo import settings_for
from .real_like import REAL, mission_of, percentile, result_row, run_jobs
from .report import markdown_table, median, num, write_run

MODES = ('unpruned', 'pruned')
#: The return's true length may differ from its route's by this share (issue 15).
LENGTH_TOLERANCE = 0.05


def jobs_for(paths, first_seed=2000, trajectory_seeds=1, wheel_error=None):
    """(group, mission key, seed, wheel error per metre or None) per run: loop paths
    spread over the categories (path k: category k mod 4, seed first_seed + k), then
    each real trajectory."""
    from ..sim.command_series import trajectory_names
    categories = sorted(LOOP_CATEGORIES)
    jobs = [(categories[k % len(categories)], categories[k % len(categories)], first_seed + k, wheel_error)
            for k in range(paths)]
    jobs += [(REAL + name, name, first_seed + s, wheel_error) for name in trajectory_names()
             for s in range(trajectory_seeds)]
    return jobs


def true_junction_gaps(result):
    """Per cut of ``result`` (a pruned harness MissionResult): how far apart the
    robot truly was at the loop's two passes (m), from the true forward path."""
    times, path = result.forward_times, result.forward_path

    def at(t):
        i = min(max(bisect.bisect_left(times, t), 1), len(times) - 1)
        share = (t - times[i - 1]) / (times[i] - times[i - 1]) if times[i] > times[i - 1] else 0.0
        share = max(0.0, min(1.0, share))
        return [a + share * (b - a) for a, b in zip(path[i - 1], path[i])]
    gaps = []
    for cut in result.pruning.cuts:
        (x0, y0), (x1, y1) = at(cut.started), at(cut.started + cut.duration)
        gaps.append(math.hypot(x1 - x0, y1 - y0))
    return gaps


def run_job(job):
    """One mission, returned unpruned and pruned -> list of two row dicts."""
    group, key, seed, wheel_error = job
    launched = settings_for('paper', seed)('closed_loop')
    params = None
    if wheel_error is not None:
        params = default_params(harness_settings(**launched), load_profile('paper'))
        params.wheel_error_per_m = wheel_error
    started = time.time()
    results = run_modes(mission_of(group, key, seed), 'paper', MODES, seed, params=params,
                        run_mode=lambda mode: 'closed_loop',
                        settings_of=lambda mode: dict(launched, event_sampling=True, floor=False,
                                                      prune_loops=mode == 'pruned'))
    rows = []
    for mode in MODES:
        r = results[mode]
        pruning = r.pruning
        rows.append(dict(result_row(group, seed, mode, r), **{
            'route_length': r.route_length, 'return_length': r.return_length, 'return_time': r.return_time,
            'length_deviation': abs(r.return_length / r.route_length - 1.0) if r.route_length else float('nan'),
            'cuts': len(pruning.cuts) if pruning else 0, 'refused': len(pruning.refused) if pruning else 0,
            'saved': pruning.saved if pruning else 0.0, 'wall': time.time() - started,
            'true_gaps': true_junction_gaps(r) if pruning else []}))
    base = rows[0]
    for row in rows:
        row['length_ratio'] = row['return_length'] / base['return_length']
        row['time_ratio'] = row['return_time'] / base['return_time']
        row['error_change'] = row['error'] - base['error']
        row['true_gap_max'] = max(row['true_gaps'], default=float('nan'))
        row['cuts_over_radius'] = sum(g > PRUNE_DEFAULTS['prune_radius'] for g in row['true_gaps'])
    return rows



def summary(rows):
    """Numbers of one group (both modes' rows, paired by mission and seed)."""
    by = {mode: [r for r in rows if r['mode'] == mode] for mode in MODES}
    pruned, unpruned = by['pruned'], by['unpruned']
    return {
        'runs': len(pruned), 'aborted': {m: sum(r['status'] != 'home' for r in by[m]) for m in MODES},
        'error': {m: median([r['error'] for r in by[m]]) for m in MODES},
        'p95': {m: percentile([r['error'] for r in by[m]], 0.95) for m in MODES},
        'length_ratio': median([r['length_ratio'] for r in pruned]),
        'time_ratio': median([r['time_ratio'] for r in pruned]),
        'deviation': max([r['length_deviation'] for r in pruned] or [float('nan')]),
        'deviation_unpruned': max([r['length_deviation'] for r in unpruned] or [float('nan')]),
        'cuts': median([r['cuts'] for r in pruned]), 'refused': median([r['refused'] for r in pruned]),
        'worse': sum(p['error'] > u['error'] for p, u in zip(pruned, unpruned)),
        'change': median([r['error_change'] for r in pruned]),
        'all_cuts': sum(r['cuts'] for r in pruned),
        'over_radius': sum(r['cuts_over_radius'] for r in pruned),
        'true_gap': median([g for r in pruned for g in r['true_gaps']]),
        'true_gap_max': max([g for r in pruned for g in r['true_gaps']] or [float('nan')]),
    }


def table(rows):
    """Markdown: per group, all loop paths, all real trajectories."""
    groups = sorted({r['group'] for r in rows}, key=lambda g: (g.startswith(REAL), g))
    lines = []

    def line(name, selected):
        s = summary(selected)
        if s['runs']:
            lines.append([name, s['runs'], '%d / %d' % (s['aborted']['unpruned'], s['aborted']['pruned']),
                          '%s / %s' % (num(s['error']['unpruned']), num(s['error']['pruned'])),
                          '%s / %s' % (num(s['p95']['unpruned']), num(s['p95']['pruned'])),
                          num(s['change']), '%d' % s['worse'], num(s['length_ratio'], 2),
                          num(s['time_ratio'], 2),
                          '%s / %s' % (num(100.0 * s['deviation_unpruned'], 1), num(100.0 * s['deviation'], 1)),
                          num(s['cuts'], 0), num(s['refused'], 0),
                          '%d: %s (%s), %d' % (s['all_cuts'], num(s['true_gap']), num(s['true_gap_max']),
                                               s['over_radius'])])
    for name in groups:
        line(name, [r for r in rows if r['group'] == name])
    line('**all loop paths**', [r for r in rows if not r['group'].startswith(REAL)])
    line('**all real trajectories**', [r for r in rows if r['group'].startswith(REAL)])
    return markdown_table(['paths', 'runs', 'aborted (unpruned / pruned)', 'median home error m (unpruned / pruned)',
                           'p95 error m', 'median error change m (pruned - unpruned)', 'runs pruned worse',
                           'median return length pruned / unpruned', 'median return time pruned / unpruned',
                           'largest deviation of the return length from the route % (unpruned / pruned)',
                           'median cuts', 'median refused',
                           'cuts: true junction gap median (max) m, over prune_radius'], lines)


def verdict(rows):
    """The issue's targets on the loop paths: (text, all met)."""
    s = summary([r for r in rows if not r['group'].startswith(REAL)])
    checks = [('none aborted', s['aborted']['unpruned'] == 0 and s['aborted']['pruned'] == 0),
              ('return length within %d %% of the pruned route' % (100 * LENGTH_TOLERANCE),
               s['deviation'] <= LENGTH_TOLERANCE),
              ('median home error pruned <= unpruned (%s <= %s m)' % (num(s['error']['pruned']),
                                                                    num(s['error']['unpruned'])),
               s['error']['pruned'] <= s['error']['unpruned'])]
    text = '; '.join('%s: %s' % (name, 'met' if ok else 'NOT met') for name, ok in checks)
    return text, all(ok for _, ok in checks)


NOTE = ('Each mission is recorded once (paper noise profile, blind_navigation.launch\'s configuration: '
        'heading correction with a gyro calibration on seed + 10000, motion-event samples) and returned '
        'twice from the same state: `unpruned` (the whole route) and `pruned` (core/pruning.py, its '
        'default params). Home error: ground-truth distance from the start where the robot stopped. '
        'Return length: the true path driven from the return\'s start; time: from the return\'s start to '
        'its last goal. Ratios and the error change: the median of the per-run values. True junction gap: '
        'where the robot truly was at the two passes of each cut loop (the rule promises within '
        'prune_radius, %.3f m, at 95 %%). Loop paths: sim/random_paths.py LOOP_CATEGORIES, driven as plans on '
        'ground truth; real trajectories: config/paths, replayed open loop.\n' % PRUNE_DEFAULTS['prune_radius'])


def run(paths, first_seed, trajectory_seeds, processes, progress=None, wheel_error=None):
    """Rows of the loops evaluation."""
    return run_jobs(jobs_for(paths, first_seed, trajectory_seeds, wheel_error), processes, progress,
                    job=run_job)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--paths', type=int, default=120, help='loop paths (spread over the categories)')
    parser.add_argument('--first-seed', type=int, default=2000)
    parser.add_argument('--trajectory-seeds', type=int, default=1, help='seeds per real trajectory')
    parser.add_argument('--wheel-error-per-m', type=float, default=None,
                        help='prune with this wheel-odometry error per metre (default: the core default)')
    parser.add_argument('--processes', type=int, default=2)
    parser.add_argument('--out', default='results/loops')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    started = time.time()
    rows = run(args.paths, args.first_seed, args.trajectory_seeds, args.processes,
               lambda done, total: print('loops %d/%d missions (%.0f s)' % (done, total, time.time() - started),
                                         flush=True) if done % 10 == 0 or done == total else None,
               args.wheel_error_per_m)
    write_run(args.out, 'loops', argv, started, rows, '%s\n%s\n**Targets** (issue 15, loop paths): %s\n'
              % (table(rows), NOTE, verdict(rows)[0]))
    return rows


if __name__ == '__main__':
    main()
