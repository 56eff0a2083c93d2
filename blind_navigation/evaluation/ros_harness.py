"""ROS beside the harness, run by run: the same paths, seeds and settings.

    /usr/bin/python3 -m blind_navigation.evaluation.ros_harness [--rtf 5] [--seeds 2]
        [--rtf1-runs 3] [--events KEY ...] [--reuse] [--out results/ros_harness]
    /usr/bin/python3 -m blind_navigation.evaluation.ros_harness --set 10
        [--bases kinematic mujoco] [--extra 15:2 1:2] [--rtf 5] [--out DIR]

Paths: :data:`PATHS`, the real trajectories of config/paths and short real-like
paths (sim/random_paths.py), written as mission files for the fake's
mission_driver. Each (path, seed) runs closed_loop in blind_navigation.launch's
recording configuration (paper profile, heading correction with the gyro
calibration of seed + 10000 written to the file the layer reads, no pruning,
no motion events: bench.launch's) on the harness and over ROS (bench.launch) at
``--rtf``; the first ``--rtf1-runs`` pairs also at rtf 1. The harness runs a
second time as the ROS run ran: recording the time the layer recorded before the operator
started (``start_delay``: the sampling's phase on the path) and with its median hand-over gap
(``handover_latency``).
Table: error % of the recorded length per run, ratios, medians (docs/evaluation.md).
``--set N`` (issue 29, :func:`run_set`): N seeded real-like paths 5-40 m (:func:`path_set`) on each
base, the harness on the same base beside each, summed up per base and rtf (:func:`set_table`).
"""
import argparse
import json
import os
import time

import yaml

from ..core.geometry import distance
from ..core.gyro_calibration import SPIN_DEFAULTS, save_calibration
from ..sim.harness import SIMULATION_DEFAULTS, run_modes
from .montecarlo import gyro_calibration_for, settings_for
from .real_like import REAL, mission_of
from .report import markdown_table, median, num, write_csv
from .ros_runs import run_ros

#: (group, key, path seed): the paths, shortest first (the rtf 1 runs take the first ones).
PATHS = [('move_base_like', 'move_base_like', 1002), ('reversing', 'reversing', 1000),
         (REAL + 'mrclam6_robot1_stopgo', 'mrclam6_robot1_stopgo', 1000),
         ('turns_in_place', 'turns_in_place', 1007), ('indoor_mixed', 'indoor_mixed', 1008),
         (REAL + 'tuc_lecture_hall_loop', 'tuc_lecture_hall_loop', 1000),
         (REAL + 'tuc_corridor_uturn', 'tuc_corridor_uturn', 1000)]
#: Issue 29's set: seeded real-like paths of these categories (sim/random_paths.py), 5-40 m long.
SET_CATEGORIES = ('indoor_mixed', 'move_base_like', 'reversing', 'turns_in_place')
SET_LENGTH = (5.0, 40.0)
#: Issue 29's targets per base: all home, median and worst % of the path, ROS / harness median.
SET_TARGETS = {'median': 1.0, 'worst': 2.5, 'ratio': 1.3}
#: Other noise realisations of each harness run (``shift`` 1.., :func:`harness_run`).
REALISATIONS = 5
#: Sim s from the clock's start to the operator's first command over ROS, at any rtf (the
#: layer must record by then; bench.launch's 3 x rtf is too short at rtf 1 on a loaded machine).
START_DELAY = 15.0
PROFILE = 'paper'
MODE = 'closed_loop'


NOTE = ('\nError: ground-truth distance from the start to where the robot stopped, %% of the recorded '
        'length. Harness range: the same harness run with 1..%d control steps (20 ms) more standing '
        'still before vision is lost: the same robot and recorded path (gyro bias, visual-odometry drift, '
        'calibration; the standstill at its end longer), the return\'s noise draws shifted: how far one run\'s error moves with the draws '
        'alone. ROS cannot replay the harness\'s draws (docs/evaluation.md). Hand-over gap: sim s from '
        'a goal\'s result to the next goal sent; turn point: where the ROS run\'s robot truly was at '
        'vision loss, m from the harness\'s (the operator\'s commands are open loop: another noise '
        'realisation, and commands arriving late under load, drive another path); harness as the ROS '
        'run: recording the ROS run\'s lead before the operator starts (the samples\' phase on the '
        'path) and with its median hand-over gap; stops: how often the layer\'s return commands fell to '
        'zero and then moved again; final hold: from the last non-zero return command to the zero '
        'after it (the harness: handover_timeout 0.1 s). Load: the 1-minute load average as the run started (2 cores).\n'
        % REALISATIONS)


def write_mission(mission, path):
    """``mission`` (a sim/mission.Mission) as a mission file of ``(v, w, duration)`` segments."""
    data = {'description': '%s (evaluation/ros_harness.py)' % mission.name, 'rate': mission.rate,
            'segments': [{'v': v, 'w': w, 'duration': d} for v, w, d in mission.segments]}
    with open(path, 'w') as stream:
        yaml.safe_dump(data, stream)
    return path


def handover_gaps(result):
    """Sim s from each goal's result to the next goal sent, from a ROS run's probe."""
    goals = result.get('goal_stamps') or []
    gaps = []
    for ended in result.get('result_stamps') or []:
        later = [g for g in goals if g >= ended]
        if later:
            gaps.append(later[0] - ended)
    return gaps


def harness_run(mission, seed, latency=0.0, shift=0, lead=0.0, events=False, base='kinematic', prune=False):
    """The harness's closed_loop row of ``mission`` on ``seed``, ``latency`` s per hand-over,
    ``lead`` s recording before the operator starts (``start_delay``), with the motion-event
    samples if ``events``;
    ``shift`` control steps more of standing still before vision is lost: the same robot (its
    per-run draws) with the later noise draws shifted, another realisation of the same run; ``base``: sim/mujoco_kobuki.BASES; ``prune``: prune_loops."""
    launched = settings_for(PROFILE, seed, base)
    settle = SIMULATION_DEFAULTS['settle_time'] + shift * SIMULATION_DEFAULTS['control_dt']
    result = run_modes(mission, PROFILE, (MODE,), seed, settings_of=lambda mode: dict(
        launched(mode), handover_latency=latency, settle_time=settle, start_delay=lead,
        event_sampling=events, prune_loops=prune))[MODE]
    return {'status': result.status, 'length': result.distance, 'error': result.position_error,
            'error_pct': 100.0 * result.position_error / result.distance, 'samples': result.samples,
            'floor_pct': 100.0 * result.floor_error / result.distance, 'turn_point': result.forward_path[-1]}


def handover_stops(result):
    """How often the layer's return commands fell to zero and then moved again (a stop
    between two goals, or a hold on stale odometry), from a ROS run's probe; None without them."""
    if 'return_commands' not in result:
        return None
    moving, stops, stopped = False, 0, False
    for _, v, w in result['return_commands']:
        if v != 0.0 or w != 0.0:
            stops += stopped
            moving, stopped = True, False
        elif moving:
            stopped = True
    return stops


def final_hold(result):
    """Sim s from the layer's last non-zero return command to the zero after it (the harness
    holds the last command ``handover_timeout``), from a ROS run's probe; None without them."""
    commands = result.get('return_commands') or []
    moving = [t for t, v, w in commands if v != 0.0 or w != 0.0]
    zeros = [t for t, v, w in commands if moving and t > moving[-1] and v == 0.0 and w == 0.0]
    return zeros[0] - moving[-1] if zeros else None


def ros_run(out_dir, label, mission_file, seed, rtf, calibration, reuse, events=False, base='kinematic',
            prune=False):
    """The probe's result of one ROS run (run_ros) with the machine's 1-minute load average at
    its start (``load``); with ``reuse`` an earlier run's probe.json."""
    name = os.path.join(label, 'rtf%g' % rtf)
    probe, load_file = (os.path.join(out_dir, name, f) for f in ('probe.json', 'load.json'))
    if reuse and os.path.exists(probe):
        with open(probe) as stream:
            result = json.load(stream)
        if os.path.exists(load_file):
            with open(load_file) as stream:
                result.update(json.load(stream))
        return result
    load = os.getloadavg()[0]
    result = run_ros(out_dir, label, MODE, seed, rtf, start_delay=START_DELAY,
                     gyro_calibration_file=calibration, name=name, mission=mission_file,
                     launch_args=('event_sampling:=%s' % str(events).lower(), 'base:=%s' % base,
                                  'prune_loops:=%s' % str(prune).lower()))
    with open(load_file, 'w') as stream:
        json.dump({'load': load}, stream)
    return dict(result, load=load)


def pair(out_dir, group, key, path_seed, seed, rtfs, log, reuse=False, events=False, base='kinematic',
         realisations=REALISATIONS, prune=False, robots=0):
    """One path and seed: the harness, and ROS at each of ``rtfs``; a row dict. ``events``:
    both record with the motion-event samples (blind_navigation.launch's default); ``base``:
    the fake's and the harness's; ``realisations``: the harness's other noise realisations;
    ``prune``: both prune loops (with ``events``: blind_navigation.launch's defaults); ``robots``:
    the harness on as many other robots (noise seeds ``seed`` + 1000 k), their median error
    (``harness_robots_pct``) and how many the ROS run's error exceeds (``ros<rtf>_rank``)."""
    mission = mission_of(group, key, path_seed)
    label = '%s_p%d_s%d%s%s%s' % (key, path_seed, seed, '_events' if events else '', '_pruned' if prune else '',
                                  '' if base == 'kinematic' else '_' + base)
    run_dir = os.path.join(out_dir, label)
    os.makedirs(run_dir, exist_ok=True)
    mission_file = write_mission(mission, os.path.join(run_dir, 'mission.yaml'))
    calibration = os.path.join(run_dir, 'gyro_calibration.yaml')
    save_calibration(calibration, gyro_calibration_for(PROFILE, seed, base), SPIN_DEFAULTS['turns'])
    row = {'path': group + (' +events' if events else ''), 'path_seed': path_seed, 'seed': seed, 'base': base}
    row.update({'harness_' + k: v for k, v in harness_run(mission, seed, events=events, base=base,
                                                          prune=prune).items()})
    shifted = [row['harness_error_pct']] + [harness_run(mission, seed, shift=k, events=events, base=base,
                                                        prune=prune)['error_pct'] for k in range(1, realisations + 1)]
    row.update(harness_min=min(shifted), harness_max=max(shifted))
    others = [harness_run(mission, seed + 1000 * k, events=events, base=base, prune=prune)['error_pct']
              for k in range(1, robots + 1)]
    if others:
        row.update(harness_robots_pct=median(others), harness_robots=len(others))
    for rtf in rtfs:
        log('ROS %s at rtf %g (load %.2f now)' % (label, rtf, os.getloadavg()[0]))
        ros = ros_run(out_dir, label, mission_file, seed, rtf, calibration, reuse, events, base, prune)
        tag = 'ros%g_' % rtf
        row[tag + 'load'] = ros.get('load')
        if 'failed' in ros:
            row[tag + 'failed'] = ros['failed']
            continue
        gaps = handover_gaps(ros)
        turn_point = ros['forward_path'][-1] if ros.get('forward_path') else None
        row.update({tag + 'offset': distance(turn_point[0], turn_point[1], *row['harness_turn_point'])
                    if turn_point else None})
        row.update({tag + 'state': ros['state'], tag + 'length': ros['length'], tag + 'error': ros['error'],
                    tag + 'error_pct': 100.0 * ros['error'] / ros['length'], tag + 'rtf': ros['rtf'],
                    tag + 'gap_median': median(gaps), tag + 'gap_max': max(gaps) if gaps else None,
                    tag + 'stops': handover_stops(ros), tag + 'final_hold': final_hold(ros), tag + 'goals': len(ros.get('goal_stamps') or [])})
        if others:
            row[tag + 'rank'] = sum(other < row[tag + 'error_pct'] for other in others)
        lead = max(0.0, ros['mission_start'] - ros['recording_state']) \
            if ros.get('mission_start') and ros.get('recording_state') else 0.0
        row[tag + 'as_ros_error_pct'] = harness_run(mission, seed, median(gaps) if gaps else 0.0,
                                                    lead=lead, events=events, base=base, prune=prune)['error_pct']
    return row


def run(out_dir, rtf=5.0, seeds=2, rtf1_runs=3, log=print, reuse=False, events=()):
    """Rows of every path x seed (seeds: the path seed and the next ones); the paths whose key
    is in ``events`` once more with the motion-event samples, at ``rtf``."""
    rows, out_dir = [], os.path.abspath(out_dir)     # roslaunch's nodes run in ROS_HOME
    for index, (group, key, path_seed) in enumerate(PATHS):
        for k in range(seeds):
            rtfs = (rtf, 1.0) if k == 0 and index < rtf1_runs else (rtf,)
            rows.append(pair(out_dir, group, key, path_seed, path_seed + k, rtfs, log, reuse))
    rows += [pair(out_dir, group, key, path_seed, path_seed + k, (rtf,), log, reuse, True)
             for group, key, path_seed in PATHS if key in events for k in range(seeds)]
    return _written(os.path.join(out_dir, 'ros_harness.csv'), rows)


def _written(path, rows):
    """``rows`` written to the CSV ``path`` (every key of any row a column); ``rows``."""
    fields = []
    for row in rows:
        fields += [k for k in row if k not in fields]
    write_csv(path, rows, fields)
    return rows


def path_set(count, first_seed=3000, length=SET_LENGTH):
    """(group, key, path seed) of ``count`` seeded paths of :data:`SET_CATEGORIES` in turn, seeds
    ``first_seed`` on, those whose commands drive ``length`` (min, max) m on an ideal robot."""
    paths, k = [], 0
    while len(paths) < count:
        key, seed = SET_CATEGORIES[k % len(SET_CATEGORIES)], first_seed + k // len(SET_CATEGORIES)
        if length[0] <= mission_of(key, key, seed).nominal_length() <= length[1]:
            paths.append((key, key, seed))
        k += 1
    return paths


#: the harness's other robots (noise seeds) beside each ROS run of the set
OTHER_ROBOTS = 8


def run_set(out_dir, bases, count, rtf=5.0, extra=((1.0, 2), (15.0, 2)), first_seed=3000, log=print):
    """Issue 29's runs: on each of ``bases`` the :func:`path_set` at ``rtf``, the first
    ``n`` of them also at each (rtf, n) of ``extra``; the harness beside each (no other
    realisations) and as each ROS run ran (its start lead and median hand-over gap, :func:`pair`);
    blind_navigation.launch's defaults (motion-event samples, pruning). Each run its own robot:
    noise seed ``first_seed`` + its index (the fake draws its noise by sim time, so runs of one
    seed share their standstill's gyro noise); the harness also on :data:`OTHER_ROBOTS` other robots
    a path. Rows, one per (path, base), written to ros_set.csv."""
    rows, out_dir = [], os.path.abspath(out_dir)
    for base in bases:
        for index, (group, key, path_seed) in enumerate(path_set(count, first_seed)):
            rtfs = (rtf,) + tuple(other for other, n in extra if index < n)
            rows.append(pair(out_dir, group, key, path_seed, first_seed + index, rtfs, log, True, True, base, 0,
                             True, OTHER_ROBOTS))
    return _written(os.path.join(out_dir, 'ros_set.csv'), rows)


def set_table(rows, rtf=5.0):
    """Markdown: per run (path, base, each rtf run: error, achieved rtf), then per base and
    rtf the summary against :data:`SET_TARGETS`."""
    rtfs = sorted({float(k[3:].split('_')[0]) for r in rows for k in r
                   if k.startswith('ros') and k.endswith(('_state', '_failed'))}, key=lambda x: (x != rtf, x))
    lines = [[r['path'], '%d / %d' % (r['path_seed'], r['seed']), r['base'], num(r['harness_length'], 1), num(r['harness_floor_pct'], 2),
              num(r['harness_error_pct'], 2)]
             + ['%s (%s, %s)' % (num(r.get('ros%g_error_pct' % x), 2), num(r.get('ros%g_rtf' % x), 1),
                                 r.get('ros%g_state' % x) or r.get('ros%g_failed' % x, '—')) for x in rtfs]
             for r in rows]
    text = markdown_table(['path', 'path / noise seed', 'base', 'length m', 'harness floor %', 'harness error %']
                          + ['ROS rtf %g error %% (achieved rtf, state)' % x for x in rtfs], lines)
    summary = []
    for base in sorted({r['base'] for r in rows}):
        for x in rtfs:
            tag = 'ros%g_' % x
            done = [r for r in rows if r['base'] == base and r.get(tag + 'error_pct') is not None]
            failed = sum(r['base'] == base and tag + 'failed' in r for r in rows)
            if not done:
                continue
            ros, harness = median([r[tag + 'error_pct'] for r in done]), median([r['harness_error_pct'] for r in done])
            as_ros = median([r[tag + 'as_ros_error_pct'] for r in done if tag + 'as_ros_error_pct' in r])
            worst = max(r[tag + 'error_pct'] for r in done)
            home = sum(r[tag + 'state'] == 'home' for r in done)
            ratio = ros / harness if harness else float('nan')
            robots = median([r['harness_robots_pct'] for r in done if 'harness_robots_pct' in r])
            ranks = ','.join(str(r[tag + 'rank']) for r in done if 'harness_robots_pct' in r)
            met = home == len(done) and not failed and ros <= SET_TARGETS['median'] and worst <= SET_TARGETS['worst'] \
                and ratio <= SET_TARGETS['ratio']
            summary.append([base, num(x, 0), len(done) + failed, '%d / %d' % (home, len(done) + failed), num(ros, 2), num(worst, 2),
                            num(harness, 2), num(ratio, 2), num(as_ros, 2), num(ros / as_ros if as_ros else None, 2),
                            num(robots, 2), num(ros / robots if robots else None, 2), ranks or '—',
                            num(median([r[tag + 'rtf'] for r in done]), 1), 'met' if met else 'NOT met'])
    return text + '\n' + markdown_table(
        ['base', 'rtf', 'runs', 'home', 'ROS median %', 'ROS worst %', 'harness median % (same runs)',
         'ROS / harness median', 'harness as the ROS run median %', 'ROS / that',
         'harness on other robots (%d a path) median %%' % OTHER_ROBOTS, 'ROS / that',
         'ROS ranks among them (0-%d)' % OTHER_ROBOTS, 'median achieved rtf',
         'targets (all home, <= 1 %, <= 2.5 %, <= 1.3 x)'], summary)


def _ratio(row, tag):
    value = row.get(tag + 'error_pct')
    return value / row['harness_error_pct'] if value is not None else float('nan')


def _within(row, tag):
    value = row.get(tag + 'error_pct')
    return '—' if value is None else ('yes' if row['harness_min'] <= value <= row['harness_max'] else 'no')


def table(rows, rtf=5.0):
    """Markdown: per run, then the medians and the summary."""
    fast, slow = 'ros%g_' % rtf, 'ros1_'
    lines = []
    for r in rows:
        lines.append([r['path'], r['seed'], num(r['harness_length'], 2), num(r['harness_error_pct'], 2),
                      '%s..%s' % (num(r['harness_min'], 2), num(r['harness_max'], 2)),
                      num(r.get(fast + 'as_ros_error_pct'), 2), num(r.get(fast + 'error_pct'), 2),
                      _within(r, fast), num(_ratio(r, fast), 2), num(r.get(slow + 'error_pct'), 2),
                      num(_ratio(r, slow), 2), num(r.get(fast + 'rtf'), 1),
                      '%s / %s' % (num(r.get(fast + 'offset'), 2), num(r.get(slow + 'offset'), 2)),
                      '%s / %s' % (num(r.get(fast + 'gap_median'), 2), num(r.get(fast + 'gap_max'), 2)),
                      '%s of %s' % (r.get(fast + 'stops', '—'), r.get(fast + 'goals', '—')),
                      '%s / %s' % (num(r.get(fast + 'final_hold'), 2), num(r.get(slow + 'final_hold'), 2)),
                      '%s / %s' % (num(r.get(slow + 'gap_median'), 2), num(r.get(slow + 'gap_max'), 2)),
                      num(r.get(fast + 'load'), 1), r.get(fast + 'failed') or r.get(fast + 'state', '')])

    def med(key):
        return num(median([r.get(key) for r in rows if r.get(key) is not None]), 2)
    paired = [r for r in rows if r.get(slow + 'error_pct') is not None]
    lines.append(['**median**', '', '', med('harness_error_pct'), '', med(fast + 'as_ros_error_pct'),
                  med(fast + 'error_pct'), '', num(median([_ratio(r, fast) for r in rows]), 2),
                  med(slow + 'error_pct'), num(median([_ratio(r, slow) for r in rows]), 2)] + [''] * 8)
    text = markdown_table(['path', 'seed', 'length m', 'harness error %',
                           'harness, %d other noise realisations: range %%' % REALISATIONS,
                           'harness as the ROS run: its start lead and median gap, error %',
                           'ROS rtf %g error %%' % rtf, 'ROS within the harness range', 'ROS / harness',
                           'ROS rtf 1 error %', 'rtf 1 / harness', 'achieved rtf',
                           'turn point from the harness\'s m, rtf %g / 1' % rtf,
                           'hand-over gap median / max s', 'hand-over stops of goals',
                           'final hold s, rtf %g / 1' % rtf,
                           'rtf 1 gap median / max s', 'load (1 min)', 'ROS state'], lines)
    ros = [r for r in rows if r.get(fast + 'error_pct') is not None]
    text += ('\n%d ROS runs at rtf %g: median error %s %% (harness, same paths and seeds: %s %%), median '
             'of the run-by-run ratios %s; %d of %d within the harness\'s own range over %d noise '
             'realisations of the same run. rtf 1 (%d runs): median %s %% against the harness\'s %s %% '
             'and rtf %g\'s %s %% on the same runs.\n' % (
                 len(ros), rtf, med(fast + 'error_pct'), num(median([r['harness_error_pct'] for r in ros]), 2),
                 num(median([_ratio(r, fast) for r in ros]), 2), sum(_within(r, fast) == 'yes' for r in ros),
                 len(ros), REALISATIONS + 1, len(paired), num(median([r[slow + 'error_pct'] for r in paired]), 2),
                 num(median([r['harness_error_pct'] for r in paired]), 2), rtf,
                 num(median([r.get(fast + 'error_pct') for r in paired]), 2)))
    return text


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--rtf', type=float, default=5.0)
    parser.add_argument('--seeds', type=int, default=2, help='seeds per path')
    parser.add_argument('--rtf1-runs', type=int, default=3, help='pairs also run at rtf 1 (shortest paths)')
    parser.add_argument('--events', nargs='*', default=[], metavar='KEY',
                        help='these paths (keys of PATHS) also with the motion-event samples')
    parser.add_argument('--reuse', action='store_true', help='reuse the ROS runs found in --out')
    parser.add_argument('--set', type=int, default=0, metavar='N',
                        help='instead: issue 29\'s set, N seeded real-like paths 5-40 m (path_set) per base')
    parser.add_argument('--bases', nargs='*', default=['kinematic', 'mujoco'], help='with --set')
    parser.add_argument('--extra', nargs='*', default=['1:2', '15:2'], metavar='RTF:N',
                        help='with --set: the first N paths also at RTF')
    parser.add_argument('--out', default='results/ros_harness')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    started = time.time()
    if args.set:
        extra = tuple((float(e.split(':')[0]), int(e.split(':')[1])) for e in args.extra)
        rows = run_set(args.out, args.bases, args.set, args.rtf, extra,
                       log=lambda message: print('ros_harness: %s' % message, flush=True))
        text = set_table(rows, args.rtf)
        with open(os.path.join(args.out, 'ros_set.md'), 'w') as stream:
            stream.write(text)
        print(text)
        return rows
    rows = run(args.out, args.rtf, args.seeds, args.rtf1_runs,
               lambda message: print('ros_harness: %s' % message, flush=True), args.reuse, args.events)
    text = table(rows, args.rtf)
    with open(os.path.join(args.out, 'ros_harness.md'), 'w') as stream:
        stream.write(text)
    print(text)
    print('ros_harness: %.0f s wall' % (time.time() - started))
    return rows


if __name__ == '__main__':
    main()
