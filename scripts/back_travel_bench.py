#!/usr/bin/env python3
"""Back-travel benchmark (plain Python, sim/harness.py): final position error
of each control mode on the paper's Table VI missions, over seeds.

    /usr/bin/python3 scripts/back_travel_bench.py [--seeds 10] [--profiles ideal paper]
        [--modes time distance closed_loop] [--heading-correction on|off]
        [--standstill-time 120] [--events] [--out results/back_travel_bench.md]

Prints and writes a Markdown table: per mission, profile and mode the median
and worst error (m), the median as % of the recorded length, and the paper's
Table VI error. Each mode runs in its launch configuration
(evaluation/montecarlo.recording_settings): ``time`` and ``distance`` with
launch/paper.launch's (dead-band 0, no heading correction), ``closed_loop``
with blind_navigation.launch's (dead-band 0.01, heading correction with a gyro
calibration made on another seed: evaluation/montecarlo.gyro_calibration_for).
``--heading-correction off`` turns the heading correction off for
``closed_loop`` too; ``--standstill-time`` sets its longest standstill after vision
loss; ``--events`` records ``closed_loop`` with the proposed motion-event samples
(core/motion_events.py). Same seeds for every mode and profile (on ``ideal`` the
seed changes nothing). The ``calibration`` column counts the runs whose
correction used bias and scale, the bias only, the scale only, or nothing; the
``floor`` column is the median physical floor (sim/harness: the recorded
odometry tracked back perfectly on the same robot).
For paths other than the paper's missions: evaluation/real_like.py.
"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.abspath(os.path.join(os.path.dirname(__file__), '..')))
from blind_navigation.sim.harness import SIMULATION_DEFAULTS, run_mission  # noqa: E402
from blind_navigation.evaluation.montecarlo import (gyro_calibration_for,  # noqa: E402
                                                    recording_settings)

PAPER_TABLE6 = {'table6_test1': 0.56, 'table6_test2': 0.28, 'table6_test3': 0.48,
                'table6_test4': 0.39, 'table6_test5': 0.93, 'table6_test6': 1.3}
STATUSES = ('full', 'bias', 'scale', 'none')


def settings_for(mode, profile, seed, args):
    """run_mission settings of ``mode``'s launch configuration, as the options change it."""
    settings = recording_settings(mode)
    if args.heading_correction == 'off':
        settings['heading_correction'] = False
    if settings.get('heading_correction', SIMULATION_DEFAULTS['heading_correction']):
        settings['gyro_calibration'] = gyro_calibration_for(profile, seed)
        settings['standstill_time'] = args.standstill_time
    if args.events and mode == 'closed_loop':
        settings['event_sampling'] = True
    return settings


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=10)
    parser.add_argument('--profiles', nargs='+', default=['ideal', 'paper'])
    parser.add_argument('--modes', nargs='+', default=['time', 'distance', 'closed_loop'])
    parser.add_argument('--missions', nargs='+', default=sorted(PAPER_TABLE6))
    parser.add_argument('--heading-correction', choices=('off', 'on'), default='on',
                        help='closed_loop with (launch default) or without the heading correction')
    parser.add_argument('--standstill-time', type=float,
                        default=SIMULATION_DEFAULTS['standstill_time'],
                        help='the longest standstill after vision loss measuring the gyro bias, s')
    parser.add_argument('--events', action='store_true',
                        help='closed_loop recorded with the motion-event samples (a proposal)')
    parser.add_argument('--out', default='results/back_travel_bench.md')
    args = parser.parse_args()
    lines = ['| mission | profile | mode | length m | samples | KB | median err m | max err m | '
             'median % of length | median floor m | aborted | correction full/bias/scale/none | '
             'paper err m |',
             '|' + '---|' * 13]
    for mission in args.missions:
        for profile in args.profiles:
            seeds = range(args.seeds)
            for mode in args.modes:
                runs = [run_mission(mission, profile, mode, seed,
                                    **settings_for(mode, profile, seed, args)) for seed in seeds]
                statuses = [r.heading_correction.status for r in runs]
                errors = [r.position_error for r in runs]
                length = statistics.median(r.distance for r in runs)
                median = statistics.median(errors)
                line = '| %s | %s | %s | %.2f | %d | %.1f | %.3f | %.3f | %.2f | %.3f | %d | %s | %s |' % (
                    mission, profile, mode, length, statistics.median(r.samples for r in runs),
                    statistics.median(r.bytes for r in runs) / 1024.0, median, max(errors),
                    100.0 * median / length, statistics.median(r.floor_error for r in runs),
                    sum(r.status != 'home' for r in runs),
                    '/'.join(str(statuses.count(k)) for k in STATUSES),
                    PAPER_TABLE6.get(mission, ''))
                print(line, flush=True)
                lines.append(line)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, 'w') as stream:
        stream.write('Back-travel benchmark: %s, seeds 0..%d\n\n'
                     % (' '.join(sys.argv[1:]) or 'defaults', args.seeds - 1))
        stream.write('\n'.join(lines[:2] + lines[2:]) + '\n')
    print('wrote %s' % args.out)


if __name__ == '__main__':
    main()
