#!/usr/bin/env python3
"""Where the loop paths' closed-loop error exceeds the floor (issue 29), in the harness.

Each loop path of the physics section (evaluation/physics.py: seed s is the category
sorted(LOOP_CATEGORIES)[s mod 4], as the section's from its default 2000; paper noise, the default launch's settings,
motion events, pruning) is recorded once and returned twice from the same turned
robot: along the floor's dense route (the recorded 50 Hz odometry) and along the
landmarks' pruned route. Per run:

- ``err``, ``floor``: the true error (m) and the floor (the floor return's error had
  its odometry ended on its route's end), as the physics table;
- ``miss``: how far, by its odometry, the landmark return stopped from its route's end;
- ``recon``: how far the landmarks' route ends from the dense route's end (the
  landmarks' reconstruction of the recorded path, before the return moves);
- ``mapped``: the landmark return's error had its odometry ended on its route's end;
- ``limF``/``limP``: the share of the return's 10 ms steps where kobuki_driver's limiter
  held the command back (more than 5 mm/s or 0.05 rad/s), floor and landmark return;
- ``slipF``/``slipP``: rms of the true forward speed minus the odometry's (m/s);
- with ``--kinds``, ``recon`` left without each kind of period (both ends below
  event_speed but moved, the speed reversing, the turn reversing, other), each
  period's modelled chord (core/period_model) against the odometry's;
- with ``--no-return-limiter``, both returns run without kobuki_driver's limiter (the
  recording keeps the base's).

    /usr/bin/python3 scripts/loop_excess.py FIRST COUNT [kinematic|mujoco] [--kinds] [--no-return-limiter]
"""
import bisect
import copy
import math
import sys
from multiprocessing import Pool

from blind_navigation.core.geometry import distance
from blind_navigation.core.motion_events import EVENT_DEFAULTS
from blind_navigation.core.period_model import period_shape
from blind_navigation.core.route import _start_state, _subdivisions
from blind_navigation.evaluation.montecarlo import settings_for
from blind_navigation.sim import harness
from blind_navigation.sim.random_paths import LOOP_CATEGORIES, random_mission

KINDS = ('ends still', 'v reverses', 'turn reverses', 'other')


def _traced(run):
    """Per 10 ms step of ``run``: (limiter holding the command back, true v - odometry v)."""
    rows, advance = [], run.advance

    def traced(command=None):
        advance(command)
        base = run.base
        rows.append((abs(base._cmd[0] - base._limited[0]) > 0.005 or abs(base._cmd[1] - base._limited[1]) > 0.05,
                     base.true_twist[0] - base.odom.v))
    run.advance = traced
    return rows


def _return(recorded, settings, dense, limiter=True):
    run, owner = copy.deepcopy((recorded.run, recorded.owner))
    run.base.profile['acceleration_limiter'] = run.base.profile['acceleration_limiter'] and limiter
    rows = _traced(run)
    if dense:
        owner.configure_return(landmarks=harness.correct_landmarks(harness.dense_landmarks(recorded.odometry),
                                                                   owner.correction),
                               mode='closed_loop', prune_loops=False)
    else:
        owner.configure_return(mode='closed_loop', prune_loops=True)
    harness._return(run, owner, settings)
    route = owner.route
    harness._stop(run, owner, settings)
    truth, odom, start = run.base.true_pose, owner.odom(), run.path_start
    dx, dy = route.x[-1] - odom.x, route.y[-1] - odom.y
    turn = truth.yaw - odom.yaw
    x = truth.x + math.cos(turn) * dx - math.sin(turn) * dy
    y = truth.y + math.sin(turn) * dx + math.cos(turn) * dy
    return {'err': distance(start[0], start[1], truth.x, truth.y), 'miss': math.hypot(dx, dy),
            'mapped': distance(start[0], start[1], x, y), 'end': (route.x[-1], route.y[-1]),
            'limiter': sum(r[0] for r in rows) / float(len(rows)),
            'slip': math.sqrt(sum(r[1] ** 2 for r in rows) / len(rows))}


def _kinds(recorded):
    """{kind: the landmarks' chain end error (m) without that kind's periods' errors}."""
    odometry, landmarks = recorded.odometry, recorded.loaded.landmarks
    stamps = [o.stamp for o in odometry]
    t, previous = odometry[0].stamp, (odometry[0].x, odometry[0].y)
    sums = dict((kind, [0.0, 0.0]) for kind in KINDS)
    for k, b in enumerate(landmarks):
        t += b.T
        first, last = bisect.bisect_left(stamps, t - b.T - 1e-6), min(bisect.bisect_left(stamps, t - 1e-6),
                                                                      len(odometry) - 1)
        a = landmarks[k - 1] if k > 0 else _start_state(b)
        direction = period_shape(a, b, b.d, _subdivisions(a, b, b.d, None))[0]
        state = odometry[last]
        vs = [odometry[j].v for j in range(first, last + 1)]
        ws = [odometry[j].w for j in range(first, last + 1)]
        speed, rate = EVENT_DEFAULTS['event_speed'], EVENT_DEFAULTS['event_turn_rate']
        if max(abs(a.v), abs(b.v)) < speed and b.d > speed:
            kind = KINDS[0]
        elif min(vs) < -speed and max(vs) > speed:
            kind = KINDS[1]
        elif min(ws) < -rate and max(ws) > rate:
            kind = KINDS[2]
        else:
            kind = KINDS[3]
        sums[kind][0] += b.d * math.cos(direction) - (state.x - previous[0])
        sums[kind][1] += b.d * math.sin(direction) - (state.y - previous[1])
        previous = (state.x, state.y)
    total = [sum(s[i] for s in sums.values()) for i in (0, 1)]
    return dict((kind, math.hypot(total[0] - s[0], total[1] - s[1])) for kind, s in sums.items())


def measure(job):
    """One loop path -> a printed line."""
    category, seed, base, kinds, limiter = job
    settings = harness._settings(dict(settings_for('paper', seed, base)('closed_loop'), event_sampling=True))
    recorded = harness._Recorded(random_mission(category, seed), 'paper', seed, settings, None, None)
    floor, pruned = _return(recorded, settings, True, limiter), _return(recorded, settings, False, limiter)
    recon = distance(floor['end'][0], floor['end'][1], pruned['end'][0], pruned['end'][1])
    line = '%-13s %5d %-9s %7.4f %7.4f %6.2f %7.4f %7.4f %7.4f %6.3f %6.3f %6.4f %6.4f' % (
        category, seed, base, pruned['err'], floor['mapped'], pruned['err'] / floor['mapped'], pruned['miss'],
        recon, pruned['mapped'], floor['limiter'], pruned['limiter'], floor['slip'], pruned['slip'])
    if kinds:
        without = _kinds(recorded)
        line += '  ' + ' '.join('%7.4f' % without[kind] for kind in KINDS)
    return line


def main(first, count, base='kinematic', kinds=False, limiter=True):
    categories = sorted(LOOP_CATEGORIES)
    print('%-13s %5s %-9s %7s %7s %6s %7s %7s %7s %6s %6s %6s %6s%s' % (
        'path', 'seed', 'base', 'err', 'floor', 'ratio', 'miss', 'recon', 'mapped', 'limF', 'limP', 'slipF',
        'slipP', '  recon without: ' + ', '.join(KINDS) if kinds else ''))
    jobs = [(categories[seed % len(categories)], seed, base, kinds, limiter)
            for seed in range(first, first + count)]
    pool = Pool(2)
    try:
        for line in pool.imap(measure, jobs):
            print(line, flush=True)
    finally:
        pool.close()
        pool.join()


if __name__ == '__main__':
    main(int(sys.argv[1]), int(sys.argv[2]), *[a for a in sys.argv[3:4] if not a.startswith('--')],
         kinds='--kinds' in sys.argv, limiter='--no-return-limiter' not in sys.argv)
