"""ROS runs of the bench: ``roslaunch blind_navigation bench.launch`` (fake
TurtleBot + the layer + ``rosbag record /odom`` + bench_probe), one master per
run on a free port, read back from the probe's JSON and the bag."""
import json
import os
import signal
import socket
import subprocess
import time


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


def run_ros(out_dir, scenario, control, seed=0, rtf=5.0, vision_failure='dark', start_delay=None,
            bag=True, timeout=600.0):
    """One bench.launch run; returns the probe's result dict (+ 'bag', 'wall_s', 'log')
    or {'failed': reason, ...} if the launch did not produce a result."""
    name = '%s_%s_s%d_%s' % (scenario, control, seed, vision_failure)
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
               'bag:=%s' % (bag_path if bag else '')]
    started = time.time()
    with open(log, 'w') as stream:
        process = subprocess.Popen(command, stdout=stream, stderr=subprocess.STDOUT,
                                   start_new_session=True)
        try:
            process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGINT)
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
    wall = time.time() - started
    if not os.path.exists(out):
        return {'failed': 'no result after %.0f s (exit %s), see %s' % (wall, process.returncode, log),
                'mission': scenario, 'mode': control, 'seed': seed, 'detector': vision_failure,
                'wall_s': wall, 'log': log}
    with open(out) as stream:
        result = json.load(stream)
    result.update({'bag': bag_summary(bag_path) if bag else None, 'wall_s': wall, 'log': log,
                   'vision_failure': vision_failure, 'rtf_requested': rtf})
    return result
