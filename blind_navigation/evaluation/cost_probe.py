"""The probe of one real-time cost run (evaluation/cost.py, docs/cost.md).

A plain process beside ``cost.launch``: starts ``rosbag record /odom``, starts the drive
once the layer records, finds the layer's processes (getPid), snapshots their CPU time,
VmRSS and VmHWM every ``window`` s and at each state change, optionally makes vision
fail and times ``vision_lost``; writes JSON to ``--out``.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time
import xmlrpc.client

import psutil
import rosgraph
import rospy
from std_msgs.msg import Bool, Empty, String
from std_srvs.srv import SetBool

from blind_navigation import names
from blind_navigation.core.mission_state import TERMINAL
from blind_navigation.msg import StorageUsage
from blind_navigation.sim.node_common import MISSION_DONE, MISSION_GO, SET_VISION

#: The fake TurtleBot's nodes (launch/fake_turtlebot.launch) and the master's own: not the layer.
NOT_LAYER = ('/mobile_base', '/cmd_vel_mux', '/fake_vision', '/mission_driver', '/rosout')
#: Where the vision monitor latches the detector that fired: alone, and hosted in the one process.
LOSS_TOPICS = ('/vision_monitor/loss', '/blind_navigation/loss')
UNTIL = ('windows', 'vision_lost', 'recording_end', 'home')


def proc_status_kb(pid, field):
    """A ``kB`` field of /proc/<pid>/status (VmRSS, VmHWM), or None when the process is gone."""
    try:
        with open('/proc/%d/status' % pid) as stream:
            for line in stream:
                if line.startswith(field + ':'):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def snapshot(processes):
    """{name: {'cpu_s', 'rss_kb', 'hwm_kb', 'threads'}} of ``processes`` ({name: psutil.Process}),
    those still alive."""
    out = {}
    for name, process in processes.items():
        try:
            with process.oneshot():
                times = process.cpu_times()
                threads = process.num_threads()
        except psutil.Error:
            continue
        out[name] = {'cpu_s': times.user + times.system, 'threads': threads,
                     'rss_kb': proc_status_kb(process.pid, 'VmRSS'),
                     'hwm_kb': proc_status_kb(process.pid, 'VmHWM')}
    return out


class Bag(object):
    """``rosbag record -O path /odom``: the wrapper and the C++ recorder it spawns."""

    def __init__(self, path):
        self.process = subprocess.Popen(['rosbag', 'record', '-O', path, names.ODOM],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        start_new_session=True)
        self.wrapper = psutil.Process(self.process.pid)
        self.recorder = None

    def find_recorder(self, timeout):
        """The C++ ``record`` child, or RuntimeError after ``timeout`` s."""
        deadline = time.monotonic() + timeout
        while self.recorder is None:
            children = [c for c in self.wrapper.children() if os.path.basename(c.exe()) == 'record']
            if children:
                self.recorder = children[0]
            elif time.monotonic() > deadline or self.process.poll() is not None:
                raise RuntimeError('rosbag record did not start its recorder (exit %s)'
                                   % self.process.poll())
            else:
                time.sleep(0.1)
        return self.recorder

    def stop(self):
        if self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGINT)
            try:
                self.process.wait(20)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)


class CostProbe(object):
    """One run (module docstring); ``args`` from :func:`parser`."""

    def __init__(self, args):
        self.args = args
        self.master = rosgraph.Master(rospy.get_name())
        self.lock = threading.Lock()
        self.state = None
        self.state_times = {}
        self.marks = []
        self.processes = {}
        self.kinds = {}
        self.detector = ''
        self.storage_after_recording = None
        self.mission_done = False
        self.times = {}
        rospy.Subscriber(names.STATE, String, self._on_state, queue_size=10)
        rospy.Subscriber(names.VISION_LOST, Empty, self._on_vision_lost, queue_size=1)
        rospy.Subscriber(MISSION_DONE, Bool, self._on_done, queue_size=1)
        rospy.Subscriber(names.STORAGE, StorageUsage, self._on_storage, queue_size=10)
        for topic in LOSS_TOPICS:
            rospy.Subscriber(topic, String, self._on_loss, queue_size=1)
        self.go = rospy.Publisher(MISSION_GO, Empty, queue_size=1, latch=True)

    # --- what the layer says --------------------------------------------------------------------
    def _on_state(self, msg):
        with self.lock:
            changed = msg.data != self.state
            self.state = msg.data
            self.state_times.setdefault(msg.data, rospy.get_time())
        if changed and self.processes:
            self.mark('state ' + msg.data)

    def _on_vision_lost(self, _msg):
        self.times.setdefault('vision_lost', rospy.get_time())

    def _on_loss(self, msg):
        self.detector = msg.data.split(':', 1)[0]

    def _on_done(self, msg):
        self.mission_done = self.mission_done or msg.data

    def _on_storage(self, msg):
        if self.state is not None and self.state != 'recording':
            self.storage_after_recording = {'landmarks': msg.landmarks, 'bytes': msg.bytes,
                                            'distance': msg.distance, 'file': msg.file}

    # --- measuring ------------------------------------------------------------------------------
    def mark(self, label):
        """Snapshot every measured process now, under ``label``."""
        with self.lock:
            self.marks.append({'label': label, 't': rospy.get_time(), 'load': os.getloadavg()[0],
                               'processes': snapshot(self.processes)})

    def wait(self, condition, timeout, what):
        deadline = time.monotonic() + timeout
        while not condition():
            if rospy.is_shutdown():
                raise RuntimeError('shut down while waiting for %s' % what)
            if time.monotonic() > deadline:
                raise RuntimeError('timed out after %.0f s waiting for %s (state %s)'
                                   % (timeout, what, self.state))
            time.sleep(0.05)

    def layer_processes(self):
        """{node name: psutil.Process} of every node on the master that is not the fake's,
        rosout, the bag's recorder or this probe."""
        publishers, subscribers, services = self.master.getSystemState()
        nodes = {node for _, listed in publishers + subscribers + services for node in listed}
        found = {}
        skip = set(NOT_LAYER) | {rospy.get_name()}
        bag_pid = self.bag.recorder.pid
        for node in sorted(nodes - skip):
            _, _, pid = xmlrpc.client.ServerProxy(self.master.lookupNode(node)).getPid(rospy.get_name())
            if pid != bag_pid:
                found[node] = psutil.Process(pid)
        return found

    def bag_listens(self):
        _, subscribers, _ = self.master.getSystemState()
        odom = rospy.resolve_name(names.ODOM)
        for topic, nodes in subscribers:
            if topic == odom:
                for node in nodes:
                    uri = self.master.lookupNode(node)
                    if xmlrpc.client.ServerProxy(uri).getPid(rospy.get_name())[2] == self.bag.recorder.pid:
                        return True
        return False

    def run(self):
        a = self.args
        self.bag = Bag(a.bag)
        try:
            self.bag.find_recorder(60.0)
            self.wait(lambda: self.state == 'recording', a.start_timeout, 'the layer to record')
            self.wait(self.bag_listens, a.start_timeout, 'rosbag record to subscribe to /odom')
            self.go.publish(Empty())
            self.times['go'] = rospy.get_time()
            time.sleep(a.warmup)
            self.processes = dict(self.layer_processes(), **{
                'rosbag record (C++ recorder)': self.bag.recorder,
                'rosbag (Python wrapper)': self.bag.wrapper})
            self.kinds = {name: ('bag' if name.startswith('rosbag record') else
                                 'bag_wrapper' if name.startswith('rosbag (') else 'layer')
                          for name in self.processes}
            start = time.monotonic()
            for index in range(a.windows + 1):
                time.sleep(max(0.0, start + index * a.window - time.monotonic()))
                self.mark('recording %d' % index)
            if a.until != 'windows':
                self.fail_and_follow()
        finally:
            self.bag.stop()
        self.write()

    def fail_and_follow(self):
        a = self.args
        self.wait(lambda: self.mission_done, a.drive_timeout, 'the scripted drive to end')
        time.sleep(a.settle)
        rospy.wait_for_service(SET_VISION, timeout=30.0)
        self.times['failure'] = rospy.get_time()
        rospy.ServiceProxy(SET_VISION, SetBool)(False)
        self.wait(lambda: 'vision_lost' in self.times, a.detect_timeout, 'vision_lost')
        if a.until == 'recording_end':
            self.wait(lambda: self.state != 'recording' and self.storage_after_recording,
                      a.detect_timeout + 30.0, 'the final landmark')
        elif a.until == 'home':
            self.wait(lambda: self.state in TERMINAL, a.return_timeout, 'state home or aborted')
            time.sleep(a.settle)
            self.mark('after ' + self.state)

    def write(self):
        t = self.times
        result = {
            'args': vars(self.args), 'kinds': self.kinds, 'marks': self.marks,
            'pids': {name: p.pid for name, p in self.processes.items()},
            'state_times': self.state_times, 'times': t, 'detector': self.detector,
            'latency': t['vision_lost'] - t['failure'] if 'vision_lost' in t and 'failure' in t else None,
            'final_state': self.state, 'storage': self.storage_after_recording,
        }
        with open(self.args.out, 'w') as stream:
            json.dump(result, stream, indent=1)


def parser():
    p = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    p.add_argument('--out', required=True, help='JSON result file')
    p.add_argument('--bag', required=True, help='the bag rosbag record writes')
    p.add_argument('--warmup', type=float, default=10.0, help='s of recording before the first mark')
    p.add_argument('--windows', type=int, default=6, help='measurement windows while recording')
    p.add_argument('--window', type=float, default=10.0, help='s per window')
    p.add_argument('--until', choices=UNTIL, default='home', help='what ends the run')
    p.add_argument('--settle', type=float, default=2.0, help='s after the drive and after the end')
    p.add_argument('--start-timeout', type=float, default=120.0)
    p.add_argument('--drive-timeout', type=float, default=4000.0)
    p.add_argument('--detect-timeout', type=float, default=30.0)
    p.add_argument('--return-timeout', type=float, default=900.0)
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    rospy.init_node('cost_probe', disable_signals=True)
    try:
        CostProbe(args).run()
    except RuntimeError as error:
        print('cost_probe: %s' % error, file=sys.stderr)
        return 1
    finally:
        rospy.signal_shutdown('done')
    return 0


if __name__ == '__main__':
    sys.exit(main())
