"""The demo observer (demo_observer, bench_probe): runs the demo's script and reports it.

Waits for ``recording``, starts the scripted operator, waits for the mission's end and
``settle`` s, fails vision, waits for ``home``/``aborted``, then prints a Table-VI-style
row and writes a plot of the forward and return paths to ``results_dir``.
"""
import os

import rospy
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool, Empty, String
from std_srvs.srv import SetBool

from blind_navigation import names
from blind_navigation.core.geometry import distance
from blind_navigation.core.mission_state import TERMINAL
from blind_navigation.msg import StorageUsage
from blind_navigation.sim.node_common import (GROUND_TRUTH, MISSION_DONE, MISSION_GO, SET_VISION,
                                               load_params, start_node)


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
        rospy.Subscriber(MISSION_DONE, Bool, self._on_done)
        rospy.Subscriber(GROUND_TRUTH, Odometry, self._on_truth, queue_size=20)
        self.go = rospy.Publisher(MISSION_GO, Empty, queue_size=1, latch=True)

    def _on_state(self, msg):
        self.state = msg.data

    def _on_storage(self, msg):
        self.storage = msg

    def _on_done(self, msg):
        self.mission_done = self.mission_done or msg.data

    def _on_truth(self, msg):
        key = 'return' if self.state in ('rotating', 'returning') or self.state in TERMINAL else 'forward'
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
        self.wait(lambda: self.state == 'recording' and self.paths['forward'], 300.0,
                  'the layer to record (state recording) and the ground truth')
        self.go.publish(Empty())
        self.wait(lambda: self.mission_done, 3600.0, 'the scripted mission to finish')
        rospy.sleep(p.settle)
        rospy.wait_for_service(SET_VISION, timeout=30.0)
        rospy.ServiceProxy(SET_VISION, SetBool)(False)
        rospy.loginfo('demo: vision failed on purpose; waiting for the return')
        self.wait(lambda: self.state in TERMINAL, p.timeout, 'state home or aborted')
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
        results_dir = os.path.expanduser(p.results_dir)
        os.makedirs(results_dir, exist_ok=True)
        stem = os.path.join(results_dir, 'demo_%s_%s' % (p.scenario, p.control))
        with open(stem + '.txt', 'w') as stream:
            stream.write(row + '\n')
        self.plot(forward, back, stem + '.png', '%s, %s: position error %.3f m'
                  % (p.scenario, p.control, error))
        print('\n' + row + '\nplot: %s.png\n' % stem, flush=True)

    @staticmethod
    def plot(forward, back, path, title):
        """Forward and return ground truth on equal axes with margins; start, turn (where
        the return began) and end marked; the legend below the axes, off the paths."""
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        figure, axes = plt.subplots(figsize=(8, 6.5))
        axes.plot(*zip(*forward), '-', color='tab:blue', label='forward (ground truth)')
        # start: a large open ring, so that the end drawn on it stays visible
        axes.plot(*forward[0], 'o', markersize=14, markerfacecolor='none', markeredgewidth=2,
                  color='tab:green', linestyle='none', label='start', zorder=3)
        if back:
            axes.plot(*zip(*back), '--', color='tab:orange', label='return (ground truth)')
            axes.plot(*back[0], 's', markersize=9, color='tab:purple', markeredgecolor='black',
                      linestyle='none', label='turn (vision lost)', zorder=3)
            axes.plot(*back[-1], 'X', markersize=8, color='tab:red', markeredgecolor='black',
                      linestyle='none', label='end', zorder=4)
        if back:
            (x0, y0), (x1, y1) = forward[0], back[-1]
            axes.plot([x0, x1], [y0, y1], ':', color='tab:red', linewidth=1,
                      label='position error %.3f m' % distance(x0, y0, x1, y1))
        axes.set_aspect('equal', adjustable='box')
        (x_low, x_high), (y_low, y_high) = padded_limits(forward + back)
        axes.set_xlim(x_low, x_high)
        axes.set_ylim(y_low, y_high)
        axes.grid(alpha=0.3)
        axes.set_xlabel('x [m]')
        axes.set_ylabel('y [m]')
        axes.set_title(title)
        figure.canvas.draw()                       # where the x label ended up: the legend goes below
        label_bottom = axes.xaxis.label.get_window_extent().y0
        below = axes.transAxes.inverted().transform((0.0, label_bottom))[1]
        axes.legend(loc='upper center', bbox_to_anchor=(0.5, below), ncol=3, fontsize=9,
                    frameon=False)
        figure.savefig(path, dpi=120, bbox_inches='tight')
        plt.close(figure)


def padded_limits(points, margin=0.1, least=0.5):
    """((x_low, x_high), (y_low, y_high)) around ``points`` [(x, y)], each side padded by
    ``margin`` (a fraction) of the larger span and at least ``least`` m wide in all."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    span = max(max(xs) - min(xs), max(ys) - min(ys), least)
    pad = margin * span
    limits = []
    for low, high in ((min(xs), max(xs)), (min(ys), max(ys))):
        extra = max(0.0, least - (high - low)) / 2.0
        limits.append((low - pad - extra, high + pad + extra))
    return tuple(limits)


def main(name='demo_observer', node_class=DemoObserver):
    """Run an observer node (``node_class``: DemoObserver or a subclass) until its report
    is out; returns it (its ``state`` is the mission's last). Exits 1 on a timeout or a
    shutdown before the report."""
    node = start_node(name, node_class)
    try:
        node.run()
    except rospy.ROSInterruptException:
        rospy.loginfo('%s: shut down before the report', name)
        raise SystemExit(1)
    except (RuntimeError, rospy.ROSException) as error:
        rospy.logerr('%s', error)
        raise SystemExit(1)
    return node
