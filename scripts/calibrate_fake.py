#!/usr/bin/env python3
"""Re-run the paper's experiments (Tables III, IV, V, VI) on the simulated Kobuki, paper's way.

Each run is the whole mission through the plain-Python harness
(sim/harness.py): a person drives the mission file with the keyboard
teleop (sim/operator.py) while the layer records at the paper's rates with the
paper's literal classifier (dead-band 0, as launch/paper.launch), then vision
is lost, the robot turns by pi and comes back with the paper's sampled-time
control (``time``). The recorded landmarks give the Table III/V/VI columns
(RLV = the landmarks' v, RAV = their w), the ground-truth end gives Table IV's
remaining distance and Table VI's position error. Medians over seeds, with
[min..max]; the paper's value in brackets.

    PYTHONPATH=. /usr/bin/python3 scripts/calibrate_fake.py [--profile paper] [--seeds 10]
"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.abspath(os.path.join(os.path.dirname(__file__), '..')))
from blind_navigation.sim.harness import run_mission  # noqa: E402

PAPER = {'straight_period': 2.0, 'curved_period': 1.0, 'deadband': 0.0,
         'heading_correction': False}   # launch/paper.launch
# Table III: SV -> (RLV max, RLV min, samples > SV, samples); Table IV: FV -> PE %.
TABLE3 = {1: (0.05, 0.053, 0.036, 12, 37), 2: (0.08, 0.096, 0.066, 15, 23), 3: (0.12, 0.122, 0.083, 3, 17),
          4: (0.2, 0.194, 0.160, 0, 12), 5: (0.25, 0.249, 0.209, 0, 10)}
TABLE4 = {1: 6.93, 2: 6.13, 3: 7.57, 4: 11.93}
# Table V: (SV, RLV max, RLV min, samples > SV, samples, straight/curved period): test 2 at 1/2 Hz.
TABLE5 = {1: (0.086, 0.096, 0.006, 7, 47, (2.0, 1.0)), 2: (0.086, 0.092, 0.021, 16, 82, (1.0, 0.5)),
          3: (0.069, 0.072, 0.019, 9, 57, (2.0, 1.0))}
# Table VI: (RLV > LSV, max RLV, max RAV, min RAV, position error m, KB, samples).
TABLE6 = {1: (4, 0.093, 0.135, -0.071, 0.56, 4, 35), 2: (15, 0.096, 0.042, -0.044, 0.28, 5, 43),
          3: (23, 0.096, 0.074, -0.054, 0.48, 6, 53), 4: (30, 0.102, 0.033, -0.043, 0.39, 8, 75),
          5: (37, 0.098, 0.055, -0.042, 0.93, 9, 87), 6: (40, 0.100, 0.09, -0.064, 1.3, 14, 137)}


def runs(mission, profile, seeds, **settings):
    return [run_mission(mission, profile, 'time', seed, **dict(PAPER, **settings)) for seed in range(seeds)]


def cell(values, fmt='%.3f'):
    values = list(values)
    return (fmt + ' [' + fmt + '..' + fmt + ']') % (statistics.median(values), min(values), max(values))


def moving(result):
    """Landmarks taken while driving: without the start-up one and those after the person stopped."""
    landmarks = list(result.landmarks[1:])
    while landmarks and landmarks[-1].v < 0.005:
        landmarks.pop()
    return landmarks[:-1]      # the last one may catch the deceleration


def table3(profile, seeds):
    print('\nTable III (straight, SV) and Table IV (back travel, time mode): fake median [min..max] (paper)')
    print('| SV m/s | RLV max | RLV min | samples > SV | samples | PE % (Table IV) |')
    print('|---|---|---|---|---|---|')
    for test, (sv, p_max, p_min, p_over, p_total) in sorted(TABLE3.items()):
        rs = runs('table3_test%d' % test, profile, seeds)
        pe = TABLE4.get(test)
        print('| %.2f | %s (%.3f) | %s (%.3f) | %s (%d) | %s (%d) | %s (%s) |' % (
            sv, cell(max(l.v for l in moving(r)) for r in rs), p_max,
            cell(min(l.v for l in moving(r)) for r in rs), p_min,
            cell((sum(l.v > sv for l in r.landmarks) for r in rs), '%.0f'), p_over,
            cell((r.samples for r in rs), '%.0f'), p_total,
            cell((100.0 * r.position_error / r.distance for r in rs), '%.1f'), pe if pe else '-'))


def table5(profile, seeds):
    print('\nTable V (curved paths around an obstacle): fake median [min..max] (paper)')
    print('| test | SV m/s | rates Hz | RLV max | RLV min | samples > SV | samples |')
    print('|---|---|---|---|---|---|---|')
    for test, (sv, p_max, p_min, p_over, p_total, (straight, curved)) in sorted(TABLE5.items()):
        rs = runs('table5_test%d' % test, profile, seeds, straight_period=straight, curved_period=curved)
        print('| %d | %.3f | %g/%g | %s (%.3f) | %s (%.3f) | %s (%d) | %s (%d) |' % (
            test, sv, 1 / straight, 1 / curved, cell(max(l.v for l in moving(r)) for r in rs), p_max,
            cell(min(l.v for l in moving(r)) for r in rs), p_min,
            cell((sum(l.v > sv for l in r.landmarks) for r in rs), '%.0f'), p_over,
            cell((r.samples for r in rs), '%.0f'), p_total))


def table6(profile, seeds):
    print('\nTable VI (paths in a 1.7 m corridor, LSV 0.086 m/s, ASV 0.097 rad/s, time mode): '
          'fake median [min..max] (paper)')
    print('| test | length m | RLV > LSV | max RLV | max RAV | min RAV | samples | curved % | KB | '
          'max |y| m | position error m |')
    print('|---|---|---|---|---|---|---|---|---|---|---|')
    for test, (p_over, p_rlv, p_rav_max, p_rav_min, p_error, p_kb, p_total) in sorted(TABLE6.items()):
        rs = runs('table6_test%d' % test, profile, seeds)
        print('| %d | %.2f | %s (%d) | %s (%.3f) | %s (%.3f) | %s (%.3f) | %s (%d) | %s | %s (%d) | %s | %s (%.2f) |' % (
            test, statistics.median(r.distance for r in rs),
            cell((sum(l.v > 0.086 for l in r.landmarks) for r in rs), '%.0f'), p_over,
            cell(max(l.v for l in r.landmarks) for r in rs), p_rlv,
            cell(max(l.w for l in r.landmarks) for r in rs), p_rav_max,
            cell(min(l.w for l in r.landmarks) for r in rs), p_rav_min,
            cell((r.samples for r in rs), '%.0f'), p_total,
            cell((100.0 * sum(l.T < 1.5 for l in r.landmarks) / r.samples for r in rs), '%.0f'),
            cell((r.bytes / 1024.0 for r in rs), '%.1f'), p_kb,
            cell(max(abs(y) for _, y in r.forward_path) for r in rs),
            cell(r.position_error for r in rs), p_error))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--profile', default='paper')
    parser.add_argument('--seeds', type=int, default=10)
    parser.add_argument('--tables', nargs='+', default=['3', '5', '6'], help='3 (with IV), 5, 6')
    args = parser.parse_args()
    print('profile %s, seeds 0..%d, paper configuration (%s)' % (args.profile, args.seeds - 1, PAPER))
    for table in args.tables:
        {'3': table3, '5': table5, '6': table6}[table](args.profile, args.seeds)


if __name__ == '__main__':
    main()
