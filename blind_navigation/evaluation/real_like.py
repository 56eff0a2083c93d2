"""Real-like paths: the return on paths no one tuned for, against the physical floor.

    /usr/bin/python3 -m blind_navigation.evaluation.real_like [--paths 60] [--first-seed 1000]
        [--trajectory-seeds 2] [--events] [--processes 2] [--out results/real_like]

Random paths and real trajectories, every mode in its launch configuration (``--events``
adds ``closed_loop+events``); per group and mode: % home, error, floor, error / floor.
"""
import argparse
import math
import os
import time

from ..core.back_travel import MODES
from ..sim.command_series import load_trajectory, trajectory_names
from ..sim.harness import run_modes
from ..sim.random_paths import CATEGORIES, random_mission
from . import montecarlo
from .montecarlo import settings_for
from .report import markdown_table, median, num, write_run

EVENTS_MODE = 'closed_loop+events'
REAL = 'real:'


def jobs_for(paths, first_seed=1000, trajectory_seeds=2, events=False):
    """(group, mission key, seed, modes) per run: random paths spread over the
    categories (path k: category k mod 6, seed first_seed + k), then each real
    trajectory with ``trajectory_seeds`` seeds."""
    modes = MODES + ((EVENTS_MODE,) if events else ())
    categories = sorted(CATEGORIES)
    jobs = [(categories[k % len(categories)], categories[k % len(categories)], first_seed + k, modes)
            for k in range(paths)]
    jobs += [(REAL + name, name, first_seed + s, modes)
             for name in trajectory_names() for s in range(trajectory_seeds)]
    return jobs


def mission_of(group, key, seed):
    return load_trajectory(key) if group.startswith(REAL) else random_mission(key, seed)


def _settings_of(seed):
    """The launch configurations' settings (evaluation/montecarlo.settings_for), and
    closed_loop's with the motion-event samples for :data:`EVENTS_MODE`."""
    launched = settings_for('paper', seed)

    def settings_of(mode):
        if mode == EVENTS_MODE:
            return dict(launched('closed_loop'), event_sampling=True)
        return launched(mode)
    return settings_of


def run_job(job):
    """One mission in every mode -> list of row dicts."""
    group, key, seed, modes = job
    mission = mission_of(group, key, seed)
    started = time.time()
    results = run_modes(mission, 'paper', modes, seed, settings_of=_settings_of(seed),
                        run_mode=lambda mode: 'closed_loop' if mode == EVENTS_MODE else mode)
    rows = []
    for mode in modes:
        r = results[mode]
        length = r.distance
        rows.append(dict(result_row(group, seed, mode, r), **{
            'error_pct': 100.0 * r.position_error / length if length else float('nan'),
            'floor': r.floor_error,
            'floor_pct': 100.0 * r.floor_error / length if length and r.floor_error is not None
            else float('nan'),
            'dense_error': r.dense_error, 'ratio': _ratio(r.position_error, r.floor_error),
            'late': len(r.late), 'duration': r.duration, 'wall': time.time() - started}))
    return rows


def result_row(group, seed, mode, r):
    """The columns every harness row has: the run (group, mission, seed, mode) and its
    outcome (sim/harness.MissionResult ``r``: status, reason, length, landmarks, error)."""
    return {'group': group, 'mission': r.mission, 'seed': seed, 'mode': mode, 'status': r.status,
            'reason': r.reason, 'length': r.distance, 'landmarks': r.samples, 'error': r.position_error}


def _ratio(error, floor):
    return error / floor if floor and math.isfinite(floor) and floor > 0 else float('nan')


def run_jobs(jobs, processes=2, progress=None, job=run_job):
    """Rows of ``job`` (default :func:`run_job`) over ``jobs`` (montecarlo.run_jobs), sorted
    by group, seed and mode."""
    rows = montecarlo.run_jobs(jobs, processes, progress, job)
    return sorted(rows, key=lambda r: (r['group'], r['seed'], r['mode']))


def percentile(values, share):
    """The ``share`` quantile (0..1) of finite ``values``, linear between ranks."""
    values = sorted(v for v in values if v is not None and math.isfinite(v))
    if not values:
        return float('nan')
    position = share * (len(values) - 1)
    low = int(math.floor(position))
    high = min(low + 1, len(values) - 1)
    return values[low] + (values[high] - values[low]) * (position - low)


def summary(rows):
    """Numbers of one group of rows (one mode)."""
    home = [r for r in rows if r['status'] == 'home']
    errors = [r['error_pct'] for r in rows]
    floors = [r['floor_pct'] for r in rows]
    return {'runs': len(rows), 'home_pct': 100.0 * len(home) / len(rows) if rows else float('nan'),
            'aborted': len(rows) - len(home), 'median': median(errors),
            'p95': percentile(errors, 0.95), 'floor': median(floors),
            'ratio': median([r['ratio'] for r in rows]),
            'ratio_of_medians': _ratio(median(errors), median(floors))}


def table(rows):
    """Markdown: per group and mode, then every random path and every real trajectory."""
    groups = sorted({r['group'] for r in rows}, key=lambda g: (g.startswith(REAL), g))
    modes = [m for m in MODES + (EVENTS_MODE,) if any(r['mode'] == m for r in rows)]
    lines = []

    def line(name, selected):
        for mode in modes:
            s = summary([r for r in selected if r['mode'] == mode])
            if s['runs']:
                lines.append([name, mode, s['runs'], num(s['home_pct'], 0), s['aborted'],
                              num(s['median'], 2), num(s['p95'], 2), num(s['floor'], 2),
                              num(s['ratio'], 2), num(s['ratio_of_medians'], 2)])
    for group in groups:
        line(group, [r for r in rows if r['group'] == group])
    line('**all random paths**', [r for r in rows if not r['group'].startswith(REAL)])
    line('**all real trajectories**', [r for r in rows if r['group'].startswith(REAL)])
    return markdown_table(['paths', 'mode', 'runs', '% home', 'aborted', 'median error % of length',
                           'p95 error %', 'median floor %', 'median error / floor',
                           'median error / median floor'], lines)


NOTE = ('Error = ground-truth distance between the start and where the robot stopped, %% of the '
        'recorded path length; floor = the same for a follower that tracks the recorded 50 Hz '
        'odometry back perfectly on the same simulated robot (same seed, recording, heading '
        'correction, pi turn): what no landmark scheme can beat. `time`/`distance` record in the '
        'paper\'s configuration (launch/paper.launch), `closed_loop` in blind_navigation.launch\'s '
        '(heading correction, gyro calibration on seed + 10000); `%s`: closed_loop recorded with '
        'the proposed motion-event samples (core/motion_events.py). Random paths: '
        'sim/random_paths.py; real trajectories: config/paths (sources and licences in '
        'config/paths/README.md).\n' % EVENTS_MODE)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--paths', type=int, default=60, help='random paths (spread over the categories)')
    parser.add_argument('--first-seed', type=int, default=1000)
    parser.add_argument('--trajectory-seeds', type=int, default=2, help='seeds per real trajectory')
    parser.add_argument('--events', action='store_true', help='also closed_loop with motion-event samples')
    parser.add_argument('--processes', type=int, default=2)
    parser.add_argument('--out', default='results/real_like')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    started = time.time()
    jobs = jobs_for(args.paths, args.first_seed, args.trajectory_seeds, args.events)
    rows = run_jobs(jobs, args.processes,
                    lambda done, total: print('real-like %d/%d missions (%.0f s)'
                                              % (done, total, time.time() - started), flush=True)
                    if done % 10 == 0 or done == total else None)
    write_run(args.out, 'real_like', argv, started, rows, '%s\n%s' % (table(rows), NOTE))
    return rows


if __name__ == '__main__':
    main()
