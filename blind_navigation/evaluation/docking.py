"""The bench's docking row (issue 31): seeded real-like missions of 5-30 m that start at the
Kobuki's dock, the default launch with ``dock_at_home`` on the harness (paper profile): how
many end docked, and the time from home to docked.

    /usr/bin/python3 -m blind_navigation.evaluation.docking [--paths 20] [--first-seed 4000]
        [--bases kinematic mujoco] [--processes 2] [--out results/docking]
"""
import argparse
import os
import time

from ..sim.harness import play
from ..sim.mujoco_kobuki import BASES  # noqa: F401 (the bench's bases)
from .montecarlo import run_jobs, settings_for
from .real_like import mission_of
from .report import markdown_table, med_range, write_csv
from .ros_harness import path_set

#: m, the missions' length on an ideal robot (issue 31's bench row)
LENGTH = (5.0, 30.0)


def run_job(job):
    """One mission from the dock on one base -> [row]."""
    key, seed, base = job
    started = time.time()
    settings = dict(settings_for('paper', seed, base)('closed_loop'), event_sampling=True,
                    prune_loops=True, dock_at_home=True, dock='start')
    played = play(mission_of(key, key, seed), 'paper', 'closed_loop', seed, floor=False, **settings)
    docking = played.run.docking
    return [{'mission': key, 'seed': seed, 'base': base, 'state': played.result.status,
             'length': played.result.distance, 'home_error': played.result.position_error,
             'docked': bool(docking and docking.docked),
             'dock_time': docking.time if docking else float('nan'),
             'dock_text': docking.text if docking else played.mission.reason,
             'wall': time.time() - started}]


def table(rows):
    """Per base: missions, how many ended docked, the time from home to docked."""
    lines = []
    for base in sorted({r['base'] for r in rows}):
        these = [r for r in rows if r['base'] == base]
        docked = [r for r in these if r['docked']]
        lines.append([base, len(these), '%d (%.0f %%)' % (len(docked), 100.0 * len(docked) / len(these)),
                      med_range([r['dock_time'] for r in docked], 1),
                      '; '.join(sorted({r['dock_text'] for r in these if not r['docked']}))[:300]])
    return markdown_table(['base', 'missions', 'docked', 'home -> docked s, median [min..max]',
                           'why not'], lines)


def section(paths, first_seed, bases, processes, out, log=print):
    """(Markdown, rows) of :data:`LENGTH` m paths from the dock, on each of ``bases``."""
    jobs = [(key, seed, base) for base in bases
            for _, key, seed in path_set(paths, first_seed, LENGTH)]
    rows = run_jobs(jobs, processes, lambda done, total: log('docking %d/%d missions' % (done, total)),
                    run_job)
    write_csv(os.path.join(out, 'docking.csv'), rows)
    text = ('%d seeded real-like paths of %g-%g m (seeds from %d), each starting backed off the '
            'dock (`dock:=start`), paper profile, `dock_at_home`; the harness plays the fake\'s dock '
            'drive (sim/dock_drive.py):\n\n%s' % (paths, LENGTH[0], LENGTH[1], first_seed, table(rows)))
    return text, rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--paths', type=int, default=20)
    parser.add_argument('--first-seed', type=int, default=4000)
    parser.add_argument('--bases', nargs='*', default=list(BASES))
    parser.add_argument('--processes', type=int, default=2)
    parser.add_argument('--out', default='results/docking')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    text, _ = section(args.paths, args.first_seed, args.bases, args.processes, args.out)
    with open(os.path.join(args.out, 'docking.md'), 'w') as stream:
        stream.write('## Docking at home\n\n' + text)
    print(text)


if __name__ == '__main__':
    main()
