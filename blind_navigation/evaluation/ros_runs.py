"""ROS runs of the bench: ``roslaunch blind_navigation bench.launch`` (fake
TurtleBot + the layer + ``rosbag record /odom`` + bench_probe), one master per
run on a free port, read back from the probe's JSON and the bag."""
import json
import os
import signal
import socket
import subprocess
import time

from .montecarlo import CALIBRATION_SEED_OFFSET, recording_settings


def free_port():
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        return sock.getsockname()[1]


def bag_summary(path):
    """{'bytes', 'messages', 'duration'} of a bag file, or None if it is missing."""
    if not os.path.exists(path):
        return None
    import rosbag
    with rosbag.Bag(path) as bag:
        return {'bytes': os.path.getsize(path), 'messages': bag.get_message_count(),
                'duration': bag.get_end_time() - bag.get_start_time()}


def log_findings(path):
    """From a launch log: the back-travel client's abort reason ('' if none), how
    often the fake base logged that it fell behind real time (machine overload),
    and the last state the client logged."""
    reason, behind, state = '', 0, ''
    with open(path, errors='replace') as stream:
        for line in stream:
            if 'behind real time' in line:
                behind += 1
            if 'back_travel_client: state ' in line and ' -> ' in line:
                state = line.split(' -> ', 1)[1].split(':')[0].strip()
            if '-> aborted:' in line and not reason:
                reason = line.split('-> aborted:', 1)[1].strip()
    return reason, behind, state


def _roslaunch(command, log, timeout):
    """Run ``command`` (roslaunch ...) in its own session, output to ``log``; SIGINT,
    then SIGKILL, after ``timeout`` wall s. Returns (exit code, wall s)."""
    started = time.time()
    with open(log, 'w') as stream:
        process = subprocess.Popen(command, stdout=stream, stderr=subprocess.STDOUT,
                                   start_new_session=True)
        try:
            process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            stop_group(process)
    return process.returncode, time.time() - started


def stop_group(process):
    """SIGINT to the process group of ``process`` (started with start_new_session), SIGKILL
    after 20 s; nothing if it has ended."""
    if process is None or process.poll() is not None:
        return
    os.killpg(process.pid, signal.SIGINT)
    try:
        process.wait(timeout=20)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()


def calibrate_ros(out_dir, seed=0, rtf=10.0, timeout=300.0):
    """The gyro calibration missions of ``seed`` use (fake_gyro_calibration.launch on
    seed + CALIBRATION_SEED_OFFSET, as the harness's); its file path, or None if
    it failed (the log says why)."""
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, 'gyro_calibration_s%d.yaml' % seed)
    if os.path.exists(path):
        os.remove(path)
    _roslaunch(['roslaunch', '-p', str(free_port()), 'blind_navigation', 'fake_gyro_calibration.launch',
                'seed:=%d' % (seed + CALIBRATION_SEED_OFFSET), 'rtf:=%g' % rtf,
                'calibration_file:=%s' % path],
               os.path.join(out_dir, 'gyro_calibration_s%d.log' % seed), timeout)
    return path if os.path.exists(path) else None


def run_ros(out_dir, scenario, control, seed=0, rtf=5.0, vision_failure='dark', start_delay=None,
            bag=True, timeout=600.0, return_timeout=400.0, gyro_calibration_file='', name=None,
            mission=None, launch_args=(), case=''):
    """One bench.launch run, the mode in its launch configuration
    (montecarlo.recording_settings; the heading correction, when on, with
    ``gyro_calibration_file``); returns the probe's result dict (+ 'bag',
    'wall_s', 'log') or {'failed': reason, ...} if the launch produced no result. ``scenario``: a
    mission name (or a label, with ``mission`` an absolute mission file's path); ``name``: the
    run's directory under ``out_dir`` (default from the rest); ``launch_args``: more
    ``name:=value`` for bench.launch; ``case``: bench_probe's (evaluation/survival.py)."""
    name = name or '%s_%s_s%d_%s%s' % (scenario, control, seed, vision_failure,
                                       '_' + case if case else '')
    run_dir = os.path.join(out_dir, name)
    os.makedirs(run_dir, exist_ok=True)
    out, bag_path, log = (os.path.join(run_dir, f) for f in ('probe.json', 'odom.bag', 'launch.log'))
    for stale in (out, bag_path):
        if os.path.exists(stale):
            os.remove(stale)
    start_delay = 3.0 * rtf if start_delay is None else start_delay
    command = ['roslaunch', '-p', str(free_port()), 'blind_navigation', 'bench.launch',
               'scenario:=%s' % scenario, 'control:=%s' % control, 'seed:=%d' % seed,
               'rtf:=%g' % rtf, 'vision_failure:=%s' % vision_failure,
               'start_delay:=%g' % start_delay, 'out:=%s' % out, 'results_dir:=%s' % run_dir,
               'landmark_file:=%s' % os.path.join(run_dir, 'landmarks', 'landmarks.yaml'),
               'return_timeout:=%g' % return_timeout, 'bag:=%s' % (bag_path if bag else ''),
               'case:=%s' % (case or 'none')]
    if mission:
        command.append('mission:=%s' % mission)
    command.extend(launch_args)
    settings = recording_settings(control)
    if 'deadband' in settings:
        command.append('deadband:=%g' % settings['deadband'])
    heading_correction = settings.get('heading_correction', True)
    command.append('heading_correction:=%s' % str(heading_correction).lower())
    if heading_correction:
        command.append('gyro_calibration_file:=%s' % gyro_calibration_file)
    returncode, wall = _roslaunch(command, log, timeout)
    reason, behind, state = log_findings(log)
    if not os.path.exists(out):
        return {'failed': 'no result after %.0f s wall (exit %s), last state %r, see %s'
                          % (wall, returncode, state, log),
                'mission': scenario, 'mode': control, 'seed': seed, 'detector': vision_failure,
                'wall_s': wall, 'log': log}
    with open(out) as stream:
        result = json.load(stream)
    result.update({'bag': bag_summary(bag_path) if bag else None, 'wall_s': wall, 'log': log,
                   'abort_reason': reason, 'behind_real_time': behind,
                   'vision_failure': vision_failure, 'rtf_requested': rtf})
    return result
