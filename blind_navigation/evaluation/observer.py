"""The demo observer (nodes demo_observer and bench_probe): runs the demo's script and reports it (launch/demo.launch).

Waits for the scripted mission to finish (/mission_driver/done), lets the robot
stop for ``settle`` s, makes vision fail (/fake_turtlebot/set_vision false),
waits for /blind_navigation/state ``home`` or ``aborted`` (``timeout`` s of sim
time), then prints a Table-VI-style row (distance, samples, memory, position
error = ground-truth distance between start and end) and writes a PNG of the
forward and return ground-truth paths (like the paper's Figures 12-13) and a
one-line text file to ``results_dir``. Exits the launch when done.
"""
import os

import rospy
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool, String
from std_srvs.srv import SetBool

from blind_navigation import names
from blind_navigation.core.geometry import distance
from blind_navigation.msg import StorageUsage
from blind_navigation.ros.common import load_params, start_node

FINAL = ('home', 'aborted')


class DemoObserver(object):
    """Params (DEFAULTS): ``scenario`` (label), ``control`` (label), ``settle``
    (s, 2), ``timeout`` (sim s for the return, 900), ``results_dir`` ('results')."""

    DEFAULTS = {'scenario': '', 'control': '', 'settle': 2.0, 'timeout': 900.0,
                'results_dir': 'results'}

    def __init__(self):
        self.params = load_params(self.DEFAULTS)
        self.state = None
        self.storage = None
        self.mission_done = False
        self.paths = {'forward': [], 'return': []}
        rospy.Subscriber(names.STATE, String, self._on_state)
        rospy.Subscriber(names.STORAGE, StorageUsage, self._on_storage)
        rospy.Subscriber('/mission_driver/done', Bool, self._on_done)
        rospy.Subscriber('/ground_truth/odom', Odometry, self._on_truth, queue_size=20)

    def _on_state(self, msg):
        self.state = msg.data

    def _on_storage(self, msg):
        self.storage = msg

    def _on_done(self, msg):
        self.mission_done = self.mission_done or msg.data

    def _on_truth(self, msg):
        key = 'return' if self.state in ('rotating', 'returning') or self.state in FINAL else 'forward'
        p = msg.pose.pose.position
        path = self.paths[key]
        if not path or distance(path[-1][0], path[-1][1], p.x, p.y) > 0.005:
            path.append((p.x, p.y))

    def wait(self, condition, timeout, what):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while not condition():
            if rospy.is_shutdown() or rospy.Time.now() > deadline:
                raise RuntimeError('demo: timed out after %.0f s (sim) waiting for %s' % (timeout, what))
            rospy.sleep(0.1)

    def run(self):
        p = self.params
        self.wait(lambda: self.mission_done, 3600.0, 'the scripted mission to finish')
        rospy.sleep(p.settle)
        rospy.wait_for_service('/fake_turtlebot/set_vision', timeout=30.0)
        rospy.ServiceProxy('/fake_turtlebot/set_vision', SetBool)(False)
        rospy.loginfo('demo: vision failed on purpose; waiting for the return')
        self.wait(lambda: self.state in FINAL, p.timeout, 'state home or aborted')
        rospy.sleep(p.settle)
        self.report()

    def report(self):
        p = self.params
        forward, back = self.paths['forward'], self.paths['return']
        start, end = forward[0], (back or forward)[-1]
        error = distance(start[0], start[1], end[0], end[1])
        fp = self.storage
        row = ('| %s | %s | %s | distance %.2f m | samples %d | memory %.1f KB | position error %.3f m |'
               % (p.scenario, p.control, self.state, fp.distance if fp else 0.0,
                  fp.landmarks if fp else 0, (fp.bytes if fp else 0) / 1024.0, error))
        os.makedirs(p.results_dir, exist_ok=True)
        stem = os.path.join(p.results_dir, 'demo_%s_%s' % (p.scenario, p.control))
        with open(stem + '.txt', 'w') as stream:
            stream.write(row + '\n')
        self.plot(forward, back, stem + '.png', '%s, %s: position error %.3f m'
                  % (p.scenario, p.control, error))
        print('\n' + row + '\nplot: %s.png\n' % stem, flush=True)

    @staticmethod
    def plot(forward, back, path, title):
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        figure, axes = plt.subplots(figsize=(8, 4))
        axes.plot(*zip(*forward), '-', label='forward (ground truth)')
        if back:
            axes.plot(*zip(*back), '--', label='back travel (ground truth)')
        axes.plot(*forward[0], 'go', label='start')
        axes.set_aspect('equal')
        axes.set_xlabel('x [m]')
        axes.set_ylabel('y [m]')
        axes.set_title(title)
        axes.legend(loc='best')
        figure.savefig(path, dpi=120, bbox_inches='tight')


def main(name='demo_observer', node_class=DemoObserver):
    """Run an observer node (``node_class``: DemoObserver or a subclass) until its report is out."""
    node = start_node(name, node_class)
    try:
        node.run()
    except (RuntimeError, rospy.ROSException) as error:
        rospy.logerr('%s', error)
        raise SystemExit(1)
