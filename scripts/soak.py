#!/usr/bin/env python3
"""Soak run of the layer as a robot runs it (issues 6 and 14): the default launch
(blind_navigation.launch, every role in one process) records for an hour at rtf 1
in wall time while the fake TurtleBot (``paper`` noise, 640x480 camera) drives
laps, ``rosbag record /odom`` beside it; then vision fails and the recording
ends. One run of evaluation/cost.py with windows of ``--window`` s.

    source scripts/ros_env.sh
    /usr/bin/python3 scripts/soak.py [--duration 3600] [--window 600] [--out results/soak.md]

(`make soak` does both.) It reports the layer's resident memory (VmRSS) at the
end of each window and its CPU per window beside the bag's, and checks:

- memory: RSS growth from the end of the warm-up to the end <= ``--max-growth-mb``;
- CPU: no growth: the layer's CPU relative to the bag's in the same window (the
  bag's work per message is constant: the ratio takes out what the shared
  machine does to both) in the last ``--compare`` windows is within
  ``--max-cpu-growth`` of the first ones';
- the recording: every landmark valid (core/store), their periods summing to the
  time recorded (the first landmark's start to ``rotating``) and their summed ``d`` to the path length
  of the odometry in the bag over the same time, both within 1 %.

Exit status 0 when all hold.
"""
import argparse
import math
import os
import sys

from blind_navigation.core.geometry import distance
from blind_navigation.core.store import load_landmarks
from blind_navigation.evaluation import cost


def odometry_path(bag_path, start, end):
    """Length (m) of the /odom positions in the bag stamped within [start, end] (s)."""
    import rosbag
    length, last = 0.0, None
    with rosbag.Bag(bag_path) as bag:
        for _, msg, _ in bag.read_messages():
            stamp = msg.header.stamp.to_sec()
            if stamp < start or stamp > end:
                continue
            p = msg.pose.pose.position
            if last is not None:
                length += distance(last[0], last[1], p.x, p.y)
            last = (p.x, p.y)
    return length


def window_table(result):
    """[(end of window s after the first mark, layer RSS MiB, layer CPU %, bag CPU %)]."""
    marks = [m for m in result['marks'] if m['label'].startswith('recording ')]
    layer = [name for name, kind in result['kinds'].items() if kind == 'layer']
    bag = [name for name, kind in result['kinds'].items() if kind == 'bag']
    rows = [(0.0, sum(marks[0]['processes'][n]['rss_kb'] for n in layer) / 1024.0, None, None)]
    for start, end in zip(marks, marks[1:]):
        rows.append((end['t'] - marks[0]['t'],
                     sum(end['processes'][n]['rss_kb'] for n in layer) / 1024.0,
                     sum(cost.cpu_pct(start, end, n) for n in layer),
                     sum(cost.cpu_pct(start, end, n) for n in bag)))
    return rows


def check_recording(result, run_dir):
    """(lines, problems) about the landmark file against the bag's odometry."""
    landmarks = load_landmarks(os.path.join(run_dir, 'landmarks', 'landmarks.yaml')).landmarks
    # the mission turns ``recording`` when the first landmark is saved, one period after the start
    started = result['state_times']['recording'] - landmarks[0].T
    ended = result['state_times']['rotating']
    recorded = sum(lm.d for lm in landmarks)
    periods = sum(lm.T for lm in landmarks)
    driven = odometry_path(os.path.join(run_dir, 'odom.bag'), started, ended)
    problems = []
    if abs(periods - (ended - started)) > 0.01 * (ended - started):
        problems.append('landmark periods sum to %.1f s, recorded %.1f s' % (periods, ended - started))
    if abs(recorded - driven) > 0.01 * driven:
        problems.append('summed d %.2f m vs %.2f m of odometry' % (recorded, driven))
    lines = ['%d landmarks over %.0f s recorded (periods sum to %.1f s), summed d %.2f m against '
             '%.2f m of odometry in the bag (%+.2f %%)' % (len(landmarks), ended - started, periods,
                                                         recorded, driven,
                                                         100.0 * (recorded / driven - 1.0) if driven else math.nan)]
    return lines, problems


def report(result, args):
    """(Markdown text, problems)."""
    rows = window_table(result)
    growth = rows[-1][1] - rows[0][1]
    ratios = [layer / bag for _, _, layer, bag in rows[1:] if bag]
    first = sum(ratios[:args.compare]) / len(ratios[:args.compare])
    last = sum(ratios[-args.compare:]) / len(ratios[-args.compare:])
    cpu_growth = last / first - 1.0
    problems = []
    if growth > args.max_growth_mb:
        problems.append('RSS grew by %.2f MiB (> %.2f)' % (growth, args.max_growth_mb))
    if cpu_growth > args.max_cpu_growth:
        problems.append('CPU relative to the bag grew by %.1f %% (> %.0f %%)'
                        % (100 * cpu_growth, 100 * args.max_cpu_growth))
    recording, recording_problems = check_recording(result, result['run_dir'])
    problems += recording_problems
    lines = ['# Soak run (scripts/soak.py)', '',
             'Default launch (blind_navigation.launch, one process) recording at rtf 1 in wall '
             'time, fake TurtleBot (paper noise, 640x480 camera at 30 Hz) driving laps, `rosbag '
             'record /odom` beside it; %.0f s of windows after %.0f s of warm-up. Run directory: %s'
             % (args.duration, args.warmup, result['run_dir']), '',
             '| window end, s | layer RSS MiB | layer CPU % | bag CPU % | layer / bag |',
             '|---|---|---|---|---|']
    for t, rss, layer, bag in rows:
        lines.append('| %.0f | %.2f | %s | %s | %s |' % (
            t, rss, '—' if layer is None else '%.2f' % layer, '—' if bag is None else '%.2f' % bag,
            '%.2f' % (layer / bag) if layer is not None and bag else '—'))
    lines += ['', 'RSS growth %+.2f MiB (limit %.2f); CPU relative to the bag, last %d windows vs '
              'first %d: %+.1f %% (limit %+.0f %%).' % (growth, args.max_growth_mb, args.compare,
                                                        args.compare, 100 * cpu_growth,
                                                        100 * args.max_cpu_growth), '']
    lines += recording + ['', 'result: ' + ('OK' if not problems else 'FAILED: ' + '; '.join(problems))]
    return '\n'.join(lines), problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--duration', type=float, default=3600.0, help='s of measured recording')
    parser.add_argument('--window', type=float, default=600.0, help='s per window')
    parser.add_argument('--warmup', type=float, default=60.0, help='s of recording before the first mark')
    parser.add_argument('--max-growth-mb', type=float, default=1.0, help='largest accepted RSS growth, MiB')
    parser.add_argument('--max-cpu-growth', type=float, default=0.10,
                        help='largest accepted growth of the CPU ratio to the bag (0.10: 10 %%)')
    parser.add_argument('--compare', type=int, default=2, help='windows compared at each end')
    parser.add_argument('--run-dir', default='results/soak', help='where the run writes (bag, logs)')
    parser.add_argument('--out', default='', help='also write the report (Markdown) here')
    args = parser.parse_args()
    windows = int(round(args.duration / args.window))
    if windows < 2 * args.compare:
        parser.error('--duration / --window must give at least 2 x --compare windows')
    result = cost.run_once(os.path.abspath(args.run_dir), dict(cost.CONFIGS['default'][1], seed='0'),
                           ['--warmup', str(args.warmup), '--windows', str(windows), '--window',
                            str(args.window), '--until', 'recording_end'],
                           timeout=args.warmup + windows * args.window + 600.0,
                           drive_s=args.warmup + windows * args.window + 3.0)
    if 'failed' in result:
        print('soak: %s' % result['failed'], file=sys.stderr)
        return 1
    text, problems = report(result, args)
    print(text)
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out, 'w') as stream:
            stream.write(text + '\n')
    return 0 if not problems else 1


if __name__ == '__main__':
    sys.exit(main())
