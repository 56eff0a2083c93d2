"""Over ROS as in the harness (issue 29): the same path and seed run over ROS and in the
harness, each traced at 50 Hz (commanded and executed speeds, ground truth, odometry, wheels)
and summed up by :func:`metrics`: hand-over stops, command steps, late cycles, rtf, the
odometry's error growth, the wheel slip.

    /usr/bin/python3 -m blind_navigation.evaluation.handover_trace ros KEY SEED BASE RTF [--out DIR]
    /usr/bin/python3 -m blind_navigation.evaluation.handover_trace harness KEY SEED BASE [--latency S]
    /usr/bin/python3 -m blind_navigation.evaluation.handover_trace show DIR

KEY: a key of evaluation/ros_harness.PATHS (its path seed); BASE: kinematic or mujoco.
"""
import argparse
import json
import math
import os

from ..core.geometry import wrap_angle
from ..core.gyro_calibration import SPIN_DEFAULTS, save_calibration
from ..sim import harness
from ..sim.kobuki import WHEEL_RADIUS, WHEEL_SEPARATION
from .montecarlo import gyro_calibration_for, settings_for
from .real_like import mission_of
from .ros_harness import PATHS, PROFILE, START_DELAY, write_mission
from .ros_runs import run_ros

TOPICS = ('/odom', '/ground_truth/odom', '/mobile_base/commands/velocity', '/joint_states')
FIELDS = ('t', 'cmd_v', 'cmd_w', 'x', 'y', 'yaw', 'v', 'w', 'ox', 'oy', 'oyaw', 'ov', 'ow', 'left', 'right')


def path_of(key):
    """(group, key, path seed) of PATHS' ``key``."""
    return [p for p in PATHS if p[1] == key][0]


def harness_trace(key, seed, base, latency=0.0, floor=False, follow=harness.HANDOVER_FOLLOW):
    """(result, rows, (turn start, return start) sim s) of the harness's closed_loop run of
    ``key`` on ``seed`` and ``base``: one row per control step (:data:`FIELDS`)."""
    group, key, path_seed = path_of(key)
    mission = mission_of(group, key, path_seed)
    rows, marks, command = [], {}, [(0.0, 0.0)]
    advance, turn, back = harness._Run.advance, harness._turn, harness._return

    def traced(run, cmd=None):
        if cmd is not None:
            command[0] = cmd
        advance(run, cmd)
        b, o = run.base, run.base.odom
        p, (v, w) = b.true_pose, b.true_twist
        rows.append((b.t,) + tuple(command[0]) + (p.x, p.y, p.yaw, v, w, o.x, o.y, o.yaw, o.v, o.w)
                    + tuple(b.wheel_speeds))

    def traced_turn(run, *args):
        marks.setdefault('turn', run.base.t)
        return turn(run, *args)

    def traced_return(run, *args, **kwargs):
        marks.setdefault('return', run.base.t)
        return back(run, *args, **kwargs)
    settings = dict(settings_for(PROFILE, seed, base)('closed_loop'), handover_latency=latency,
                    floor=floor, handover_follow=follow)         # the calibration is simulated before the trace starts
    harness._Run.advance, harness._turn, harness._return = traced, traced_turn, traced_return
    try:
        result = harness.run_modes(mission, PROFILE, ('closed_loop',), seed,
                                   settings_of=lambda _mode: settings)['closed_loop']
    finally:
        harness._Run.advance, harness._turn, harness._return = advance, turn, back
    return result, rows, (marks.get('turn'), marks.get('return'))


def ros_trace(out_dir, key, seed, base, rtf, launch_args=()):
    """The probe's result of a ROS run (bench.launch, ``base``) with the bag of :data:`TOPICS`."""
    group, key, path_seed = path_of(key)
    label = '%s_s%d_%s_rtf%g%s' % (key, seed, base, rtf, ''.join('_' + a.replace(':=', '') for a in launch_args))
    run_dir = os.path.abspath(os.path.join(out_dir, label))
    os.makedirs(run_dir, exist_ok=True)
    mission = write_mission(mission_of(group, key, path_seed), os.path.join(run_dir, 'mission.yaml'))
    calibration = os.path.join(run_dir, 'gyro_calibration.yaml')
    save_calibration(calibration, gyro_calibration_for(PROFILE, seed, base), SPIN_DEFAULTS['turns'])
    load = os.getloadavg()[0]
    result = run_ros(os.path.dirname(run_dir), label, 'closed_loop', seed, rtf, start_delay=START_DELAY,
                     gyro_calibration_file=calibration, name=os.path.basename(run_dir) + '/ros',
                     mission=mission, timeout=1500.0, return_timeout=1200.0,
                     launch_args=('event_sampling:=false', 'base:=%s' % base,
                                  'trace_bag:=%s' % os.path.join(run_dir, 'trace.bag'),
                                  'trace_topics:=%s' % ' '.join(TOPICS)) + tuple(launch_args))
    result['load'] = load
    with open(os.path.join(run_dir, 'result.json'), 'w') as stream:
        json.dump(result, stream)
    return result


def _yaw(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def bag_rows(path):
    """Rows (:data:`FIELDS`) of a ROS run's bag, one per ground-truth message; the command is
    the last one on the base's input before it (the mux's output)."""
    import rosbag
    truth, odom, joints, commands = [], {}, {}, []
    with rosbag.Bag(path) as bag:
        for topic, msg, stamp in bag.read_messages(topics=list(TOPICS)):
            if topic == '/mobile_base/commands/velocity':
                commands.append((stamp.to_sec(), msg.linear.x, msg.angular.z))
            elif topic == '/joint_states':
                joints[msg.header.stamp.to_sec()] = tuple(msg.velocity)
            else:
                p, t = msg.pose.pose, msg.twist.twist
                state = (p.position.x, p.position.y, _yaw(p.orientation), t.linear.x, t.angular.z)
                if topic == '/odom':
                    odom[msg.header.stamp.to_sec()] = state
                else:
                    truth.append((msg.header.stamp.to_sec(),) + state)
    rows, k, command = [], 0, (0.0, 0.0)
    for entry in sorted(truth):
        t = entry[0]
        while k < len(commands) and commands[k][0] <= t:
            command, k = commands[k][1:], k + 1
        if t in odom and t in joints:
            rows.append((t,) + command + entry[1:] + odom[t] + joints[t])
    return rows


def stops(commands):
    """How often ``commands`` ((v, w), ...) fell to zero and moved again."""
    count, moving, stopped = 0, False, False
    for v, w in commands:
        if v or w:
            count += stopped
            moving, stopped = True, False
        elif moving:
            stopped = True
    return count


def metrics(rows, start, end=None):
    """What the trace ``rows`` (:data:`FIELDS`) shows from ``start`` to ``end`` sim s (the return):
    stops, command steps over the Kobuki's acceleration limits (0.5 m/s^2, 3.5 rad/s^2),
    commanded - executed speed (rms), wheel slip (rim speed at the nominal radius - ground speed under the wheel,
    rms and integral m), the odometry's drift over the span (m, its displacement against the
    truth's, in the truth's frame at ``start``), the odometry's error against the truth at
    ``start`` and at ``end`` (m, world frame: both start at the origin), true and odometry length."""
    part = [r for r in rows if r[0] >= start and (end is None or r[0] <= end)]
    f = dict((name, i) for i, name in enumerate(FIELDS))
    steps_v = steps_w = 0
    slip, slip_sq, err_sq, length, olength = 0.0, 0.0, 0.0, 0.0, 0.0
    for a, b in zip(part, part[1:]):
        dt = b[0] - a[0]
        if dt <= 0:
            continue
        steps_v += abs(b[1] - a[1]) > 0.5 * dt + 1e-9
        steps_w += abs(b[2] - a[2]) > 3.5 * dt + 1e-9
        err_sq += ((b[1] - b[f['v']]) ** 2) * dt
        for rim, ground in ((WHEEL_RADIUS * b[f['left']], b[f['v']] - b[f['w']] * WHEEL_SEPARATION / 2.0),
                            (WHEEL_RADIUS * b[f['right']], b[f['v']] + b[f['w']] * WHEEL_SEPARATION / 2.0)):
            slip += abs(rim - ground) * dt
            slip_sq += (rim - ground) ** 2 * dt
        length += math.hypot(b[3] - a[3], b[4] - a[4])
        olength += math.hypot(b[8] - a[8], b[9] - a[9])
    first, last = part[0], part[-1]
    span = max(last[0] - first[0], 1e-9)
    turn = first[5] - first[10]
    dx, dy = last[8] - first[8], last[9] - first[9]
    drift = math.hypot(math.cos(turn) * dx - math.sin(turn) * dy - (last[3] - first[3]),
                       math.sin(turn) * dx + math.cos(turn) * dy - (last[4] - first[4]))
    return {'span_s': span, 'stops': stops([(r[1], r[2]) for r in part]), 'steps_v': steps_v,
            'steps_w': steps_w, 'cmd_minus_v_rms': math.sqrt(err_sq / span),
            'slip_rms': math.sqrt(slip_sq / span / 2.0), 'slip_m': slip, 'drift_m': drift,
            'yaw_drift': wrap_angle((last[10] - first[10]) - (last[5] - first[5])),
            'odom_error_start': math.hypot(first[8] - first[3], first[9] - first[4]),
            'odom_error_end': math.hypot(last[8] - last[3], last[9] - last[4]),
            'length': length, 'odom_length': olength}


def late_cycles(return_commands, goals, results, period=0.02, late=2.0):
    """(count, largest s) of the gaps between the layer's successive return commands longer
    than ``late`` x ``period`` (sim s) within a goal (not across a hand-over: from a result to
    the next goal's first command), from a probe's ``return_commands``, ``goal_stamps``, ``result_stamps``."""
    handovers = list(_handovers(goals, results))
    times = [t for t, _, _ in return_commands]
    gaps = [b - a for a, b in zip(times, times[1:]) if b - a > late * period
            and not any(a < end and b > start for start, end in handovers)
            and not any(a < goal <= b for goal in goals)]
    return len(gaps), max(gaps) if gaps else 0.0


def _handovers(goals, results):
    for ended in results:
        later = [g for g in goals if g >= ended]
        if later:
            yield ended, later[0]


def harness_summary(key, seed, base, latency=0.0, follow=harness.HANDOVER_FOLLOW):
    """The harness's run as a dict: error %, floor %, the return's :func:`metrics`."""
    result, rows, (turned, returned) = harness_trace(key, seed, base, latency, follow=follow)
    floor = harness_trace(key, seed, base, latency, floor=True, follow=follow)[0].floor_error
    summary = {'side': 'harness', 'key': key, 'seed': seed, 'base': base, 'latency': latency,
               'follow': follow,
               'status': result.status, 'length': result.distance, 'error': result.position_error,
               'error_pct': 100.0 * result.position_error / result.distance,
               'floor_pct': 100.0 * floor / result.distance, 'goals': len(result.landmarks)}
    summary.update(('return_' + k, v) for k, v in metrics(rows, returned).items())
    summary.update(('forward_' + k, v) for k, v in metrics(rows, 0.0, returned).items())
    return summary


def ros_summary(run_dir):
    """A ROS run (:func:`ros_trace`'s directory) as a dict like :func:`harness_summary`'s."""
    with open(os.path.join(run_dir, 'result.json')) as stream:
        result = json.load(stream)
    rows = bag_rows(os.path.join(run_dir, 'trace.bag'))
    goals, results = result['goal_stamps'], result['result_stamps']
    summary = {'side': 'ros', 'run': os.path.basename(os.path.normpath(run_dir)), 'state': result['state'],
               'length': result['length'], 'error': result['error'],
               'error_pct': 100.0 * result['error'] / result['length'], 'rtf': result['rtf'],
               'load': result.get('load'), 'goals': len(goals),
               'gap_median': _median([b - a for a, b in _handovers(goals, results)]),
               'gap_max': max([b - a for a, b in _handovers(goals, results)] or [0.0])}
    summary['late_cycles'], summary['late_max'] = late_cycles(result.get('return_commands') or [],
                                                              goals, results)
    summary.update(('return_' + k, v) for k, v in metrics(rows, goals[0], results[-1] + 1.0).items())
    summary.update(('forward_' + k, v) for k, v in metrics(rows, 0.0, goals[0]).items())
    return summary


def _median(values):
    values = sorted(values)
    return values[len(values) // 2] if values else None


COLUMNS = ('error_pct', 'floor_pct', 'rtf', 'goals', 'gap_median', 'gap_max', 'late_cycles', 'late_max',
           'return_stops', 'return_steps_v', 'return_steps_w', 'return_cmd_minus_v_rms',
           'return_slip_rms', 'return_drift_m', 'return_yaw_drift', 'return_odom_error_start',
           'return_odom_error_end', 'return_span_s')


def show(summaries):
    """A plain table of summaries (:func:`harness_summary`, :func:`ros_summary`)."""
    lines = ['run ' + ' '.join(c.replace('return_', 'r_') for c in COLUMNS)]
    for s in summaries:
        name = s.get('run') or '%s_s%d_%s_lat%g_follow%g' % (s['key'], s['seed'], s['base'], s['latency'],
                                                             s['follow'])
        lines.append(name + ' ' + ' '.join('%.4g' % s[c] if isinstance(s.get(c), float) else str(s.get(c, '-'))
                                           for c in COLUMNS))
    return '\n'.join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('what', choices=('ros', 'harness', 'show'))
    parser.add_argument('args', nargs='*', help='ros: KEY SEED BASE RTF [name:=value ...]; harness: '
                        'KEY SEED BASE [LATENCY [FOLLOW]]; show: run directories of ros')
    parser.add_argument('--out', default='results/handover_trace')
    args = parser.parse_args(argv)
    a = args.args
    if args.what == 'ros':
        result = ros_trace(args.out, a[0], int(a[1]), a[2], float(a[3]), tuple(a[4:]))
        print(json.dumps({k: result.get(k) for k in ('state', 'error', 'length', 'rtf', 'failed')}))
    elif args.what == 'harness':
        extra = [float(x) for x in a[3:5]]
        print(json.dumps(harness_summary(a[0], int(a[1]), a[2], *extra)))
    else:
        print(show([ros_summary(d) for d in a]))


if __name__ == '__main__':
    main()
