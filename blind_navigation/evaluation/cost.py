"""What the layer costs on a robot: CPU and memory in real time, beside ``rosbag record /odom``.

Each run is ``cost.launch`` on its own master (the fake as a robot runs: wall time, a
640x480 camera) with the layer in one of :data:`CONFIGS`, measured by
evaluation/cost_probe.py while recording and through the return; :func:`latency_runs`
times each vision failure. Command and meaning: docs/cost.md.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import yaml

from .report import markdown_table, med_range, median
from .ros_runs import free_port, stop_group

#: The paper's teleop speeds (Table VI: LSV, ASV): the laps of every drive.
LAP_V, LAP_W, LAP_STRAIGHT = 0.086, 0.097, 20.0
#: name -> (what it is, cost.launch args, what ends the run: cost_probe --until)
CONFIGS = {
    'default': ('blind_navigation.launch (the default: one process, the core mission object, '
                'one loop thread)',
                {'layout': 'blind_navigation'}, 'home'),
    'recording': ('the recording part: blind_navigation.launch with auto_detect false, '
                  'heading_correction false (one process: recorder, sampling publisher and the '
                  'idle pi turn, back-travel server and client)',
                  {'layout': 'blind_navigation', 'auto_detect': 'false',
                   'heading_correction': 'false'}, 'windows'),
    'paper': ('paper.launch (one process per role, the paper\'s configuration)',
              {'layout': 'paper'}, 'home'),
}
FAILURES = ('dark', 'stall', 'lost')
#: detector sets of the latency runs: name -> cost.launch args
DETECTOR_SETS = {'default (camera_info + visual odometry)': {},
                 'image-based (detect_dark: images + visual odometry)': {'detect_dark': 'true'}}
BAG = 'rosbag record (C++ recorder)'
WRAPPER = 'rosbag (Python wrapper)'
#: Budget of issue 30 (default launch, rtf 1, 640x480 camera): % of one core, MiB (120 MB).
BUDGET = {'recording_cpu': 5.0, 'returning_cpu': 10.0, 'rss_mib': 120e6 / 2 ** 20}


def cpu_model(path='/proc/cpuinfo'):
    """The machine's CPU model and core count, as /proc/cpuinfo names them."""
    try:
        with open(path) as stream:
            models = [line.split(':', 1)[1].strip() for line in stream if line.startswith('model name')]
    except OSError:
        return 'unknown CPU'
    return '%s, %d cores' % (models[0], len(models)) if models else 'unknown CPU'


def log(message):
    print('cost: %s' % message, flush=True)


# --------------------------------------------------------------- the drive
def lap_mission(duration, v=LAP_V, w=LAP_W, straight=LAP_STRAIGHT):
    """A mission dict (sim/mission.py) of laps of a rounded square, ``straight`` s
    straight then a quarter turn at ``v``, ``w``, at least ``duration`` s long."""
    if not (duration > 0 and v > 0 and w > 0 and straight > 0):
        raise ValueError('lap_mission: duration, v, w and straight must be > 0, got %r'
                         % ((duration, v, w, straight),))
    quarter = 3.141592653589793 / 2.0
    segments, total = [], 0.0
    while total < duration:
        segments.append({'v': v, 'duration': straight})
        segments.append({'v': v, 'w': w, 'angle': quarter})
        total += straight + quarter / w
    return {'description': 'laps of a rounded square at LSV/ASV, %.0f s' % total, 'rate': 10,
            'segments': segments}


# --------------------------------------------------------------- one run
def run_once(run_dir, launch_args, probe_args, timeout, drive_s):
    """One cost.launch run with the probe; the probe's result dict (+ 'run_dir', 'wall_s')
    or {'failed': why, 'run_dir': ...}. ``run_dir`` may be relative: the launch's nodes, which
    start elsewhere, are given its absolute path."""
    run_dir = os.path.abspath(run_dir)
    os.makedirs(run_dir, exist_ok=True)
    mission = os.path.join(run_dir, 'drive.yaml')
    with open(mission, 'w') as stream:
        yaml.safe_dump(lap_mission(drive_s), stream)
    out, bag = os.path.join(run_dir, 'probe.json'), os.path.join(run_dir, 'odom.bag')
    for stale in (out, bag):
        if os.path.exists(stale):
            os.remove(stale)
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port,
               ROS_HOME=os.path.join(run_dir, 'ros_home'), ROS_LOG_DIR=os.path.join(run_dir, 'log'))
    args = dict({'mission': mission, 'landmark_file': os.path.join(run_dir, 'landmarks', 'landmarks.yaml')},
                **launch_args)
    command = ['roslaunch', '-p', str(port), 'blind_navigation', 'cost.launch'] + \
        ['%s:=%s' % item for item in sorted(args.items())]
    started = time.time()
    with open(os.path.join(run_dir, 'launch.log'), 'w') as launch_log, \
            open(os.path.join(run_dir, 'probe.log'), 'w') as probe_log:
        launch = subprocess.Popen(command, stdout=launch_log, stderr=subprocess.STDOUT, env=env,
                                  start_new_session=True)
        probe = None
        try:
            _wait_for_master(env['ROS_MASTER_URI'], launch)
            # run outside the source tree: the package is the workspace's (with its messages)
            probe = subprocess.Popen([sys.executable, '-m', 'blind_navigation.evaluation.cost_probe',
                                      '--out', out, '--bag', bag] + probe_args,
                                     stdout=probe_log, stderr=subprocess.STDOUT, env=env,
                                     cwd=run_dir, start_new_session=True)
            probe.wait(timeout=timeout)
        except (subprocess.TimeoutExpired, RuntimeError) as error:
            log('%s: %s' % (run_dir, error or 'timed out'))
        finally:
            for process in (probe, launch):
                stop_group(process)
    wall = time.time() - started
    if not os.path.exists(out):
        return {'failed': 'no probe result after %.0f s (probe exit %s); see %s' % (
            wall, probe.returncode if probe else None, run_dir), 'run_dir': run_dir}
    with open(out) as stream:
        result = json.load(stream)
    result.update(run_dir=run_dir, wall_s=wall, launch_args=launch_args)
    return result


def _wait_for_master(uri, launch, timeout=60.0):
    import rosgraph
    deadline = time.monotonic() + timeout
    while not rosgraph.Master('/cost', master_uri=uri).is_online():
        if launch.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError('roslaunch did not bring up a master on %s (exit %s)'
                               % (uri, launch.poll()))
        time.sleep(0.2)


# --------------------------------------------------------------- reading a run
def _marks(result, prefix):
    return [m for m in result['marks'] if m['label'].startswith(prefix)]


def cpu_pct(start, end, name):
    """CPU % of one core of process ``name`` between two marks, None if it is missing."""
    a, b = start['processes'].get(name), end['processes'].get(name)
    if a is None or b is None or end['t'] <= start['t']:
        return None
    return 100.0 * (b['cpu_s'] - a['cpu_s']) / (end['t'] - start['t'])


def phases(result):
    """{phase: (start mark, end mark)} of a run: ``recording`` (the windows), ``rotating``
    (standstill and pi turn), ``returning`` (the return)."""
    out = {}
    recording = _marks(result, 'recording ')
    if len(recording) >= 2:
        out['recording'] = (recording[0], recording[-1])
    states = {m['label'][len('state '):]: m for m in _marks(result, 'state ')}
    if 'rotating' in states and 'returning' in states:
        out['rotating'] = (states['rotating'], states['returning'])
    end = states.get('home') or states.get('aborted')
    if 'returning' in states and end is not None:
        out['returning'] = (states['returning'], end)
    return out


def process_costs(result):
    """[{'process', 'kind', phase: CPU %, 'windows': [CPU % per window], 'hwm_mb', 'rss_mb'}]
    of one run; the memory at the end of the recording windows (peak: VmHWM)."""
    spans = phases(result)
    recording = _marks(result, 'recording ')
    rows = []
    for name, kind in sorted(result['kinds'].items(), key=lambda item: (item[1], item[0])):
        row = {'process': name, 'kind': kind,
               'windows': [cpu_pct(a, b, name) for a, b in zip(recording, recording[1:])]}
        for phase, (start, end) in spans.items():
            row[phase] = cpu_pct(start, end, name)
        last = recording[-1]['processes'].get(name, {}) if recording else {}
        row['hwm_mb'] = last.get('hwm_kb', 0) / 1024.0 if last.get('hwm_kb') else None
        row['rss_mb'] = last.get('rss_kb', 0) / 1024.0 if last.get('rss_kb') else None
        rows.append(row)
    return rows


def totals(result):
    """{'layer_<phase>', 'bag_<phase>' CPU %, 'layer_windows', 'bag_windows', 'layer_hwm_mb',
    'bag_hwm_mb', 'layer_processes'} of one run: the layer's processes summed."""
    rows = process_costs(result)
    layer = [r for r in rows if r['kind'] == 'layer']
    bag = [r for r in rows if r['kind'] == 'bag']
    out = {'layer_processes': len(layer)}
    for phase in ('recording', 'rotating', 'returning'):
        for who, group in (('layer', layer), ('bag', bag)):
            values = [r.get(phase) for r in group]
            out['%s_%s' % (who, phase)] = sum(values) if group and None not in values else None
    for who, group in (('layer', layer), ('bag', bag)):
        per_window = list(zip(*[r['windows'] for r in group])) if group else []
        out['%s_windows' % who] = [sum(w) if None not in w else None for w in per_window]
        hwm = [r['hwm_mb'] for r in group]
        out['%s_hwm_mb' % who] = sum(hwm) if group and None not in hwm else None
    return out


def ratio(a, b):
    return a / b if a is not None and b else None


# --------------------------------------------------------------- sections
def cost_runs(out_dir, configs, reps, windows, window, warmup=10.0):
    """Every config x rep; the run results (failed runs carry 'failed')."""
    runs = []
    recording_s = warmup + windows * window
    for rep in range(reps):                      # interleaved: load drifts hit every config alike
        for config in configs:
            _, launch_args, until = CONFIGS[config]
            log('cost run %s, repetition %d (about %.0f s of drive)' % (config, rep, recording_s))
            result = run_once(os.path.join(out_dir, '%s_r%d' % (config, rep)),
                              dict(launch_args, seed=str(rep)),
                              ['--warmup', str(warmup), '--windows', str(windows), '--window',
                               str(window), '--until', until],
                              timeout=3 * recording_s + 420.0, drive_s=recording_s + 3.0)
            result.update(config=config, rep=rep)
            if 'failed' in result:
                log('cost run %s r%d FAILED: %s' % (config, rep, result['failed']))
            runs.append(result)
    return runs


def cost_tables(runs):
    """The Markdown tables of :func:`cost_runs`."""
    ok = [r for r in runs if 'failed' not in r]
    text = ''
    failed = [r for r in runs if 'failed' in r]
    if failed:
        text += '**Failed runs:** %s\n\n' % '; '.join('%s r%d: %s' % (r['config'], r['rep'], r['failed'])
                                                      for r in failed)
    lines = []
    for config in CONFIGS:
        these = [r for r in ok if r['config'] == config]
        if not these:
            continue
        by_process = {}
        for run in these:
            for row in process_costs(run):
                by_process.setdefault((row['kind'], row['process']), []).append(row)
        for (kind, process), rows in sorted(by_process.items()):
            windows = [w for r in rows for w in r['windows']]
            lines.append([config, process if kind == 'layer' else '*%s*' % process,
                          med_range([r.get('recording') for r in rows], 2),
                          '%s..%s' % _span(windows), med_range([r['hwm_mb'] for r in rows], 1),
                          med_range([r.get('rotating') for r in rows], 2),
                          med_range([r.get('returning') for r in rows], 2)])
    text += ('CPU % of one core and peak resident memory (VmHWM, MiB) per process; median '
             '[min..max] over the repetitions; while recording: the whole window, and the range '
             'over its 10 s windows; standstill + pi turn (`rotating`) and the return '
             '(`returning`) as long as each took.\n\n')
    text += markdown_table(['config', 'process', 'CPU % recording', 'per window', 'peak RSS MiB',
                            'CPU % rotating', 'CPU % returning'], lines)
    text += '\n' + summary_table(ok)
    return text


def _span(values):
    values = [v for v in values if v is not None]
    return ('%.2f' % min(values), '%.2f' % max(values)) if values else ('—', '—')


def summary_table(ok):
    """Each config's layer total against the bag of the same run, and the targets."""
    lines = []
    for config, (what, _, _) in CONFIGS.items():
        these = [totals(r) for r in ok if r['config'] == config]
        if not these:
            continue
        cpu_ratio = [ratio(t['layer_recording'], t['bag_recording']) for t in these]
        rss_ratio = [ratio(t['layer_hwm_mb'], t['bag_hwm_mb']) for t in these]
        lines.append([config, these[0]['layer_processes'], len(these),
                      med_range([t['layer_recording'] for t in these], 2),
                      med_range([t['bag_recording'] for t in these], 2),
                      med_range(cpu_ratio, 2), med_range([t['layer_hwm_mb'] for t in these], 1),
                      med_range([t['bag_hwm_mb'] for t in these], 1), med_range(rss_ratio, 2),
                      med_range([t['layer_returning'] for t in these], 2),
                      _verdict(config, these)])
    return ('The layer (its processes summed) at rtf 1 on %s, beside `rosbag record /odom` on '
            'the same stream in the same run (the C++ recorder; its Python wrapper is listed '
            'above, not counted); per run, then median [min..max]; the budget (issue 30) is judged '
            'on the worst run of each one-process layer:\n\n' % cpu_model()
            + markdown_table(['config', 'processes', 'runs', 'layer CPU % recording', 'bag CPU %',
                              'CPU ratio', 'layer peak RSS MiB', 'bag peak RSS MiB', 'RSS ratio',
                              'layer CPU % returning', 'budget'], lines))


def _verdict(config, these):
    """The budget of :data:`BUDGET` against the worst run of a one-process default layer."""
    if config != 'default':
        return '(no budget)'
    def check(values, limit, what, unit):
        values = [v for v in values if v is not None]
        if not values:
            return '%s: not measured' % what
        worst = max(values)
        return '%s <= %g%s: %s (%.2f)' % (what, round(limit, 1), unit,
                                         'met' if worst <= limit else 'MISSED', worst)
    return '; '.join([check([t['layer_recording'] for t in these], BUDGET['recording_cpu'],
                            'recording', ' %'),
                      check([t['layer_returning'] for t in these], BUDGET['returning_cpu'],
                            'returning', ' %'),
                      check([t['layer_hwm_mb'] for t in these], BUDGET['rss_mib'], 'RSS', ' MiB')])


def latency_runs(out_dir, seeds, warmup=15.0):
    """Each fake vision failure x detector set x seed, default launch: the time from the
    failure to blind_navigation/vision_lost."""
    runs = []
    for seed in seeds:
        for failure in FAILURES:
            for detectors, launch_args in DETECTOR_SETS.items():
                slug = 'dark_images' if launch_args else 'default'
                log('latency run: %s failure, %s detectors, seed %d' % (failure, slug, seed))
                result = run_once(os.path.join(out_dir, 'latency_%s_%s_s%d' % (failure, slug, seed)),
                                  dict(launch_args, layout='blind_navigation', seed=str(seed),
                                       vision_failure=failure),
                                  ['--warmup', str(warmup), '--windows', '0', '--until', 'vision_lost'],
                                  timeout=warmup + 240.0, drive_s=warmup + 3.0)
                result.update(failure=failure, detectors=detectors, seed=seed)
                runs.append(result)
    return runs


def latency_table(runs):
    lines = []
    for failure in FAILURES:
        for detectors in DETECTOR_SETS:
            these = [r for r in runs if r['failure'] == failure and r['detectors'] == detectors]
            ok = [r for r in these if 'failed' not in r and r.get('latency') is not None]
            lines.append([failure, detectors, '%d of %d' % (len(ok), len(these)),
                          ', '.join(sorted({r['detector'] or '?' for r in ok})) or '—',
                          med_range([r['latency'] for r in ok], 3),
                          ', '.join(str(r['seed']) for r in these)])
    return ('Wall time from the failure (fake_turtlebot/set_vision false) to '
            'blind_navigation/vision_lost, default launch at rtf 1, 640x480 camera; median '
            '[min..max] over the seeds:\n\n'
            + markdown_table(['fake failure', 'detectors', 'runs detected', 'detector that fired',
                              'latency s', 'seeds'], lines))


def section(out_dir, configs=tuple(CONFIGS), reps=3, windows=6, window=10.0, latency_seeds=3):
    """The whole cost section: (Markdown text, run results)."""
    runs = cost_runs(out_dir, configs, reps, windows, window) if reps > 0 else []
    latency = latency_runs(out_dir, range(latency_seeds)) if latency_seeds > 0 else []
    text = ''
    if runs:
        text += cost_tables(runs)
    if latency:
        text += '\n### Detection latency\n\n' + latency_table(latency)
    slim = [{k: v for k, v in r.items() if k != 'marks'} for r in runs + latency]
    with open(os.path.join(out_dir, 'cost_runs.json'), 'w') as stream:
        json.dump(runs + latency, stream, indent=1)
    return text, slim


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--configs', default=','.join(CONFIGS),
                        help='comma-separated of %s' % ', '.join(CONFIGS))
    parser.add_argument('--reps', type=int, default=3, help='runs of each config')
    parser.add_argument('--windows', type=int, default=6, help='measurement windows while recording')
    parser.add_argument('--window', type=float, default=10.0, help='s per window')
    parser.add_argument('--latency-seeds', type=int, default=3,
                        help='seeds of the detection latency runs (0: none)')
    parser.add_argument('--out', default='results/cost')
    args = parser.parse_args(argv)
    configs = [c for c in args.configs.split(',') if c]
    unknown = [c for c in configs if c not in CONFIGS]
    if unknown:
        parser.error('unknown config(s) %s; known: %s' % (', '.join(unknown), ', '.join(CONFIGS)))
    os.makedirs(args.out, exist_ok=True)
    text, _ = section(args.out, configs, args.reps, args.windows, args.window, args.latency_seeds)
    with open(os.path.join(args.out, 'cost.md'), 'w') as stream:
        stream.write('## The layer\'s running cost (real time)\n\n' + text)
    print(text)


if __name__ == '__main__':
    main()
