"""A standing lead before the operator starts (issue 29), in the harness: the gyro bias the
heading correction uses against the robot's own, and the return's error and floor.

    /usr/bin/python3 -m blind_navigation.evaluation.standing_lead [--bases kinematic mujoco]
        [--paths 12] [--first-seed 5000] [--leads 0 5 12 30] [--out results/standing_lead]

Paths: ros_harness.path_set, configured as ros_harness.run_set's harness side; docs/evaluation.md.
"""
import argparse
import os
import statistics
import time

from ..sim.harness import play
from .montecarlo import settings_for
from .real_like import mission_of
from .report import markdown_table, median, num, write_run
from .ros_harness import MODE, PROFILE, path_set


def lead_row(group, key, path_seed, lead, base):
    """One run: ``path_seed`` is the path's and the robot's seed, ``lead`` s standing first."""
    settings = dict(settings_for(PROFILE, path_seed, base)(MODE), start_delay=lead,
                    event_sampling=True, prune_loops=True)
    played = play(mission_of(group, key, path_seed), PROFILE, MODE, path_seed, **settings)
    result, correction = played.result, played.result.heading_correction
    standstill = played.mission.standstill
    return {'path': key, 'path_seed': path_seed, 'base': base, 'lead': lead, 'length': result.distance,
            'status': result.status, 'true_bias': played.run.base._gyro_bias, 'bias': correction.bias,
            'bias_std': correction.bias_std, 'applied': correction.status in ('full', 'bias'),
            'standstill_s': standstill.measurement.duration if standstill else None,
            'error_pct': 100.0 * result.position_error / result.distance,
            'floor_pct': 100.0 * result.floor_error / result.distance}


def table(rows):
    """Markdown: per base and lead, the bias's use and error, the return's error."""
    lines = []
    for base in sorted({r['base'] for r in rows}):
        for lead in sorted({r['lead'] for r in rows}):
            sel = [r for r in rows if r['base'] == base and r['lead'] == lead]
            if not sel:
                continue
            errors = [r['error_pct'] for r in sel]
            lines.append([base, num(lead, 0), len(sel), sum(r['status'] == 'home' for r in sel),
                          sum(not r['applied'] for r in sel),
                          '%.1e' % median([abs(r['bias'] - r['true_bias']) for r in sel]),
                          num(median([r['standstill_s'] for r in sel]), 0), num(median(errors), 2),
                          num(statistics.mean(errors), 2), num(max(errors), 2),
                          num(median([r['error_pct'] / r['floor_pct'] for r in sel]), 2)])
    return markdown_table(['base', 'lead s', 'runs', 'home', 'bias left out', 'median bias error (abs) rad/s',
                           'median standstill s', 'median error %', 'mean error %', 'worst error %',
                           'median error / floor'], lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--bases', nargs='+', default=['kinematic', 'mujoco'])
    parser.add_argument('--paths', type=int, default=12)
    parser.add_argument('--first-seed', type=int, default=5000)
    parser.add_argument('--leads', nargs='+', type=float, default=[0.0, 5.0, 12.0, 30.0])
    parser.add_argument('--out', default='results/standing_lead')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    started = time.time()
    rows = [lead_row(group, key, seed, lead, base) for base in args.bases
            for group, key, seed in path_set(args.paths, args.first_seed) for lead in args.leads]
    return write_run(args.out, 'standing_lead', argv, started, rows, table(rows))


if __name__ == '__main__':
    main()
