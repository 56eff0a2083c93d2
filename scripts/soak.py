#!/usr/bin/env python3
"""Soak run of the recording layer under sim time (issue 6): a long mission
(default one hour of sim time) with 50 Hz odometry, recorded by the real
sampling_publisher + landmark_saver on a private roscore; reports the saver's
and the publisher's resident memory (RSS) at the start and the end, and checks
the recording: every landmark valid, the count matching the sampling rates,
the summed d matching the driven path length.

    /usr/bin/python3 scripts/soak.py [--duration 3600] [--rtf 10] [--out results/soak.md]

Needs the built workspace (source scripts/ros_env.sh first). Exit status 0 when
the recording is correct and the RSS growth is within --max-growth-mb.
The odometry drives laps of a rounded square (20 s straight at 0.1 m/s, then a
90 degree left arc at 0.1 rad/s), integrated exactly.
"""
import argparse
import math
import os
import socket
import subprocess
import sys
import tempfile
import time

SPEED, TURN_RATE, STRAIGHT_TIME = 0.1, 0.1, 20.0
ARC_TIME = (math.pi / 2) / TURN_RATE
LAP_TIME = 4 * (STRAIGHT_TIME + ARC_TIME)


def pose_at(t):
    """(x, y, yaw, v, w) on the lap path at t s (exact unicycle integration)."""
    x = y = yaw = 0.0
    laps, t_lap = divmod(t, LAP_TIME)
    del laps                      # each lap ends where it started
    for _ in range(4):
        step = min(t_lap, STRAIGHT_TIME)
        x, y = x + SPEED * step * math.cos(yaw), y + SPEED * step * math.sin(yaw)
        t_lap -= step
        if t_lap <= 0:
            return x, y, yaw, SPEED, 0.0
        step = min(t_lap, ARC_TIME)
        radius = SPEED / TURN_RATE
        end = yaw + TURN_RATE * step
        x, y = x + radius * (math.sin(end) - math.sin(yaw)), y - radius * (math.cos(end) - math.cos(yaw))
        yaw = end
        t_lap -= step
        if t_lap <= 0:
            return x, y, yaw, SPEED, TURN_RATE
    return x, y, yaw, SPEED, 0.0


def rss_kb(pid):
    with open('/proc/%d/status' % pid) as stream:
        for line in stream:
            if line.startswith('VmRSS:'):
                return int(line.split()[1])
    return 0


def free_port():
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        return sock.getsockname()[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--duration', type=float, default=3600.0, help='sim seconds recorded')
    parser.add_argument('--rtf', type=float, default=10.0, help='sim time / wall time')
    parser.add_argument('--max-growth-mb', type=float, default=10.0,
                        help='largest accepted RSS growth of each node, MB')
    parser.add_argument('--out', default='', help='also write the report (markdown) here')
    args = parser.parse_args()

    port = free_port()
    os.environ['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % port
    work = tempfile.mkdtemp(prefix='bn_soak_')
    os.environ['ROS_HOME'] = work
    roscore = subprocess.Popen(['roscore', '-p', str(port)], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, start_new_session=True)
    nodes = []
    try:
        import roslib.packages
        import rosgraph
        import rospy
        from nav_msgs.msg import Odometry
        from rosgraph_msgs.msg import Clock
        from std_msgs.msg import Empty
        deadline = time.monotonic() + 60
        while not rosgraph.is_master_online():
            if time.monotonic() > deadline:
                raise SystemExit('soak: roscore did not start on port %d' % port)
            time.sleep(0.2)
        rospy.set_param('/use_sim_time', True)
        link = os.path.join(work, 'landmarks.yaml')
        for node_type, params in (('landmark_saver.py', ['_landmark_file:=' + link, '_fsync:=false']),
                                  ('sampling_publisher.py', [])):
            found = roslib.packages.find_node('blind_navigation', node_type)
            if not found:
                raise SystemExit('soak: %s not found (build the workspace and source '
                                 'scripts/ros_env.sh)' % node_type)
            nodes.append(subprocess.Popen([found[0]] + params, stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL, start_new_session=True))
        rospy.init_node('soak', disable_signals=True)
        clock = rospy.Publisher('/clock', Clock, queue_size=10)
        odom = rospy.Publisher('/odom', Odometry, queue_size=100)
        base, dt = 100.0, 0.02
        clock.publish(Clock(clock=rospy.Time.from_sec(base)))
        deadline = time.monotonic() + 60
        while odom.get_num_connections() < 2 or not os.path.islink(link):
            if time.monotonic() > deadline:
                raise SystemExit('soak: the recording nodes did not subscribe to /odom')
            clock.publish(Clock(clock=rospy.Time.from_sec(base)))
            time.sleep(0.1)
        rss = {}
        names = ('landmark_saver', 'sampling_publisher')
        steps = int(round(args.duration / dt))
        warmup = min(steps // 10, int(60.0 / dt))
        wall_start = time.monotonic()
        msg = Odometry()
        msg.header.frame_id, msg.child_frame_id = 'odom', 'base_footprint'
        for step in range(steps + 1):
            t = step * dt
            stamp = rospy.Time.from_sec(base + t)
            clock.publish(Clock(clock=stamp))
            x, y, yaw, v, w = pose_at(t)
            msg.header.stamp = stamp
            msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
            msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
            msg.twist.twist.linear.x, msg.twist.twist.angular.z = v, w
            odom.publish(msg)
            if step == warmup or step == steps or (step > warmup and step % int(600 / dt) == 0):
                for name, process in zip(names, nodes):
                    if process.poll() is not None:
                        raise SystemExit('soak: %s died (exit %s)' % (name, process.returncode))
                    rss.setdefault(name, []).append((t, rss_kb(process.pid)))
            ahead = wall_start + (step + 1) * dt / args.rtf - time.monotonic()
            if ahead > 0:
                time.sleep(ahead)
        wall = time.monotonic() - wall_start
        rospy.Publisher('/blind_navigation/vision_lost', Empty, queue_size=1, latch=True).publish(Empty())
        for extra in range(int(5.0 / dt)):     # the clock keeps running for the final landmark
            clock.publish(Clock(clock=rospy.Time.from_sec(base + args.duration + extra * dt)))
            time.sleep(dt / args.rtf)
        report = check(link, args, rss, names, wall)
    finally:
        for process in nodes + [roscore]:
            if process.poll() is None:
                os.killpg(process.pid, 2)
                try:
                    process.wait(20)
                except subprocess.TimeoutExpired:
                    os.killpg(process.pid, 9)
    text, ok = report
    print(text)
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out, 'w') as stream:
            stream.write(text + '\n')
    return 0 if ok else 1


def check(link, args, rss, names, wall):
    """The report text and whether the recording and memory are fine."""
    sys.path.insert(0, os.path.abspath(os.path.join(os.path.dirname(__file__), '..')))
    from blind_navigation.core.store import load_landmarks
    loaded = load_landmarks(link)
    landmarks = loaded.landmarks
    recorded = sum(lm.d for lm in landmarks)
    duration = sum(lm.T for lm in landmarks)
    straight = sum(1 for lm in landmarks if lm.T > 1.5)
    curved = len(landmarks) - straight
    problems = []
    driven = SPEED * args.duration      # recording runs from the clock's start to vision loss
    if abs(duration - args.duration) > 0.01 * args.duration:
        problems.append('landmark periods sum to %.1f s, mission %.1f s' % (duration, args.duration))
    if abs(recorded - driven) > 0.01 * driven:
        problems.append('summed d %.2f m vs driven %.2f m' % (recorded, driven))
    if any(abs(lm.v - SPEED) > 1e-3 for lm in landmarks[1:-1]):
        problems.append('a landmark speed differs from the odometry')
    lines = ['# Soak run (scripts/soak.py)', '',
             'sim %.0f s at rtf %.0f (%.0f s wall), odometry 50 Hz: %d landmarks (%d straight, '
             '%d curved), periods sum to %.1f s, %.1f KB, summed d %.2f m of %.2f m driven (%+.3f %%)'
             % (args.duration, args.rtf, wall, len(landmarks), straight, curved, duration,
                os.path.getsize(os.path.realpath(link)) / 1024.0, recorded, driven,
                100.0 * (recorded / driven - 1.0)), '',
             '| node | RSS start (after %.0f s sim), MB | RSS end, MB | growth, MB | samples (sim s: MB) |'
             % rss[names[0]][0][0], '|---|---|---|---|---|']
    for name in names:
        samples = rss[name]
        growth = (samples[-1][1] - samples[0][1]) / 1024.0
        if growth > args.max_growth_mb:
            problems.append('%s grew by %.1f MB' % (name, growth))
        lines.append('| %s | %.1f | %.1f | %+.2f | %s |' % (
            name, samples[0][1] / 1024.0, samples[-1][1] / 1024.0, growth,
            ', '.join('%.0f: %.1f' % (t, kb / 1024.0) for t, kb in samples)))
    lines += ['', 'result: ' + ('OK' if not problems else 'FAILED: ' + '; '.join(problems))]
    return '\n'.join(lines), not problems


if __name__ == '__main__':
    sys.exit(main())
