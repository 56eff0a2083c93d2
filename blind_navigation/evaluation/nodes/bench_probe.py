#!/usr/bin/env python3
"""bench_probe: the demo observer (evaluation/observer.py) plus what `make bench` measures.

Also measures the detection latency and the first rotation command, the layer's and the
bag's CPU and RSS while recording, the achieved rtf, the goals' hand-over gaps and the
return's commands, and how the recording lines up with the mission; writes JSON to
``out``. ``case`` ``brief``/``bump``: evaluation/survival.py drives the mission.
"""
import json
import os
import signal
import time
import xmlrpc.client

import psutil
import rosgraph
import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Empty, String

from blind_navigation import names
from blind_navigation.core.geometry import distance
from blind_navigation.core.mission_state import TERMINAL
from blind_navigation.core.store import load_landmarks
from blind_navigation.evaluation import survival
from blind_navigation.evaluation.observer import DemoObserver, main as observe
from blind_navigation.msg import BackTravelActionGoal, BackTravelActionResult
from blind_navigation.sim.node_common import SET_VISION

#: The layer as blind_navigation.launch starts it by default: every role in one node, so the
#: pi turn's commands and the vision monitor's ~loss come from that node (with
#: one_process:=false set layer_nodes, rotation_node '/rotate_pi', monitor_node '/vision_monitor').
LAYER_NODE = '/blind_navigation'
LAYER_NODES = [LAYER_NODE.lstrip('/')]


class BenchProbe(DemoObserver):
    __doc__ = __doc__
    DEFAULTS = dict(DemoObserver.DEFAULTS, out='', layer_nodes=LAYER_NODES, bag_node='odom_bag',
                    cmd_vel_topic='/cmd_vel_mux/input/teleop', rotation_node=LAYER_NODE,
                    monitor_node=LAYER_NODE, mission_node='/mission_driver',
                    landmark_file='', seed=0, case='')

    def __init__(self):
        super(BenchProbe, self).__init__()
        p = self.params
        self.times = {}
        self.detector = ''
        self.processes = {}
        self.peak_rss = {}
        self.states = []
        self.speed = None
        self.case_findings = {}
        rospy.Subscriber(names.VISION_LOST, Empty, self._on_vision_lost)
        rospy.Subscriber(p.cmd_vel_topic, Twist, self._on_cmd_vel)
        rospy.Subscriber(p.monitor_node + '/loss', String, self._on_loss)
        self.goal_stamps, self.result_stamps, self.return_commands = [], [], []
        rospy.Subscriber(names.BACK_TRAVEL + '/goal', BackTravelActionGoal,
                         lambda msg: self.goal_stamps.append(msg.goal_id.stamp.to_sec()))
        rospy.Subscriber(names.BACK_TRAVEL + '/result', BackTravelActionResult,
                         lambda msg: self.result_stamps.append(msg.header.stamp.to_sec()))

    def _stamp(self, key):
        if key not in self.times:
            self.times[key] = rospy.Time.now().to_sec()

    def _on_state(self, msg):
        super(BenchProbe, self)._on_state(msg)
        if not self.states or self.states[-1] != msg.data:
            self.states.append(msg.data)

    def _on_truth(self, msg):
        super(BenchProbe, self)._on_truth(msg)
        twist = msg.twist.twist
        self.speed = (twist.linear.x ** 2 + twist.linear.y ** 2) ** 0.5

    def _on_vision_lost(self, _msg):
        self._stamp('trigger')

    def _on_loss(self, msg):
        self.detector = msg.data.split(':', 1)[0]

    def _on_cmd_vel(self, msg):
        caller = msg._connection_header.get('callerid', '')
        if caller == self.params.mission_node and (msg.linear.x != 0.0 or msg.angular.z != 0.0):
            self._stamp('mission_start')
        if caller == self.params.rotation_node and msg.angular.z != 0.0 and 'trigger' in self.times:
            self._stamp('rotation')
        if caller == self.params.rotation_node and self.state == 'returning':
            self.return_commands.append((rospy.Time.now().to_sec(), msg.linear.x, msg.angular.z))

    # ------------------------------------------------------------ processes
    def find_processes(self):
        """{node name: psutil.Process} of the layer's nodes and the bag recorder."""
        master = rosgraph.Master(rospy.get_name())
        names = list(self.params.layer_nodes) + ([self.params.bag_node] if self.params.bag_node else [])
        for name in names:
            try:
                uri = master.lookupNode('/' + name.lstrip('/'))
                _, _, pid = xmlrpc.client.ServerProxy(uri).getPid(rospy.get_name())
                self.processes[name] = psutil.Process(pid)
            except (rosgraph.MasterError, OSError, psutil.Error) as error:
                rospy.logwarn('bench_probe: no process for node %s: %s', name, error)

    def cpu_snapshot(self):
        """{name: CPU seconds (user + system)}, and the peak RSS updated."""
        out = {}
        for name, process in self.processes.items():
            try:
                times = process.cpu_times()
                out[name] = times.user + times.system
                self._sample_rss(name, process)
            except psutil.Error:
                pass
        return out

    def _sample_rss(self, name, process):
        self.peak_rss[name] = max(self.peak_rss.get(name, 0), process.memory_info().rss)

    def _sample_all_rss(self, _event=None):
        for name, process in list(self.processes.items()):
            try:
                self._sample_rss(name, process)
            except psutil.Error:
                pass

    # ------------------------------------------------------------------ run
    def run(self):
        p = self.params
        self.wait(lambda: self.state == 'recording', 600.0, 'state recording')
        self._stamp('recording_state')
        self.find_processes()
        rss_timer = rospy.Timer(rospy.Duration(0.5), self._sample_all_rss)
        cpu_start, wall_start, sim_start = self.cpu_snapshot(), time.time(), rospy.Time.now().to_sec()
        rospy.wait_for_service(SET_VISION, timeout=30.0)
        from std_srvs.srv import SetBool
        set_vision = rospy.ServiceProxy(SET_VISION, SetBool)
        if p.case:      # its own script (the loss may come mid-mission): no one failure, no latency
            self.case_findings = survival.run_case(self, set_vision)
            self.times.pop('trigger', None)
        else:
            self.wait(lambda: self.mission_done, 3600.0, 'the scripted mission to finish')
            rospy.sleep(p.settle)
        cpu_end, wall_end = self.cpu_snapshot(), time.time()
        self.times['recording_start'], self.times['failure'] = sim_start, rospy.Time.now().to_sec()
        if not p.case:
            self.stop_bag()
            set_vision(False)
            self.wait(lambda: self.state in TERMINAL, p.timeout, 'state home or aborted')
        rss_timer.shutdown()
        rospy.sleep(p.settle)
        self.report()
        self.write_json(cpu_start, cpu_end, wall_end - wall_start,
                        self.times['failure'] - sim_start)

    def stop_bag(self):
        process = self.processes.get(self.params.bag_node)
        if process is not None:
            try:
                process.send_signal(signal.SIGINT)
            except psutil.Error as error:
                rospy.logwarn('bench_probe: could not stop the bag recorder: %s', error)

    def stationary_landmarks(self):
        """Landmarks recorded before the robot first moved, or None without a file."""
        if not self.params.landmark_file:
            return None
        count = 0
        for landmark in load_landmarks(os.path.expanduser(self.params.landmark_file)).landmarks:
            if landmark.v != 0.0 or landmark.d >= 1e-3:
                break
            count += 1
        return count

    def write_json(self, cpu_start, cpu_end, wall, sim):
        p = self.params
        if not p.out:
            return
        forward, back = self.paths['forward'], self.paths['return']
        start, end = forward[0], (back or forward)[-1]
        fp = self.storage
        t = self.times
        nodes = {name: {'cpu_s': cpu_end[name] - cpu_start[name],
                        'cpu_pct': 100.0 * (cpu_end[name] - cpu_start[name]) / wall if wall > 0 else None,
                        'rss_peak_mb': self.peak_rss.get(name, 0) / 1e6}
                 for name in cpu_start if name in cpu_end}
        result = {
            'mission': p.scenario, 'mode': p.control, 'seed': p.seed, 'state': self.state,
            'length': fp.distance if fp else None, 'samples': fp.landmarks if fp else None,
            'bytes': fp.bytes if fp else None,
            'error': distance(start[0], start[1], end[0], end[1]),
            'stationary_samples': self.stationary_landmarks(),
            'mission_start': t.get('mission_start'), 'recording_state': t.get('recording_state'),
            'detector': self.detector,
            'failure_to_trigger': t['trigger'] - t['failure'] if 'trigger' in t else None,
            'trigger_to_rotation': t['rotation'] - t['trigger'] if 'rotation' in t and 'trigger' in t else None,
            'recording_wall_s': wall, 'recording_sim_s': sim, 'rtf': sim / wall if wall > 0 else None,
            'nodes': nodes, 'forward_path': forward, 'return_path': back,
            'goal_stamps': sorted(self.goal_stamps), 'result_stamps': sorted(self.result_stamps),
            'return_commands': self.return_commands,
        }
        result.update(self.case_findings)
        with open(p.out, 'w') as stream:
            json.dump(result, stream)
        rospy.loginfo('bench_probe: wrote %s', p.out)


def main():
    observe('bench_probe', BenchProbe)


if __name__ == '__main__':
    main()
